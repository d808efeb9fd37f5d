#include "BlockField.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>

namespace canopy
{
namespace
{

bool skipped(double value, bool finiteOnly)
{
  return finiteOnly ? !std::isfinite(value) : std::isnan(value);
}

} // namespace

template <typename T>
BlockField<T>::BlockField(const FieldDescription& field, std::shared_ptr<const BlockCells> cells)
    : Cells(std::move(cells)), Components(field.components)
{
  const BlockStrides& strides = field.blockStrides;
  const int dimension = this->Cells->dimension();
  for (int a = 0; a < dimension; ++a)
  {
    const auto axis = static_cast<std::size_t>(a);
    this->CellBytes[axis] = strides.cellBytes[axis];
    this->InteriorOffset +=
        static_cast<std::size_t>(strides.ghostCells[axis]) * strides.cellBytes[axis];
  }
  for (int c = 0; c < this->Components; ++c)
  {
    const auto component = static_cast<std::size_t>(c);
    if (!field.componentBlockAddresses.empty())
    {
      this->ComponentTable.push_back(field.componentBlockAddresses[component]);
      this->ComponentOffset.push_back(0);
    }
    else
    {
      this->ComponentTable.push_back(field.blockAddresses); // null: one array
      this->ComponentOffset.push_back(component * strides.componentBytes);
    }
  }
  this->Data = static_cast<const unsigned char*>(field.data);
  this->BlockStride = field.blockStrideBytes;

  const int m = this->Cells->blockLevels();
  const std::size_t children = this->Cells->childrenPerNode();
  std::size_t levelSize = 1;
  for (int s = 0; s + 2 <= m; ++s)
  {
    this->PyramidLevelStart.push_back(this->PyramidSize);
    this->PyramidSize += levelSize;
    levelSize *= children;
  }
  const std::size_t blocks = this->Cells->numberOfBlocks();
  const auto nc = static_cast<std::size_t>(this->Components);
  // Each block's pyramid is allocated at its first read: the wrap costs a
  // pointer per block, not a value per cell (BlockField.h).
  this->Pyramids.reset(new std::unique_ptr<T[]>[blocks]);
  this->PyramidBuilt.reset(new std::once_flag[blocks]);
  this->NodeMean.reset(new double[this->Cells->numberOfNodes() * nc]);
  this->NodeMeanBuilt.reset(new std::once_flag[this->Cells->numberOfNodes()]);
}

template <typename T>
const unsigned char* BlockField<T>::blockStart(std::size_t block, int component) const
{
  const auto c = static_cast<std::size_t>(component);
  const void* const* table = this->ComponentTable[c];
  const unsigned char* start = table ? static_cast<const unsigned char*>(table[block])
                                     : this->Data + block * this->BlockStride;
  return start + this->ComponentOffset[c] + this->InteriorOffset;
}

template <typename T>
T BlockField<T>::leaf(std::size_t block, const std::array<std::uint32_t, 3>& position,
                      int component) const
{
  const unsigned char* address =
      this->blockStart(block, component) + position[0] * this->CellBytes[0] +
      position[1] * this->CellBytes[1] + position[2] * this->CellBytes[2];
  T value;
  std::memcpy(&value, address, sizeof(T));
  return value;
}

template <typename T>
template <typename Visit>
void BlockField<T>::forEachLeaf(Visit&& visit) const
{
  // Axes beyond the dimension have one cell (their stride is 0 here).
  const std::size_t n = this->Cells->cellsPerSide();
  const int dimension = this->Cells->dimension();
  const std::size_t nj = dimension >= 2 ? n : 1;
  const std::size_t nk = dimension >= 3 ? n : 1;
  std::array<std::uint32_t, 3> p{{0, 0, 0}};
  for (p[2] = 0; p[2] < nk; ++p[2])
  {
    for (p[1] = 0; p[1] < nj; ++p[1])
    {
      for (p[0] = 0; p[0] < n; ++p[0])
      {
        visit(p);
      }
    }
  }
}

template <typename T>
void BlockField<T>::buildPyramid(std::size_t block) const
{
  const int m = this->Cells->blockLevels();
  const auto bf = static_cast<std::uint32_t>(this->Cells->branchFactor());
  const int dimension = this->Cells->dimension();
  const std::size_t children = this->Cells->childrenPerNode();
  const auto nc = static_cast<std::size_t>(this->Components);
  this->Pyramids[block].reset(new T[nc * this->PyramidSize]);
  T* pyramid = this->Pyramids[block].get();
  // Level m-1 (the cells' parents) in double, then each level from the one below.
  std::size_t side = this->Cells->cellsPerSide() / bf;
  const std::size_t sideJ = dimension >= 2 ? side : 1;
  const std::size_t sideK = dimension >= 3 ? side : 1;
  std::vector<double> below;
  std::vector<double> above;
  for (std::size_t c = 0; c < nc; ++c)
  {
    below.assign(side * sideJ * sideK, 0.0); // the last component left it a level above
    this->forEachLeaf(
        [&](const std::array<std::uint32_t, 3>& p)
        {
          below[p[0] / bf + side * (p[1] / bf + sideJ * (p[2] / bf))] +=
              static_cast<double>(this->leaf(block, p, static_cast<int>(c)));
        });
    for (double& sum : below)
    {
      sum /= static_cast<double>(children);
    }
    std::size_t belowSide = side;
    for (int s = m - 2; s >= 0; --s)
    {
      const std::size_t aboveSide = belowSide / bf;
      const std::size_t aboveJ = dimension >= 2 ? aboveSide : 1;
      const std::size_t aboveK = dimension >= 3 ? aboveSide : 1;
      const std::size_t belowJ = dimension >= 2 ? belowSide : 1;
      const std::size_t belowK = dimension >= 3 ? belowSide : 1;
      above.assign(aboveSide * aboveJ * aboveK, 0.0);
      for (std::size_t k = 0; k < belowK; ++k)
      {
        for (std::size_t j = 0; j < belowJ; ++j)
        {
          for (std::size_t i = 0; i < belowSide; ++i)
          {
            above[i / bf + aboveSide * (j / bf + aboveJ * (k / bf))] +=
                below[i + belowSide * (j + belowJ * k)];
          }
        }
      }
      T* level =
          pyramid + c * this->PyramidSize + this->PyramidLevelStart[static_cast<std::size_t>(s)];
      for (std::size_t v = 0; v < above.size(); ++v)
      {
        above[v] /= static_cast<double>(children);
        level[v] = static_cast<T>(above[v]);
      }
      below.swap(above);
      belowSide = aboveSide;
    }
  }
}

template <typename T>
double BlockField<T>::coarseInBlock(std::size_t block, int subLevel,
                                    const std::array<std::uint32_t, 3>& position,
                                    int component) const
{
  const int m = this->Cells->blockLevels();
  const auto bf = static_cast<std::uint32_t>(this->Cells->branchFactor());
  const int dimension = this->Cells->dimension();
  if (subLevel == m - 1)
  {
    // The cells' parent: the mean of its bf^d cells, read now.
    double sum = 0.0;
    const std::size_t children = this->Cells->childrenPerNode();
    for (std::size_t child = 0; child < children; ++child)
    {
      std::array<std::uint32_t, 3> p = position;
      std::size_t digit = child;
      for (int a = 0; a < dimension; ++a)
      {
        p[static_cast<std::size_t>(a)] =
            p[static_cast<std::size_t>(a)] * bf + static_cast<std::uint32_t>(digit % bf);
        digit /= bf;
      }
      sum += static_cast<double>(this->leaf(block, p, component));
    }
    return sum / static_cast<double>(children);
  }
  std::call_once(this->PyramidBuilt[block], [&] { this->buildPyramid(block); });
  std::size_t side = 1;
  for (int s = 0; s < subLevel; ++s)
  {
    side *= bf;
  }
  const std::size_t sideJ = dimension >= 2 ? side : 1;
  const std::size_t at = position[0] + side * (position[1] + sideJ * position[2]);
  return static_cast<double>(
      this->Pyramids[block][static_cast<std::size_t>(component) * this->PyramidSize +
                            this->PyramidLevelStart[static_cast<std::size_t>(subLevel)] + at]);
}

template <typename T>
double BlockField<T>::nodeValue(std::size_t node, int component) const
{
  const BlockCells& cells = *this->Cells;
  if (cells.isAbsent(node))
  {
    return std::numeric_limits<double>::quiet_NaN();
  }
  if (const std::int64_t block = cells.blockOfNode(node); block >= 0)
  {
    return this->coarseInBlock(static_cast<std::size_t>(block), 0, {{0, 0, 0}}, component);
  }
  const auto nc = static_cast<std::size_t>(this->Components);
  std::call_once(this->NodeMeanBuilt[node],
                 [&]
                 {
                   const auto first = static_cast<std::size_t>(cells.firstChildOfNode(node));
                   const std::size_t children = cells.childrenPerNode();
                   for (std::size_t c = 0; c < nc; ++c)
                   {
                     double sum = 0.0;
                     std::size_t used = 0;
                     // Pass 0: unmasked children; pass 1 (all masked): every present one.
                     for (int pass = 0; pass < 2 && used == 0; ++pass)
                     {
                       for (std::size_t k = 0; k < children; ++k)
                       {
                         const std::size_t child = first + k;
                         if (cells.isAbsent(child) || (pass == 0 && cells.isMasked(child)))
                         {
                           continue;
                         }
                         sum += this->nodeValue(child, static_cast<int>(c));
                         ++used;
                       }
                     }
                     this->NodeMean[node * nc + c] = used == 0
                                                         ? std::numeric_limits<double>::quiet_NaN()
                                                         : sum / static_cast<double>(used);
                   }
                 });
  return this->NodeMean[node * nc + static_cast<std::size_t>(component)];
}

template <typename T>
T BlockField<T>::at(std::uint64_t cell, int component) const
{
  const BlockCells::Location where = this->Cells->locate(cell);
  if (where.subLevel == 0)
  {
    return static_cast<T>(this->nodeValue(static_cast<std::size_t>(where.node), component));
  }
  const auto block = static_cast<std::size_t>(where.block);
  if (where.subLevel == this->Cells->blockLevels())
  {
    return this->leaf(block, where.position, component);
  }
  return static_cast<T>(this->coarseInBlock(block, where.subLevel, where.position, component));
}

template <typename T>
void BlockField<T>::tuple(std::uint64_t cell, T* values) const
{
  const BlockCells::Location where = this->Cells->locate(cell);
  const auto block = static_cast<std::size_t>(where.block);
  for (int c = 0; c < this->Components; ++c)
  {
    if (where.subLevel == 0)
    {
      values[c] = static_cast<T>(this->nodeValue(static_cast<std::size_t>(where.node), c));
    }
    else if (where.subLevel == this->Cells->blockLevels())
    {
      values[c] = this->leaf(block, where.position, c);
    }
    else
    {
      values[c] = static_cast<T>(this->coarseInBlock(block, where.subLevel, where.position, c));
    }
  }
}

template <typename T>
bool BlockField<T>::leafRanges(double* ranges, bool finiteOnly) const
{
  const std::size_t blocks = this->Cells->numberOfBlocks();
  for (int c = 0; c < this->Components; ++c)
  {
    double low = std::numeric_limits<double>::max();
    double high = std::numeric_limits<double>::lowest();
    for (std::size_t b = 0; b < blocks; ++b)
    {
      this->forEachLeaf(
          [&](const std::array<std::uint32_t, 3>& p)
          {
            const auto value = static_cast<double>(this->leaf(b, p, c));
            if (!skipped(value, finiteOnly))
            {
              low = std::min(low, value);
              high = std::max(high, value);
            }
          });
    }
    ranges[2 * c] = low;
    ranges[2 * c + 1] = high;
  }
  return this->Cells->numberOfCells() > 0;
}

template <typename T>
bool BlockField<T>::leafNormRange(double range[2], bool finiteOnly) const
{
  double low = std::numeric_limits<double>::max();
  double high = std::numeric_limits<double>::lowest();
  for (std::size_t b = 0; b < this->Cells->numberOfBlocks(); ++b)
  {
    this->forEachLeaf(
        [&](const std::array<std::uint32_t, 3>& p)
        {
          double squared = 0.0;
          for (int c = 0; c < this->Components; ++c)
          {
            const auto value = static_cast<double>(this->leaf(b, p, c));
            squared += value * value;
          }
          if (!skipped(squared, finiteOnly))
          {
            low = std::min(low, squared);
            high = std::max(high, squared);
          }
        });
  }
  range[0] = low <= high ? std::sqrt(low) : low;
  range[1] = low <= high ? std::sqrt(high) : high;
  return this->Cells->numberOfCells() > 0;
}

template class BlockField<float>;
template class BlockField<double>;

} // namespace canopy
