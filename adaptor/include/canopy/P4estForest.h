// Canopy::p4est: this rank's part of a p4est (2D) or p8est (3D) forest described
// for Canopy, without copying field values.
//
//   canopy::P4estForest described(p4est);              // after refine/balance/partition
//   described.addQuadrantField("density", density);    // one value per local quadrant
//   insitu.execute(step, time, described.description());
//
// What it describes. The forest must live on a brick-like connectivity
// (p4est_connectivity_new_brick, periodic or not, or any connectivity whose
// trees are unrotated axis-aligned boxes tiling a rectilinear lattice of its
// vertices): the root grid is that lattice, in vertex coordinates. Each local
// tree becomes a Canopy tree described breadth-first down to this rank's
// quadrants; the parts of a tree that other ranks own (p4est splits trees
// between ranks) are absent leaves, so no rank needs values it does not own.
// Fields are leaves-only, in p4est's own order (local quadrant number: trees in
// order, each in Morton order), read in place: an array indexed by local
// quadrant number, or a member of each quadrant's user_data.
//
// Lifetime. The description borrows the forest: it is valid until the forest
// changes (refine, coarsen, balance, partition, p4est_reset_data) or is
// destroyed; describe it again after every such change. description() checks
// the forest's revision counter and quadrant count and throws InvalidForest if
// the forest changed since it was described. The field arrays are borrowed as
// well and must stay alive while a grid built from the description is in use.
#pragma once

#include <canopy/ForestDescription.h>
#include <canopy/ForestValidation.h>

#include <cstddef>
#include <memory>
#include <string>

// p4est's forest types (p4est_t and p8est_t), without including p4est here.
struct p4est;
struct p8est;

namespace canopy
{

namespace detail
{
template <int Dimension>
struct P4estTypes;
template <>
struct P4estTypes<2>
{
  using Forest = ::p4est;
};
template <>
struct P4estTypes<3>
{
  using Forest = ::p8est;
};
} // namespace detail

/// This rank's part of a p4est (Dimension 2) or p8est (Dimension 3) forest.
/// Use the aliases P4estForest and P8estForest.
template <int Dimension>
class BasicP4estForest
{
public:
  using Forest = typename detail::P4estTypes<Dimension>::Forest;

  /// Describes the local part of `forest` (not collective; each rank describes
  /// its own). `forest`: borrowed, not modified; must stay unchanged while the
  /// description is used. Throws InvalidForest, listing every problem, when the
  /// connectivity is not brick-like (no vertices, rotated or non-box trees, trees
  /// that do not tile a lattice) or the forest is inconsistent; nothing is kept.
  explicit BasicP4estForest(const Forest* forest);
  ~BasicP4estForest();
  BasicP4estForest(BasicP4estForest&&) noexcept;
  BasicP4estForest& operator=(BasicP4estForest&&) noexcept;
  BasicP4estForest(const BasicP4estForest&) = delete;
  BasicP4estForest& operator=(const BasicP4estForest&) = delete;

  /// A field held in an array indexed by local quadrant number (what most codes
  /// keep): `values` has local_num_quadrants tuples of `components` values, AoS.
  /// `values`: borrowed, read in place, never written; keep it alive and
  /// unresized while a grid built from the description is in use. Throws
  /// InvalidForest for an empty or duplicate name or components < 1.
  template <typename T>
  void addQuadrantField(std::string name, const T* values, int components = 1)
  {
    addQuadrantField(std::move(name), valueTypeOf<T>(), values, components);
  }
  void addQuadrantField(std::string name, ValueType type, const void* values, int components);

  /// A field inside each quadrant's user_data: `components` values of type T at
  /// `byteOffset` bytes into the quadrant's data (of the forest's data_size).
  /// Read in place through one address per quadrant that this object keeps;
  /// valid until the forest changes (p4est_reset_data included). Throws
  /// InvalidForest when the forest has no user data, the field does not fit in
  /// data_size, or the name is empty or taken.
  template <typename T>
  void addUserDataField(std::string name, std::size_t byteOffset, int components = 1)
  {
    addUserDataField(std::move(name), valueTypeOf<T>(), byteOffset, components);
  }
  void addUserDataField(std::string name, ValueType type, std::size_t byteOffset, int components);

  /// The description for canopy::buildHyperTreeGrid or InSitu::execute: valid
  /// while this object lives and the forest is unchanged. Throws InvalidForest if
  /// the forest changed since it was described (revision or quadrant count).
  const ForestDescription& description() const;

  /// Quadrants this rank owns (the tuples of every field).
  std::size_t numberOfQuadrants() const;
  /// Trees this rank has quadrants in; those split with other ranks have absent parts.
  std::size_t numberOfLocalTrees() const;

private:
  struct State;
  std::unique_ptr<State> Impl;
};

using P4estForest = BasicP4estForest<2>;
using P8estForest = BasicP4estForest<3>;

extern template class BasicP4estForest<2>;
extern template class BasicP4estForest<3>;

} // namespace canopy
