#include <canopy/io/CellArrayBlocks.h>

// Canopy's own array class: its typed reads go through the cell -> slot table
// without a virtual call or a conversion to double.
#include "SimulationFieldArray.h"

#include <vtkAOSDataArrayTemplate.h>
#include <vtkDataArray.h>
#include <vtkSOADataArrayTemplate.h>
#include <vtkVariant.h>

#include <algorithm>
#include <type_traits>
#include <vector>

namespace canopy::io
{
namespace
{

/// The value types Canopy wraps its fields with (FieldWrapping.cxx).
template <typename T>
constexpr bool isCanopyValue()
{
  return std::is_same<T, float>::value || std::is_same<T, double>::value ||
         std::is_same<T, int>::value || std::is_same<T, long long>::value;
}

template <typename T>
SimulationFieldArray<T>* asCanopyArray(vtkDataArray* array)
{
  if constexpr (isCanopyValue<T>())
  {
    return SimulationFieldArray<T>::SafeDownCast(array);
  }
  else
  {
    (void)array;
    return nullptr;
  }
}

/// Typed read of component `c` of tuple `t`, whatever the array's class.
template <typename T>
class TypedReader
{
public:
  explicit TypedReader(vtkDataArray* array)
      : Array(array), Soa(vtkSOADataArrayTemplate<T>::FastDownCast(array)),
        Canopy(asCanopyArray<T>(array))
  {
  }

  void tuple(vtkIdType t, int components, T* out) const
  {
    if (this->Soa)
    {
      for (int c = 0; c < components; ++c)
      {
        out[c] = this->Soa->GetTypedComponent(t, c);
      }
    }
    else if (this->Canopy)
    {
      if constexpr (isCanopyValue<T>())
      {
        for (int c = 0; c < components; ++c)
        {
          out[c] = this->Canopy->GetTypedComponent(t, c);
        }
      }
    }
    else if constexpr (std::is_integral<T>::value && sizeof(T) == 8)
    {
      // Through double, 64-bit integers above 2^53 would lose digits.
      for (int c = 0; c < components; ++c)
      {
        const vtkVariant value = this->Array->GetVariantValue(t * components + c);
        out[c] = std::is_signed<T>::value ? static_cast<T>(value.ToLongLong())
                                          : static_cast<T>(value.ToUnsignedLongLong());
      }
    }
    else
    {
      for (int c = 0; c < components; ++c)
      {
        out[c] = static_cast<T>(this->Array->GetComponent(t, c));
      }
    }
  }

private:
  vtkDataArray* Array;
  vtkSOADataArrayTemplate<T>* Soa;
  SimulationFieldArray<T>* Canopy;
};

template <typename T>
void forEachTyped(vtkDataArray* array, const std::vector<CellRun>& runs, std::size_t stagingBytes,
                  const CellArrayBlocks::Sink& sink)
{
  const int components = array->GetNumberOfComponents();
  if (auto* aos = vtkAOSDataArrayTemplate<T>::FastDownCast(array))
  {
    if (runs.size() == 1)
    {
      // GetPointer never copies for these arrays: the simulation's own memory.
      sink(aos->GetPointer(runs[0].first * components), runs[0].count);
      return;
    }
  }
  const vtkIdType blockTuples = std::max<vtkIdType>(
      1, static_cast<vtkIdType>(stagingBytes / (sizeof(T) * static_cast<std::size_t>(components))));
  std::vector<T> staging;
  TypedReader<T> reader(array);
  vtkIdType filled = 0;
  for (const CellRun& run : runs)
  {
    for (vtkIdType t = run.first; t < run.first + run.count; ++t)
    {
      if (staging.empty())
      {
        staging.resize(static_cast<std::size_t>(blockTuples * components));
      }
      reader.tuple(t, components, staging.data() + filled * components);
      if (++filled == blockTuples)
      {
        sink(staging.data(), filled);
        filled = 0;
      }
    }
  }
  if (filled > 0)
  {
    sink(staging.data(), filled);
  }
}

} // namespace

CellArrayBlocks::CellArrayBlocks(vtkDataArray* array, const std::vector<CellRun>& runs,
                                 std::size_t stagingBytes)
    : Array(array), Runs(runs), StagingBytes(stagingBytes)
{
}

void CellArrayBlocks::forEach(const Sink& sink) const
{
  switch (this->Array->GetDataType())
  {
    vtkTemplateMacro(forEachTyped<VTK_TT>(this->Array, this->Runs, this->StagingBytes, sink));
  default:
    break;
  }
}

} // namespace canopy::io
