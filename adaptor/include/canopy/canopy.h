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

  /* ---- forest (borrowed views of the simulation's arrays) ---------------- */
  /* The root grid: rectilinear point coordinates per axis; a 2D forest has one
   * point on one axis, a 1D forest (a line of roots) one point on two axes.
   * [in] dimension      1, 2 or 3.
   * [in] branch_factor  2 or 3.
   * [in] max_levels     levels any tree may have, the root's included: 1 to 62
   *                     for branch factor 2, 1 to 39 for branch factor 3.
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
  /* Forget the trees and fields (e.g. after regridding); the root grid stays.
   * Every array borrowed by canopy_forest_add_* is the caller's again. */
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
   *                       to back). Either every tree has a map or none does. */
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
  /* Finalizes and frees; *insitu becomes NULL. */
  int canopy_close(canopy_insitu** insitu);

#ifdef __cplusplus
}
#endif

#endif /* CANOPY_H */
