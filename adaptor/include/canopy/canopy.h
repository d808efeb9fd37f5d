/* Canopy's C API: the in-situ calls for C and Fortran (iso_c_binding) codes.
 *
 *   canopy_options* options = NULL;
 *   canopy_options_create(&options);
 *   canopy_options_add_script(options, "pipelines/surface_image.py");
 *   canopy_insitu* insitu = NULL;
 *   canopy_open(MPI_COMM_WORLD, options, &insitu);            (Fortran: canopy_open_f)
 *   each step:   canopy_execute(insitu, step, time, forest);  (forest: canopy_forest_*)
 *   at the end:  canopy_close(&insitu);
 *
 * Every function but the destroy ones returns CANOPY_OK (0) or an error code;
 * canopy_last_error() then says what went wrong. No C++ exception ever leaves
 * these functions; a failed call changes nothing (see each function).
 *
 * Ownership words used below (as in p4est's headers):
 *   copied    Canopy copies the value during the call; the caller may free or
 *             reuse it as soon as the call returns.
 *   borrowed  Canopy keeps the pointer and reads through it later (in
 *             canopy_execute), never writes through it and never frees it; the
 *             memory must stay valid, in place and of the same size until the
 *             forest is cleared (canopy_forest_clear) or destroyed. Its contents
 *             may change between calls: each canopy_execute reads them afresh.
 *   owned     the handle belongs to the caller, who frees it with the matching
 *             destroy/close function.
 * See docs/insitu.md. */
#ifndef CANOPY_H
#define CANOPY_H

