// A vtkDataArray that reads a simulation field where it lives.
//
// VTK 9.2 can wrap contiguous AoS and SoA buffers (vtkAOSDataArrayTemplate,
// vtkSOADataArrayTemplate) but nothing else. This array covers the rest without
// copying the simulation's values:
//  - strided fields (a member of an array of records): component c of tuple i is
//    at componentBase[c] + i * tupleStrideBytes; indirect fields (records
//    scattered in memory): at tupleAddress[i] + c * valueSize;
//  - mapped fields (leaves-only fields, forests with absent nodes): tuple i (a
//    cell) maps through a shared table either to a tuple in simulation memory
//    or to a value that Canopy computed and this array owns (a coarse average,
//    or the fill value of absent cells).
// The simulation's memory is never written: any write (VTK filters write only to
// arrays they created with NewInstance, which start owned) or a request for a raw
// pointer first detaches the array into an owned AoS copy.
#pragma once

#include "FieldView.h"
#include "FreshMemory.h"

#include <vtkGenericDataArray.h>
#include <vtkObjectFactory.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <utility>
#include <vector>

namespace canopy
{

/// Tuple map entries (see SimulationFieldArray::borrowMapped): >= 0 a borrowed
/// tuple, < 0 the computed tuple computedIndexOf(entry).
inline std::int64_t computedEntry(std::size_t computedIndex)
{
  return -static_cast<std::int64_t>(computedIndex) - 1;
}
inline std::size_t computedIndexOf(std::int64_t entry)
{
  return static_cast<std::size_t>(-entry - 1);
}

/// What an absent cell reads (it is masked, so no filter shows it): NaN for
/// floating-point fields, 0 for integers.
template <typename T>
constexpr T absentValue()
{
  return std::numeric_limits<T>::has_quiet_NaN ? std::numeric_limits<T>::quiet_NaN() : T(0);
}

template <typename T>
class SimulationFieldArray : public vtkGenericDataArray<SimulationFieldArray<T>, T>
{
  using GenericBase = vtkGenericDataArray<SimulationFieldArray<T>, T>;

public:
  using SelfType = SimulationFieldArray<T>;
  vtkAbstractTemplateTypeMacro(SelfType, GenericBase);
  // NewInstance gives a plain AoS array of the same type: filters that copy this
  // array's structure get ordinary, writable VTK memory.
  vtkAOSArrayNewInstanceMacro(SelfType);
  using ValueType = typename Superclass::ValueType;

  /// Tuple -> borrowed tuple (>= 0) or computed tuple (< 0, see computedEntry).
  using TupleMap = IndexTable;

  static SimulationFieldArray* New() { VTK_STANDARD_NEW_BODY(SimulationFieldArray<T>); }

  /// Borrows `numberOfTuples` tuples of `view` (whose values are of this array's
  /// type). Sets the number of components.
  void borrow(FieldView view, int components, vtkIdType numberOfTuples)
  {
    this->Owned.clear();
    this->Owned.shrink_to_fit();
    this->dropBorrow();
    // Through the base class: it also sizes VTK's scratch tuple used by GetTuple.
    this->GenericBase::SetNumberOfComponents(components);
    this->View = std::move(view);
    this->Borrowing = true;
    this->Size = numberOfTuples * this->NumberOfComponents;
    this->MaxId = this->Size - 1;
    this->DataChanged();
  }

  /// Like borrow(), but tuple i is read through map[i]: borrowed tuples from the
  /// view, computed tuples from `computedValues` (AoS, owned by this array).
  void borrowMapped(FieldView view, int components, std::shared_ptr<const TupleMap> map,
                    std::vector<T> computedValues)
  {
    const auto tuples = static_cast<vtkIdType>(map->size());
    this->borrow(std::move(view), components, tuples);
    this->Map = std::move(map);
    this->Computed = std::move(computedValues);
  }

  /// True while values are read from simulation memory.
  bool isBorrowing() const { return this->Borrowing; }

  ValueType GetValue(vtkIdType valueIdx) const
  {
    const int nc = this->NumberOfComponents;
    return this->GetTypedComponent(valueIdx / nc, static_cast<int>(valueIdx % nc));
  }

