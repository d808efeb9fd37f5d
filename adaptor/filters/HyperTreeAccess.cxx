#include "HyperTreeAccess.h"

#include "TopologyStamp.h"

#include <vtkCellData.h>
#include <vtkDataArray.h>
#include <vtkDataSetAttributes.h>
#include <vtkFieldData.h>
#include <vtkSMPTools.h>
#include <vtkUnsignedCharArray.h>

#include <stdexcept>
#include <string>

namespace canopy
{

HyperTreeAccess::HyperTreeAccess(vtkHyperTreeGrid* htg, bool indexTables, bool maskedDescendants)
    : IndexTables(indexTables), MaskedDescendants(maskedDescendants)
{
  Dimension = static_cast<int>(htg->GetDimension());
  BranchFactor = static_cast<int>(htg->GetBranchFactor());
  Children = static_cast<int>(htg->GetNumberOfChildren());
  if (htg->GetTransposedRootIndexing())
  {
    throw std::invalid_argument("grids with transposed root indexing are not supported");
  }
  const unsigned int* dims = htg->GetDimensions();
  vtkDataArray* coords[3] = {htg->GetXCoordinates(), htg->GetYCoordinates(),
                             htg->GetZCoordinates()};
  for (int a = 0; a < 3; ++a)
  {
    if (coords[a] == nullptr || coords[a]->GetNumberOfTuples() < 1)
    {
      throw std::invalid_argument("the grid has no coordinates along an axis");
    }
    RootCells[a] = dims[a] > 1 ? dims[a] - 1 : 1;
    for (vtkIdType i = 0; i < coords[a]->GetNumberOfTuples(); ++i)
    {
      Coordinates[a].push_back(coords[a]->GetComponent(i, 0));
      if (i > 0 && !(Coordinates[a][i] > Coordinates[a][i - 1]))
      {
        throw std::invalid_argument("root coordinates along axis " + std::to_string(a) +
                                    " are not strictly increasing at point " + std::to_string(i));
      }
    }
    Bounds[2 * a] = coords[a]->GetComponent(0, 0);
    Bounds[2 * a + 1] = coords[a]->GetComponent(coords[a]->GetNumberOfTuples() - 1, 0);
    if (dims[a] > 1)
    {
      ActiveAxes.push_back(a);
    }
  }
  Mask = htg->HasMask() ? htg->GetMask() : nullptr;
  MaskSize = Mask ? Mask->GetNumberOfValues() : 0;
  MaskBits = MaskSize > 0 ? Mask->GetPointer(0) : nullptr;
  static_assert(AbsentGhostBit == vtkDataSetAttributes::DUPLICATECELL, "VTK's ghost bits");
  if (auto* ghosts = vtkUnsignedCharArray::SafeDownCast(
          htg->GetCellData()->GetArray(vtkDataSetAttributes::GhostArrayName())))
  {
    GhostsSize = ghosts->GetNumberOfValues();
    Ghosts = GhostsSize > 0 ? ghosts->GetPointer(0) : nullptr;
    for (vtkIdType i = 0; i < GhostsSize && !AnyAbsent; ++i)
    {
      AnyAbsent = (Ghosts[i] & AbsentGhostBit) != 0;
    }
  }
  NumberOfCells = htg->GetNumberOfCells();
  if (vtkDataArray* flag = htg->GetFieldData()->GetArray(missingTreesElsewhereName()))
  {
    MissingTreesElsewhere = flag->GetNumberOfTuples() > 0 && flag->GetComponent(0, 0) != 0;
  }
  // Integer positions are int64: stop before f^level overflows.
  for (std::int64_t p = 1; CellsPerRoot.size() < 64; p *= BranchFactor)
  {
    CellsPerRoot.push_back(p);
    if (p > (std::int64_t(1) << 61) / BranchFactor)
    {
      break;
    }
  }
  for (int c = 0; c < Children; ++c)
  {
    ChildDigits[static_cast<std::size_t>(c)] = {{-1, -1, -1}};
    int rest = c;
    for (int axis : ActiveAxes)
    {
      ChildDigits[static_cast<std::size_t>(c)][static_cast<std::size_t>(axis)] =
          rest % BranchFactor;
      rest /= BranchFactor;
    }
  }
  if (static_cast<int>(ActiveAxes.size()) != Dimension)
  {
    throw std::invalid_argument("only grids with one point on each unused axis are supported");
  }
  TreeAtRoot.assign(static_cast<std::size_t>(RootCells[0]) * RootCells[1] * RootCells[2], -1);
  const std::optional<TopologyStamp> stamp = readTopologyStamp(htg);
  vtkHyperTreeGrid::vtkHyperTreeGridIterator it;
  htg->InitializeTreeIterator(it);
  vtkIdType index = 0;
  while (vtkHyperTree* tree = it.GetNextTree(index))
  {
    if (static_cast<int>(tree->GetNumberOfLevels()) > static_cast<int>(CellsPerRoot.size()))
    {
      throw std::invalid_argument("tree " + std::to_string(index) + " has " +
                                  std::to_string(tree->GetNumberOfLevels()) +
                                  " levels, more than integer positions can address");
    }
    TreeAccess access;
    access.treeIndex = index;
    access.tree = tree;
    access.elderChild = tree->GetElderChildIndexArray(access.elderChildSize);
    access.numberOfVertices = tree->GetNumberOfVertices();
    access.childrenPerNode = Children;
    // VTK 9.2's IsGlobalIndexImplicit() answers the opposite of its name
    // (GlobalIndexStart == -1); the start itself is reliable: -1 means a table.
    access.globalIndexStart = tree->GetGlobalIndexStart();
    access.implicitGlobalIndex = access.globalIndexStart >= 0;
    if (const TreeStamp* vouched = stamp ? stamp->vouchedTree(index, tree) : nullptr)
    {
      access.stampBuilder = stamp->builder;
      access.stampTopology = vouched->topology;
      // Its cells' marks live in the grid's mask and ghost arrays: the stamped ones?
      access.stampMarks = stamp->arraysVouched ? vouched->marks : 0;
    }
    unsigned int ijk[3];
    htg->GetLevelZeroCoordinatesFromIndex(index, ijk[0], ijk[1], ijk[2]);
    for (int a = 0; a < 3; ++a)
    {
      access.rootIJK[a] = ijk[a];
      if (dims[a] > 1)
      {
        access.origin[a] = coords[a]->GetComponent(ijk[a], 0);
        access.size[a] = coords[a]->GetComponent(ijk[a] + 1, 0) - access.origin[a];
      }
      else
      {
        access.origin[a] = coords[a]->GetComponent(0, 0);
        access.size[a] = 0;
      }
    }
    TreeAtRoot[static_cast<std::size_t>(index)] = static_cast<std::int64_t>(Trees.size());
    Trees.push_back(access);
  }
  // Masked descendants: only the 3D surface needs them (to skip solid subtrees).
  // Absent descendants: level of detail must not stop above them.
  const bool masked = Mask && Dimension == 3 && MaskedDescendants;
  if (masked || AnyAbsent || IndexTables)
  {
    vtkSMPTools::For(0, static_cast<vtkIdType>(Trees.size()),
                     [&](vtkIdType begin, vtkIdType end)
                     {
                       for (vtkIdType t = begin; t < end; ++t)
                       {
                         computeHiddenBelow(Trees[static_cast<std::size_t>(t)], masked, AnyAbsent);
                         if (IndexTables && Dimension < 3)
                         {
                           countVisibleLeaves(Trees[static_cast<std::size_t>(t)]);
                         }
                       }
                     });
  }
}

void HyperTreeAccess::computeHiddenBelow(TreeAccess& access, bool masked, bool absent) const
{
  // Children have larger local indices than their parent (breadth-first
  // construction and SubdivideLeaf both append), so one reverse pass suffices.
  const vtkIdType vertices = access.numberOfVertices;
  if (!access.implicitGlobalIndex && (masked || absent || IndexTables))
  {
    access.globalTable.resize(static_cast<std::size_t>(vertices));
    for (vtkIdType n = 0; n < vertices; ++n)
    {
      access.globalTable[static_cast<std::size_t>(n)] = access.tree->GetGlobalIndexFromLocal(n);
    }
  }
  if (masked)
  {
    access.maskedBelow.assign(static_cast<std::size_t>(vertices), 0);
  }
  if (absent)
  {
    access.absentBelow.assign(static_cast<std::size_t>(vertices), 0);
  }
  if (!masked && !absent)
  {
    return;
  }
  for (vtkIdType n = vertices; n-- > 0;)
  {
    if (access.isLeaf(n))
    {
      continue;
    }
    unsigned char maskedHere = 0;
    unsigned char absentHere = 0;
    const vtkIdType first = access.firstChild(n);
    for (vtkIdType c = first; c < first + Children; ++c)
    {
      const auto child = static_cast<std::size_t>(c);
      const vtkIdType global = access.globalIndex(c);
      if (masked)
      {
        maskedHere |= static_cast<unsigned char>(isMasked(global) || access.maskedBelow[child]);
      }
      if (absent)
      {
        absentHere |= static_cast<unsigned char>(isAbsent(global) || access.absentBelow[child]);
      }
    }
    if (masked)
    {
      access.maskedBelow[static_cast<std::size_t>(n)] = maskedHere;
    }
    if (absent)
    {
      access.absentBelow[static_cast<std::size_t>(n)] = absentHere;
    }
  }
}

void HyperTreeAccess::countVisibleLeaves(TreeAccess& access) const
{
  vtkIdType visible = 0;
  std::vector<vtkIdType> stack{0};
  while (!stack.empty())
  {
    const vtkIdType n = stack.back();
    stack.pop_back();
    if (Mask && isMasked(access.globalIndex(n)))
    {
      continue;
    }
    if (access.isLeaf(n))
    {
      ++visible;
      continue;
    }
    const vtkIdType first = access.firstChild(n);
    for (vtkIdType c = first; c < first + Children; ++c)
    {
      stack.push_back(c);
    }
  }
  access.visibleLeaves = visible;
}

bool HyperTreeAccess::treeElsewhere(long i, long j, long k) const
{
  return MissingTreesElsewhere && i >= 0 && j >= 0 && k >= 0 && i < RootCells[0] &&
         j < RootCells[1] && k < RootCells[2] && treeAt(i, j, k) == nullptr;
}

const TreeAccess* HyperTreeAccess::treeAt(long i, long j, long k) const
{
  if (i < 0 || j < 0 || k < 0 || i >= RootCells[0] || j >= RootCells[1] || k >= RootCells[2])
  {
    return nullptr;
  }
  const std::size_t root =
      static_cast<std::size_t>(i) +
      RootCells[0] * (static_cast<std::size_t>(j) + RootCells[1] * static_cast<std::size_t>(k));
  const std::int64_t t = TreeAtRoot[root];
  return t < 0 ? nullptr : &Trees[static_cast<std::size_t>(t)];
}

} // namespace canopy