#include <mpi.h>
#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C"
{
#endif

  enum canopy_status
  {
    CANOPY_OK = 0,
    CANOPY_INVALID_ARGUMENT = 1, /* a null handle, a bad value; nothing was done */
    CANOPY_OPEN_FAILED = 2,      /* canopy_open: Catalyst or a script could not start */
    CANOPY_STEP_FAILED = 3,      /* canopy_execute: a pipeline or the forest failed; step skipped */
    CANOPY_OUT_OF_MEMORY = 4     /* an allocation failed; nothing was done */
  };

  enum canopy_value_type
  {
    CANOPY_FLOAT32 = 0,
    CANOPY_FLOAT64 = 1,
    CANOPY_INT32 = 2,
    CANOPY_INT64 = 3
  };

  enum canopy_centering
  {
    CANOPY_EVERY_NODE = 0, /* one tuple per node, indexed by storage slot */
    CANOPY_LEAVES_ONLY = 1 /* one tuple per leaf, leaves in storage order */
  };

  /* Block forests: how a block's array orders its cells and components, for
   * canopy_block_strides_packed (C order, i along the first axis that is not flat). */
  enum canopy_block_order
  {
    CANOPY_VARIABLE_OUTERMOST = 0, /* [var][k][j][i]: each component a whole block array
                                      (Athena++, Parthenon; Fortran u(i, j, k, var)) */
    CANOPY_VARIABLE_INNERMOST = 1  /* [k][j][i][var]: a cell's components together
                                      (Fortran unk(var, i, j, k, block): FLASH) */
  };

  /* Where the cells of one block lie in its array (a block field). Interior cell
   * (i, j, k), 0 <= i, j, k < cells_per_side, component c is at the address
   *   block start + c * component_bytes + (i + ghost_cells[0]) * cell_bytes[0]
   *     + (j + ghost_cells[1]) * cell_bytes[1] + (k + ghost_cells[2]) * cell_bytes[2]
   * where the block starts at its first ghost cell. i, j, k run along the forest's
   * axes that are not flat, in x, y, z order (a 2D forest in the xz-plane: i along x,
   * j along z); the entries of missing axes are ignored. Ghost cells are never read.
   * canopy_block_strides_packed fills one for the two usual orders. */
  typedef struct canopy_block_strides
  {
    size_t cell_bytes[3];   /* from cell i to i+1, j to j+1, k to k+1 */
    size_t component_bytes; /* from component c to c+1 (unused by
                               canopy_forest_add_block_field_components) */
    int ghost_cells[3];     /* ghost cells before the interior, per axis */
  } canopy_block_strides;

  typedef struct canopy_options canopy_options;
  typedef struct canopy_forest canopy_forest;
  typedef struct canopy_insitu canopy_insitu;

  /* The message of this thread's last Canopy call if it failed, "" if it succeeded.
   * Owned by Canopy: valid until the next Canopy call on this thread. */
  const char* canopy_last_error(void);

  /* Counts (size_t) above PTRDIFF_MAX are refused as CANOPY_INVALID_ARGUMENT: they
   * are negative numbers converted to size_t (e.g. from Fortran's signed c_size_t). */

  /* ---- options ---------------------------------------------------------- */
  /* [out] options  a new owned handle with the defaults (output directory
   *                "canopy-output", channel "grid"); NULL on failure. */
  int canopy_options_create(canopy_options** options);
  /* [in] options  owned handle, or NULL (nothing to do). May be destroyed right
   *               after canopy_open: the in-situ handle keeps its own copy. */
  void canopy_options_destroy(canopy_options* options);
  /* A Catalyst script (ParaView 5.9+ format).
   * [in] path  copied; not NULL, not empty. */
  int canopy_options_add_script(canopy_options* options, const char* path);
  /* An argument for the script added last, e.g. "--frequency=5".
   * [in] argument  copied; not NULL (may be empty). */
  int canopy_options_add_script_argument(canopy_options* options, const char* argument);
  /* [in] directory  copied; not NULL, not empty. */
  int canopy_options_set_output_directory(canopy_options* options, const char* directory);
  /* [in] channel  copied; not NULL, not empty. */
  int canopy_options_set_channel(canopy_options* options, const char* channel);
  /* vtkLogger stderr verbosity (0 = INFO, 9 = TRACE); below -9 leaves it unchanged. */
  int canopy_options_set_verbosity(canopy_options* options, int verbosity);
  /* [in] enabled  nonzero: rank 0 logs one line per executed step. */
  int canopy_options_set_step_summary(canopy_options* options, int enabled);
  /* The longest a call into a script may take, in seconds (0: no limit); see
   * InSituOptions::stepTimeLimitSeconds. */
  int canopy_options_set_step_time_limit(canopy_options* options, double seconds);
  /* [in] expression  copied; a query-language expression computed every evaluated step
   *                   (docs/queries.md), e.g. "max(density)"; read with canopy_query_value. */
  int canopy_options_add_query(canopy_options* options, const char* expression);
  /* [in] name  copied; a field the simulation describes: triggers and queries naming
   *            another field are then refused at open. */
  int canopy_options_add_field_name(canopy_options* options, const char* name);

  /* ---- forest (borrowed views of the simulation's arrays) ---------------- */
  /* The root grid: rectilinear point coordinates per axis; a 2D forest has one
   * point on one axis, a 1D forest (a line of roots) one point on two axes.
   * [in] dimension      1, 2 or 3.
   * [in] branch_factor  2 or 3.
   * [in] max_levels     levels any tree may have, the root's included: 1 to 62
   *                     for branch factor 2, 1 to 39 for branch factor 3 (in a
   *                     block forest, the levels inside its blocks included).
   * [in] x, y, z        borrowed until canopy_forest_destroy (clear keeps the root
   *                     grid): points_x (points_y, points_z) increasing doubles.
   * [in] points_x, points_y, points_z  at least 1 each.
   * [out] forest        a new owned handle without trees or fields; NULL on failure.
   * The coordinates' values, and how the counts fit the dimension, are checked at
   * canopy_execute, which reports them with the rank and step. */
  int canopy_forest_create(int dimension, int branch_factor, int max_levels, const double* x,
                           size_t points_x, const double* y, size_t points_y, const double* z,
                           size_t points_z, canopy_forest** forest);
  /* [in] forest  owned handle, or NULL (nothing to do); the arrays it borrowed are
   *              the caller's again. */
  void canopy_forest_destroy(canopy_forest* forest);
  /* Forget the trees and fields (e.g. after regridding); the root grid and the
   * block size (canopy_forest_set_blocks) stay. Every array borrowed by
   * canopy_forest_add_* is the caller's again. */
  int canopy_forest_clear(canopy_forest* forest);
  /* One tree of this rank, described breadth-first (see docs/api.md).
   * [in] root_index       the root cell, i fastest, then j, then k; not negative.
   * [in] refinement       borrowed until clear/destroy: number_of_nodes bytes,
   *                       nonzero = refined; not NULL.
   * [in] number_of_nodes  at least 1 (the root).
   * [in] masked           borrowed until clear/destroy: number_of_nodes bytes,
   *                       nonzero = masked with its subtree; or NULL (none masked).
   * [in] storage_slots    borrowed until clear/destroy: number_of_nodes node ->
   *                       storage slot entries; or NULL (breadth-first, trees back
   *                       to back). Either every tree has a map or none does. NULL in
   *                       a block forest (canopy_forest_set_blocks). */
  int canopy_forest_add_tree(canopy_forest* forest, int64_t root_index, const uint8_t* refinement,
                             size_t number_of_nodes, const uint8_t* masked,
                             const int64_t* storage_slots);
  /* A tree split between ranks (as p4est splits them): this rank's part of it.
   * The parameters are those of canopy_forest_add_tree, and:
   * [in] absent  borrowed until clear/destroy: number_of_nodes bytes, nonzero =
   *              another rank owns this node's part of the tree. An absent node is
   *              a leaf of this description, never the root, and has no storage slot
   *              and no field values; or NULL: the whole tree is this rank's (the
   *              same as canopy_forest_add_tree). */
  int canopy_forest_add_partial_tree(canopy_forest* forest, int64_t root_index,
                                     const uint8_t* refinement, size_t number_of_nodes,
                                     const uint8_t* masked, const int64_t* storage_slots,
                                     const uint8_t* absent);
  /* A field with tuples packed (tuple_stride_bytes = 0) or tuple_stride_bytes apart.
   * Not in a block forest (canopy_forest_set_blocks): its fields are block fields.
   * [in] name        copied; not NULL, not empty.
   * [in] value_type  a canopy_value_type.
   * [in] components  at least 1.
   * [in] data        borrowed until clear/destroy: number_of_tuples tuples; NULL
   *                  only with number_of_tuples = 0 (a rank without trees).
   * [in] tuple_stride_bytes  0 (packed) or at least components * the value size.
   * [in] centering   a canopy_centering. */
  int canopy_forest_add_field(canopy_forest* forest, const char* name, int value_type,
                              int components, const void* data, size_t tuple_stride_bytes,
                              size_t number_of_tuples, int centering);
  /* A field with one array per component (structure of arrays).
   * [in] component_data  copied: `components` addresses, each borrowed until
   *                      clear/destroy (number_of_tuples values; NULL only with
   *                      number_of_tuples = 0). Not NULL itself.
   * The other parameters are those of canopy_forest_add_field. */
  int canopy_forest_add_field_soa(canopy_forest* forest, const char* name, int value_type,
                                  int components, const void* const* component_data,
                                  size_t number_of_tuples, int centering);

  /* ---- block forests (octrees of blocks: Athena++/Parthenon MeshBlocks, FLASH,
   * ForestClaw patches) ---------------------------------------------------- */
  /* Every present leaf of the trees is then a block of cells_per_side^d cells, kept
   * in the simulation's own block arrays (ghost cells included); the cells become
   * uniform levels of the grid below the leaf. The forest's fields are then block
   * fields (canopy_forest_add_block_field*), its trees have no storage slots. Set
   * it right after canopy_forest_create or canopy_forest_clear (the forest has no
   * trees or fields yet); canopy_forest_clear keeps it.
   * [in] cells_per_side  0: an ordinary forest (the default); else a power of the
   *                      branch factor (2, 4, 8, 16, 32, ... with branch factor 2;
   *                      3, 9, 27, ... with 3), whose levels inside a block, with
   *                      the root's, fit in max_levels: max_levels counts them (a
   *                      tree refined r times with blocks of 2^s cells across has
   *                      r + 1 + s levels). */
  int canopy_forest_set_blocks(canopy_forest* forest, int cells_per_side);
  /* One tree of a block forest: canopy_forest_add_partial_tree's parameters without
   * storage slots (canopy_forest_add_tree and canopy_forest_add_partial_tree take
   * block forests' trees too, with storage_slots NULL), and:
   * [in] block_index  borrowed until clear/destroy: number_of_nodes entries, per
   *                   node breadth-first, the index (from 0) of the leaf's block in
   *                   the fields' block tables; entries of refined and absent nodes
   *                   are ignored. Or NULL: blocks are the present leaves
   *                   breadth-first, tree by tree, in the order the trees were
   *                   added. Either every tree has one or none does; the present
   *                   leaves' entries are then exactly 0 .. blocks-1 (checked at
   *                   canopy_execute).
   * [in] absent       as canopy_forest_add_partial_tree (an absent leaf is no block);
   *                   or NULL. */
  int canopy_forest_add_block_tree(canopy_forest* forest, int64_t root_index,
                                   const uint8_t* refinement, size_t number_of_nodes,
                                   const uint8_t* masked, const uint8_t* absent,
                                   const int64_t* block_index);
  /* The strides of a block array of (cells_per_side + 2 ghost_cells)^dimension cells,
   * nothing between cells, in either order, so that nothing needs computing in bytes.
   * [in] dimension      the forest's: 1, 2 or 3 (the array's other axes have extent 1).
   * [in] cells_per_side at least 1: the forest's (canopy_forest_set_blocks).
   * [in] ghost_cells    at least 0, on each side of each axis that is not flat.
   * [in] components     at least 1; 1 for one component's array of
   *                     canopy_forest_add_block_field_components.
   * [in] value_type     a canopy_value_type.
   * [in] order          a canopy_block_order.
   * [out] strides       not NULL; unchanged on failure.
   * [out] block_bytes   the bytes of one whole block (the block_stride_bytes of
   *                     canopy_forest_add_block_field_array when blocks follow each
   *                     other), or NULL. */
  int canopy_block_strides_packed(int dimension, int cells_per_side, int ghost_cells,
                                  int components, int value_type, int order,
                                  canopy_block_strides* strides, size_t* block_bytes);
  /* A block field whose blocks are allocated one by one. Its coarse values (inside and
   * above blocks) are volume averages of the blocks' cells.
   * [in] name             copied; not NULL, not empty.
   * [in] value_type       CANOPY_FLOAT32 or CANOPY_FLOAT64.
   * [in] components       at least 1.
   * [in] block_addresses  copied: number_of_blocks addresses, block b's array (its
   *                       first ghost cell) at block_addresses[b], each borrowed until
   *                       clear/destroy, none NULL, each aligned to the value size.
   *                       NULL only with number_of_blocks = 0 (a rank without trees).
   *                       Blocks that move (regridding) are given again: clear the
   *                       forest and describe it anew.
   * [in] number_of_blocks at least the forest's blocks on this rank (checked at
   *                       canopy_execute).
   * [in] strides          copied; not NULL: for each axis that is not flat,
   *                       cell_bytes a nonzero multiple of the value size and
   *                       ghost_cells not negative; with 2 or more components,
   *                       component_bytes a nonzero multiple of the value size. */
  int canopy_forest_add_block_field(canopy_forest* forest, const char* name, int value_type,
                                    int components, const void* const* block_addresses,
                                    size_t number_of_blocks, const canopy_block_strides* strides);
  /* A block field whose blocks are all in one array (FLASH's unk): block b's array
   * begins at first_block + b * block_stride_bytes.
   * [in] first_block         borrowed until clear/destroy: where block 0's array
   *                          begins, aligned to the value size; NULL only with
   *                          number_of_blocks = 0.
   * [in] block_stride_bytes  a nonzero multiple of the value size (any value with 1
   *                          block or none).
   * [in] number_of_blocks    the blocks the array holds: at least the forest's
   *                          blocks on this rank (more is fine: a fixed-size array).
   * The other parameters are those of canopy_forest_add_block_field. */
  int canopy_forest_add_block_field_array(canopy_forest* forest, const char* name, int value_type,
                                          int components, const void* first_block,
                                          size_t block_stride_bytes, size_t number_of_blocks,
                                          const canopy_block_strides* strides);
  /* A block field whose components are each in per-block arrays of their own (a
   * vector kept as scalar variables).
   * [in] block_addresses  copied: components * number_of_blocks addresses, component c
   *                       of block b at block_addresses[c * number_of_blocks + b] (a
   *                       C array [components][number_of_blocks]; Fortran
   *                       addresses(number_of_blocks, components)), each borrowed
   *                       until clear/destroy, none NULL; NULL only with
   *                       number_of_blocks = 0.
   * [in] strides          as canopy_forest_add_block_field, component_bytes unused:
   *                       those of one component's array.
   * The other parameters are those of canopy_forest_add_block_field. */
  int canopy_forest_add_block_field_components(canopy_forest* forest, const char* name,
                                               int value_type, int components,
                                               const void* const* block_addresses,
                                               size_t number_of_blocks,
                                               const canopy_block_strides* strides);

  /* ---- the in-situ calls (collective over the communicator) ------------- */
  /* They refuse a NULL handle, NULL options or MPI_COMM_NULL before anything
   * collective: pass valid arguments on every rank, or the others wait. */
  /* [in] communicator  duplicated; not MPI_COMM_NULL.
   * [in] options       copied; the caller may destroy it after the call.
   * [out] insitu       a new owned handle (free it with canopy_close); NULL on failure. */
  int canopy_open(MPI_Comm communicator, const canopy_options* options, canopy_insitu** insitu);
  /* Fortran: the communicator as an integer handle (MPI_COMM_WORLD from mpi_f08%MPI_VAL). */
  int canopy_open_f(MPI_Fint communicator, const canopy_options* options, canopy_insitu** insitu);
  /* [out] will_execute  1 when some pipeline runs at this step (skip preparing data
   *                     otherwise), else 0. */
  int canopy_will_execute(canopy_insitu* insitu, int64_t step, double time, int* will_execute);
  /* [in] forest  this rank's forest; its borrowed arrays are read during the call.
   *              NULL still takes part in the collective: every rank skips the step. */
  int canopy_execute(canopy_insitu* insitu, int64_t step, double time, const canopy_forest* forest);
  /* canopy_will_execute with the step's forest: also runs the step's queries (one
   * collective, no grid built) and decides the scripts' triggers (docs/queries.md).
   * [in] forest  read during the call; NULL still takes part (the queries then fail). */
  int canopy_will_execute_forest(canopy_insitu* insitu, int64_t step, double time,
                                 const canopy_forest* forest, int* will_execute);
  /* The value of a query-language expression given with canopy_options_add_query (or a
   * query of a trigger, by its text, e.g. "max(density)") at the last canopy_execute
   * that evaluated the queries; the same on every rank. Not collective.
   * [in] expression  as given; [out] value  NaN when not evaluated (CANOPY_INVALID_ARGUMENT
   *                  when the expression is unknown). */
  int canopy_query_value(canopy_insitu* insitu, const char* expression, double* value);
  /* Finalizes and frees; *insitu becomes NULL. */
  int canopy_close(canopy_insitu** insitu);

#ifdef __cplusplus
}
#endif

#endif /* CANOPY_H */
