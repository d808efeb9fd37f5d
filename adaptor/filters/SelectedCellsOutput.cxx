#include "SelectedCellsOutput.h"

#include "GatherTuples.h"
#include "PointMerger.h"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCellType.h>
#include <vtkDataArray.h>
#include <vtkDoubleArray.h>
#include <vtkHyperTreeGrid.h>
#include <vtkIdTypeArray.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkUnsignedCharArray.h>
#include <vtkUnstructuredGrid.h>

#include <algorithm>

namespace canopy
{

void writeSelectedCells(const HyperTreeAccess& grid, const CellSelection& selection,
                        const std::vector<SelectedNode>& nodes, vtkHyperTreeGrid* input,
                        vtkUnstructuredGrid* output)
{
  output->Initialize();
  // Points merged by exact value, ids in order of first use; arrays sized for
  // the worst case once (growing them costs a copy per doubling).
  const int dimension = grid.dimension();
  const vtkIdType perCell = dimension == 1 ? 2 : dimension == 2 ? 4 : 8;
  const auto count = static_cast<vtkIdType>(nodes.size());
  vtkNew<vtkDoubleArray> coordinates;
  coordinates->SetNumberOfComponents(3);
  coordinates->SetNumberOfTuples(perCell * count);
  PointMerger merger(coordinates->GetPointer(0), static_cast<std::size_t>(perCell * count));
  vtkNew<vtkIdTypeArray> offsets;
  offsets->SetNumberOfTuples(count + 1);
  vtkNew<vtkIdTypeArray> connectivity;
  connectivity->SetNumberOfTuples(perCell * count);
  vtkIdType* offset = offsets->GetPointer(0);
  vtkIdType* ids = connectivity->GetPointer(0);
  for (vtkIdType i = 0; i < count; ++i)
  {
    const SelectedNode& n = nodes[static_cast<std::size_t>(i)];
    offset[i] = perCell * i;
    Vec3 lo;
    Vec3 hi;
    selection.bounds(n, lo, hi);
    if (dimension == 1)
    {
      for (const Vec3& c : segmentEnds(lo, hi, grid.activeAxes()[0]))
      {
        *ids++ = merger.id(c);
      }
    }
    else if (dimension == 3)
    {
      // VTK_HEXAHEDRON: the bottom face (z = lo), then the top one, both
      // counter-clockwise seen from +z.
      for (int k = 0; k < 2; ++k)
      {
        Vec3 layer = lo;
        layer[2] = k ? hi[2] : lo[2];
        for (const Vec3& c : rectangleCorners(layer, hi, 0, 1))
        {
          *ids++ = merger.id(c);
        }
      }
    }
    else
    {
      for (const Vec3& c : rectangleCorners(lo, hi, grid.activeAxes()[0], grid.activeAxes()[1]))
      {
        *ids++ = merger.id(c);
      }
    }
  }
  offset[count] = perCell * count;
  coordinates->SetNumberOfTuples(merger.count()); // shrinks in place
  vtkNew<vtkPoints> points;
  points->SetData(coordinates);
  vtkNew<vtkCellArray> cells;
  cells->SetData(offsets, connectivity);
  output->SetPoints(points);
  output->SetCells(dimension == 1 ? VTK_LINE : dimension == 2 ? VTK_QUAD : VTK_HEXAHEDRON, cells);
  std::vector<vtkIdType> globals(nodes.size());
  for (std::size_t i = 0; i < nodes.size(); ++i)
  {
    globals[i] = nodes[i].global;
  }
  vtkCellData* in = input->GetCellData();
  for (int a = 0; a < in->GetNumberOfArrays(); ++a)
  {
    vtkDataArray* source = in->GetArray(a);
    if (source && source->GetName())
    {
      output->GetCellData()->AddArray(gatherTuples(source, globals.data(), count));
    }
  }
  vtkNew<vtkIdTypeArray> original;
  original->SetName("OriginalCellId");
  original->SetNumberOfTuples(count);
  vtkNew<vtkUnsignedCharArray> level;
  level->SetName("Level");
  level->SetNumberOfTuples(count);
  for (vtkIdType i = 0; i < count; ++i)
  {
    original->SetValue(i, globals[static_cast<std::size_t>(i)]);
    level->SetValue(i, static_cast<unsigned char>(nodes[static_cast<std::size_t>(i)].level));
  }
  output->GetCellData()->AddArray(original);
  output->GetCellData()->AddArray(level);
}

std::array<double, 6> boundsOf(const CellSelection& selection,
                               const std::vector<SelectedNode>& nodes)
{
  std::array<double, 6> bounds{{1e300, -1e300, 1e300, -1e300, 1e300, -1e300}};
  for (const SelectedNode& n : nodes)
  {
    Vec3 lo;
    Vec3 hi;
    selection.bounds(n, lo, hi);
    for (int a = 0; a < 3; ++a)
    {
      bounds[2 * a] = std::min(bounds[2 * a], lo[a]);
      bounds[2 * a + 1] = std::max(bounds[2 * a + 1], hi[a]);
    }
  }
  return bounds;
}

} // namespace canopy
