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
//    or the fill value of absent cells);
//  - block fields (block forests): tuple i (a cell) is read through BlockField,
//    which finds it in the simulation's block arrays without a table per cell.
// The simulation's memory is never written: any write (VTK filters write only to
// arrays they created with NewInstance, which start owned) or a request for a raw
// pointer first detaches the array into an owned AoS copy.
#pragma once

#include "BlockField.h"
#include "FieldView.h"
#include "FreshMemory.h"

#include <vtkAOSDataArrayTemplate.h>
#include <vtkGenericDataArray.h>
#include <vtkIdList.h>
#include <vtkObjectFactory.h>
#include <vtkTypeTraits.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <limits>
#include <memory>
#include <type_traits>
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

  /// Reads a block field: one tuple per cell of its block forest's grid.
  void borrowBlocks(std::shared_ptr<const BlockField<T>> blocks)
  {
    const auto tuples = static_cast<vtkIdType>(blocks->numberOfCells());
    this->borrow(FieldView(), blocks->components(), tuples);
    this->Blocks = std::move(blocks);
  }

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
    if constexpr (std::is_floating_point_v<T>)
    {
      if (this->Blocks)
      {
        this->Blocks->tuple(static_cast<std::uint64_t>(tupleIdx), tuple);
        return;
      }
    }
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
    if constexpr (std::is_floating_point_v<T>)
    {
      if (this->Blocks)
      {
        return this->Blocks->at(static_cast<std::uint64_t>(tupleIdx), comp);
      }
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

  // Ranges. VTK 9.2's vtkDataArray computes the range of an array class it does
  // not know through one virtual GetComponent per value (about 0.4 us per value in
  // Debian's build: ParaView's data information and the pipelines' colour ranges
  // spent 0.5 s per image step on a 1e6-leaf grid, docs/benchmarks.md). This array
  // reads itself, with VTK's rules: NaN skipped, the finite variants also skip
  // infinities, vector ranges are of the Euclidean norm, tuples whose ghost flags
  // meet ghostsToSkip are skipped, false for an empty array.
  bool ComputeScalarRange(double* ranges) override
  {
    return this->componentRanges(ranges, nullptr, 0, false);
  }
  bool ComputeScalarRange(double* ranges, const unsigned char* ghosts,
                          unsigned char ghostsToSkip) override
  {
    return this->componentRanges(ranges, ghosts, ghostsToSkip, false);
  }
  bool ComputeFiniteScalarRange(double* ranges) override
  {
    return this->componentRanges(ranges, nullptr, 0, true);
  }
  bool ComputeFiniteScalarRange(double* ranges, const unsigned char* ghosts,
                                unsigned char ghostsToSkip) override
  {
    return this->componentRanges(ranges, ghosts, ghostsToSkip, true);
  }
  bool ComputeVectorRange(double range[2]) override
  {
    return this->normRange(range, nullptr, 0, false);
  }
  bool ComputeVectorRange(double range[2], const unsigned char* ghosts,
                          unsigned char ghostsToSkip) override
  {
    return this->normRange(range, ghosts, ghostsToSkip, false);
  }
  bool ComputeFiniteVectorRange(double range[2]) override
  {
    return this->normRange(range, nullptr, 0, true);
  }
  bool ComputeFiniteVectorRange(double range[2], const unsigned char* ghosts,
                                unsigned char ghostsToSkip) override
  {
    return this->normRange(range, ghosts, ghostsToSkip, true);
  }

  // Gathers. VTK 9.2's vtkDataArray::GetTuples dispatches only over the array
  // classes it knows; for this one it reads one virtual GetComponent per value
  // (about 90 instructions each: the filters' output fields, docs/benchmarks.md).
  // Into an AoS array of this value type and shape, this array reads itself.
  using GenericBase::GetTuples;
  void GetTuples(vtkIdList* tupleIds, vtkAbstractArray* output) override
  {
    auto* out = vtkAOSDataArrayTemplate<ValueType>::FastDownCast(output);
    const vtkIdType count = tupleIds->GetNumberOfIds();
    const int nc = this->NumberOfComponents;
    if (!out || out->GetNumberOfComponents() != nc || out->GetNumberOfTuples() < count)
    {
      this->GenericBase::GetTuples(tupleIds, output);
      return;
    }
    const vtkIdType* ids = tupleIds->GetPointer(0);
    ValueType* to = out->GetPointer(0);
    if (!this->Borrowing || this->View.tupleAddress || this->Blocks)
    {
      for (vtkIdType i = 0; i < count; ++i)
      {
        this->GetTypedTuple(ids[i], to + i * nc);
      }
    }
    else
    {
      // Strided simulation memory, possibly through the tuple map: the
      // addressing in locals (GetTypedComponent re-decides it per value).
      const std::vector<const unsigned char*>& base = this->View.componentBase;
      const std::size_t stride = this->View.strideBytes;
      const TupleMap* map = this->Map.get();
      for (vtkIdType i = 0; i < count; ++i)
      {
        const std::int64_t tuple = map ? (*map)[static_cast<std::size_t>(ids[i])] : ids[i];
        ValueType* value = to + i * nc;
        if (tuple < 0)
        {
          std::copy_n(this->Computed.data() + computedIndexOf(tuple) * static_cast<std::size_t>(nc),
                      nc, value);
          continue;
        }
        const std::size_t offset = static_cast<std::size_t>(tuple) * stride;
        for (int c = 0; c < nc; ++c)
        {
          std::memcpy(value + c, base[static_cast<std::size_t>(c)] + offset, sizeof(ValueType));
        }
      }
    }
    out->DataChanged();
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
    this->Blocks.reset();
  }

  static bool skipped(double value, bool finiteOnly)
  {
    return finiteOnly ? !std::isfinite(value) : std::isnan(value);
  }

  bool componentRanges(double* ranges, const unsigned char* ghosts, unsigned char ghostsToSkip,
                       bool finiteOnly) const
  {
    const vtkIdType tuples = this->GetNumberOfTuples();
    const int components = this->NumberOfComponents;
    if (tuples <= 0)
    {
      return false;
    }
    if constexpr (std::is_floating_point_v<T>)
    {
      // Coarse cells are means of the blocks' cells: the same range, one pass
      // over the blocks. Absent cells (the only ghosts) read NaN, skipped anyway.
      if (this->Blocks)
      {
        return this->Blocks->leafRanges(ranges, finiteOnly);
      }
    }
    for (int c = 0; c < components; ++c)
    {
      ranges[2 * c] = vtkTypeTraits<double>::Max();
      ranges[2 * c + 1] = vtkTypeTraits<double>::Min();
    }
    for (vtkIdType t = 0; t < tuples; ++t)
    {
      if (ghosts && (ghosts[t] & ghostsToSkip))
      {
        continue;
      }
      for (int c = 0; c < components; ++c)
      {
        const double value = static_cast<double>(this->GetTypedComponent(t, c));
        if (skipped(value, finiteOnly))
        {
          continue;
        }
        ranges[2 * c] = std::min(ranges[2 * c], value);
        ranges[2 * c + 1] = std::max(ranges[2 * c + 1], value);
      }
    }
    return true;
  }

  bool normRange(double range[2], const unsigned char* ghosts, unsigned char ghostsToSkip,
                 bool finiteOnly) const
  {
    const vtkIdType tuples = this->GetNumberOfTuples();
    const int components = this->NumberOfComponents;
    if (tuples <= 0)
    {
      return false;
    }
    if constexpr (std::is_floating_point_v<T>)
    {
      if (this->Blocks)
      {
        return this->Blocks->leafNormRange(range, finiteOnly);
      }
    }
    double low = vtkTypeTraits<double>::Max();
    double high = vtkTypeTraits<double>::Min();
    for (vtkIdType t = 0; t < tuples; ++t)
    {
      if (ghosts && (ghosts[t] & ghostsToSkip))
      {
        continue;
      }
      double squared = 0.0;
      for (int c = 0; c < components; ++c)
      {
        const double value = static_cast<double>(this->GetTypedComponent(t, c));
        squared += value * value;
      }
      if (skipped(squared, finiteOnly))
      {
        continue;
      }
      low = std::min(low, squared);
      high = std::max(high, squared);
    }
    range[0] = low <= high ? std::sqrt(low) : low;
    range[1] = low <= high ? std::sqrt(high) : high;
    return true;
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
  std::shared_ptr<const BlockField<T>> Blocks;
  std::vector<ValueType> Owned;
};

} // namespace canopy
