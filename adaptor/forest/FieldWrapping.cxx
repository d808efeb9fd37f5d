#include "FieldWrapping.h"

#include "FieldView.h"
#include "SimulationFieldArray.h"

#include <vtkDoubleArray.h>
#include <vtkFloatArray.h>
#include <vtkSOADataArrayTemplate.h>
#include <vtkTypeInt32Array.h>
#include <vtkTypeInt64Array.h>

#include <type_traits>

namespace canopy
{
namespace
{

// The concrete AoS class VTK readers, writers and numpy expect for each type.
template <typename T>
struct ContiguousArray;
template <>
struct ContiguousArray<double>
{
  using type = vtkDoubleArray;
};
template <>
struct ContiguousArray<float>
{
  using type = vtkFloatArray;
};
template <>
struct ContiguousArray<std::int32_t>
{
  using type = vtkTypeInt32Array;
};
template <>
struct ContiguousArray<std::int64_t>
{
  using type = vtkTypeInt64Array;
};

/// The VTK value type used for a simulation type (same size and representation).
template <typename T>
using VtkValue = std::conditional_t<std::is_same_v<T, std::int64_t>, vtkTypeInt64, T>;

template <typename T>
vtkSmartPointer<vtkDataArray> wrapTyped(const FieldDescription& field, vtkIdType tuples)
{
  const int nc = field.components;
  // Layout::Indirect is never contiguous.
  const bool contiguous =
      field.layout == Layout::AoS ||
      (field.layout == Layout::Strided && field.tupleStrideBytes == sizeof(T) * nc) ||
      (field.layout == Layout::SoA && nc == 1);
  if (contiguous)
  {
    const void* first = field.layout == Layout::SoA ? field.componentData[0] : field.data;
    auto array = vtkSmartPointer<typename ContiguousArray<T>::type>::New();
    array->SetNumberOfComponents(nc);
    // save = 1: VTK never frees or reallocates the simulation's memory.
    // vtkTypeInt64Array stores long long while std::int64_t may be long: same
    // size and representation, so the reinterpretation is exact.
    using Stored = typename ContiguousArray<T>::type::ValueType;
    static_assert(sizeof(Stored) == sizeof(T), "VTK value type must match the field's");
    array->SetArray(reinterpret_cast<Stored*>(const_cast<void*>(first)), tuples * nc, 1);
    return array;
  }
  // 64-bit integers as VTK's own 64-bit type (long long) in every layout.
  using Stored = VtkValue<T>;
  if (field.layout == Layout::SoA)
  {
    auto array = vtkSmartPointer<vtkSOADataArrayTemplate<Stored>>::New();
    array->SetNumberOfComponents(nc);
    for (int c = 0; c < nc; ++c)
    {
      array->SetArray(c, reinterpret_cast<Stored*>(const_cast<void*>(field.componentData[c])),
                      tuples, /*updateMaxId=*/true, /*save=*/true);
    }
    return array;
  }
  auto array = vtkSmartPointer<SimulationFieldArray<Stored>>::New();
  array->borrow(FieldView::of(field), nc, tuples);
  return array;
}

/// A field read through a cell -> slot table (forests with absent nodes).
template <typename T>
vtkSmartPointer<vtkDataArray> wrapMappedTyped(const FieldDescription& field, const CellSlots& slots)
{
  using Stored = VtkValue<T>;
  auto array = vtkSmartPointer<SimulationFieldArray<Stored>>::New();
  // Computed tuple 0 (what CellSlots::NoSlot reads): the absent fill.
  std::vector<Stored> fill(static_cast<std::size_t>(field.components), absentValue<Stored>());
  array->borrowMapped(FieldView::of(field), field.components, slots.slotOfCell, std::move(fill));
  return array;
}

template <typename T>
vtkSmartPointer<vtkDataArray> wrapLeafTyped(const FieldDescription& field,
                                            const ForestDescription& forest,
                                            const ForestLayout& layout, const LeafTupleMap& map)
{
  auto array = vtkSmartPointer<SimulationFieldArray<T>>::New();
  array->borrowMapped(FieldView::of(field), field.components, map.cellToTuple,
                      restrictToCoarse<T>(forest, layout, field, map));
  return array;
}

template <typename T>
vtkSmartPointer<vtkDataArray> wrapBlockTyped(const FieldDescription& field,
                                             std::shared_ptr<const BlockCells> blocks)
{
  auto array = vtkSmartPointer<SimulationFieldArray<T>>::New();
  array->borrowBlocks(std::make_shared<const BlockField<T>>(field, std::move(blocks)));
  return array;
}

} // namespace

vtkSmartPointer<vtkDataArray> wrapBlockField(const FieldDescription& field,
                                             std::shared_ptr<const BlockCells> blocks)
{
  // Validation admits only floating-point block fields.
  vtkSmartPointer<vtkDataArray> array = field.type == ValueType::Float32
                                            ? wrapBlockTyped<float>(field, std::move(blocks))
                                            : wrapBlockTyped<double>(field, std::move(blocks));
  array->SetName(field.name.c_str());
  return array;
}

vtkSmartPointer<vtkDataArray> wrapNodeField(const FieldDescription& field,
                                            const ForestLayout& layout, const CellSlots& slots)
{
  const auto tuples = static_cast<vtkIdType>(layout.totalNodes);
  const bool mapped = !slots.identity();
  vtkSmartPointer<vtkDataArray> array;
  switch (field.type)
  {
  case ValueType::Float32:
    array = mapped ? wrapMappedTyped<float>(field, slots) : wrapTyped<float>(field, tuples);
    break;
  case ValueType::Float64:
    array = mapped ? wrapMappedTyped<double>(field, slots) : wrapTyped<double>(field, tuples);
    break;
  case ValueType::Int32:
    array = mapped ? wrapMappedTyped<std::int32_t>(field, slots)
                   : wrapTyped<std::int32_t>(field, tuples);
    break;
  case ValueType::Int64:
    array = mapped ? wrapMappedTyped<std::int64_t>(field, slots)
                   : wrapTyped<std::int64_t>(field, tuples);
    break;
  }
  array->SetName(field.name.c_str());
  return array;
}

vtkSmartPointer<vtkDataArray> wrapLeafField(const FieldDescription& field,
                                            const ForestDescription& forest,
                                            const ForestLayout& layout, const LeafTupleMap& map)
{
  // Validation admits only floating-point leaves-only fields.
  vtkSmartPointer<vtkDataArray> array = field.type == ValueType::Float32
                                            ? wrapLeafTyped<float>(field, forest, layout, map)
                                            : wrapLeafTyped<double>(field, forest, layout, map);
  array->SetName(field.name.c_str());
  return array;
}

} // namespace canopy