  void SetValue(vtkIdType valueIdx, ValueType value)
  {
    const int nc = this->NumberOfComponents;
    this->SetTypedComponent(valueIdx / nc, static_cast<int>(valueIdx % nc), value);
  }

  void GetTypedTuple(vtkIdType tupleIdx, ValueType* tuple) const
  {
    for (int c = 0; c < this->NumberOfComponents; ++c)
    {
      tuple[c] = this->GetTypedComponent(tupleIdx, c);
    }
  }

  void SetTypedTuple(vtkIdType tupleIdx, const ValueType* tuple)
  {
    this->detach();
    std::copy(tuple, tuple + this->NumberOfComponents,
              this->Owned.data() + tupleIdx * this->NumberOfComponents);
  }

  ValueType GetTypedComponent(vtkIdType tupleIdx, int comp) const
  {
    if (!this->Borrowing)
    {
      return this->Owned[static_cast<std::size_t>(tupleIdx * this->NumberOfComponents + comp)];
    }
    std::int64_t source = tupleIdx;
    if (this->Map)
    {
      source = (*this->Map)[static_cast<std::size_t>(tupleIdx)];
      if (source < 0)
      {
        return this->Computed[computedIndexOf(source) *
                                  static_cast<std::size_t>(this->NumberOfComponents) +
                              static_cast<std::size_t>(comp)];
      }
    }
    return this->View.template at<ValueType>(static_cast<std::size_t>(source),
                                             static_cast<std::size_t>(comp));
  }

  void SetTypedComponent(vtkIdType tupleIdx, int comp, ValueType value)
  {
    this->detach();
    this->Owned[static_cast<std::size_t>(tupleIdx * this->NumberOfComponents + comp)] = value;
  }

  /// Changing the tuple shape ends the borrow first (the values are kept, owned).
  void SetNumberOfComponents(int num) override
  {
    if (num != this->NumberOfComponents)
    {
      this->detach();
    }
    this->GenericBase::SetNumberOfComponents(num);
  }

  /// Releases everything without copying the borrowed values first.
  void Initialize() override
  {
    this->dropBorrow();
    this->Owned.clear();
    this->Owned.shrink_to_fit();
    this->GenericBase::Initialize();
  }

  /// Raw pointers need contiguous AoS memory: detach into an owned copy (as
  /// vtkSOADataArrayTemplate does). Later simulation updates are then not seen.
  void* GetVoidPointer(vtkIdType valueIdx) override
  {
    this->detach();
    return this->Owned.data() + valueIdx;
  }

protected:
  SimulationFieldArray() = default;
  ~SimulationFieldArray() override = default;

  bool AllocateTuples(vtkIdType numTuples)
  {
    this->dropBorrow();
    this->Owned.assign(static_cast<std::size_t>(numTuples * this->NumberOfComponents), ValueType());
    return true;
  }

  bool ReallocateTuples(vtkIdType numTuples)
  {
    this->detach();
    this->Owned.resize(static_cast<std::size_t>(numTuples * this->NumberOfComponents));
    return true;
  }

  friend GenericBase;

private:
  SimulationFieldArray(const SimulationFieldArray&) = delete;
  void operator=(const SimulationFieldArray&) = delete;

  void dropBorrow()
  {
    this->Borrowing = false;
    this->View = FieldView();
    this->Map.reset();
    this->Computed.clear();
  }

  /// Copies the borrowed view into owned memory so a write never reaches the simulation.
  void detach()
  {
    if (!this->Borrowing)
    {
      return;
    }
    const vtkIdType tuples = this->GetNumberOfTuples();
    std::vector<ValueType> copy(static_cast<std::size_t>(this->Size));
    const int components = this->NumberOfComponents;
    for (vtkIdType t = 0; t < tuples; ++t)
    {
      for (int c = 0; c < components; ++c)
      {
        copy[static_cast<std::size_t>(t * this->NumberOfComponents + c)] =
            this->GetTypedComponent(t, c);
      }
    }
    this->dropBorrow();
    this->Owned = std::move(copy);
  }

  FieldView View;
  bool Borrowing = false;
  std::shared_ptr<const TupleMap> Map;
  std::vector<ValueType> Computed;
  std::vector<ValueType> Owned;
};

} // namespace canopy
