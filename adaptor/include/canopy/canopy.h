/* Canopy's C API: the in-situ calls for C and Fortran (iso_c_binding) codes.
 *
 *   canopy_options* options = canopy_options_create();
 *   canopy_options_add_script(options, "pipelines/surface_image.py");
 *   canopy_insitu* insitu = NULL;
 *   canopy_open(MPI_COMM_WORLD, options, &insitu);            (Fortran: canopy_open_f)
 *   each step:   canopy_execute(insitu, step, time, forest);  (forest: canopy_forest_*)
 *   at the end:  canopy_close(&insitu);
 *
 * Every function returns CANOPY_OK (0) or an error code; canopy_last_error()
 * then says what went wrong. Pointers given to a canopy_forest are borrowed:
 * Canopy never writes through them and keeps them only until the forest is
 * cleared or destroyed. See docs/insitu.md. */
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
    CANOPY_STEP_FAILED = 3       /* canopy_execute: a pipeline or the forest failed; step skipped */
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

  /* The message of the last call that failed on this thread ("" if none). */
  const char* canopy_last_error(void);

  /* ---- options ---------------------------------------------------------- */
  canopy_options* canopy_options_create(void);
  void canopy_options_destroy(canopy_options* options);
  /* A Catalyst script (ParaView 5.9+ format). */
  int canopy_options_add_script(canopy_options* options, const char* path);
  /* An argument for the script added last, e.g. "--frequency=5". */
  int canopy_options_add_script_argument(canopy_options* options, const char* argument);
  int canopy_options_set_output_directory(canopy_options* options, const char* directory);
  int canopy_options_set_channel(canopy_options* options, const char* channel);
  /* vtkLogger stderr verbosity (0 = INFO, 9 = TRACE); below -9 leaves it unchanged. */
  int canopy_options_set_verbosity(canopy_options* options, int verbosity);
  int canopy_options_set_step_summary(canopy_options* options, int enabled);
  /* The longest a call into a script may take, in seconds (0: no limit); see
   * InSituOptions::stepTimeLimitSeconds. */
  int canopy_options_set_step_time_limit(canopy_options* options, double seconds);

  /* ---- forest (borrowed views of the simulation's arrays) ---------------- */
  /* Root grid point coordinates per axis; a 2D forest has one point on one axis. */
  canopy_forest* canopy_forest_create(int dimension, int branch_factor, int max_levels,
                                      const double* x, size_t points_x, const double* y,
                                      size_t points_y, const double* z, size_t points_z);
  void canopy_forest_destroy(canopy_forest* forest);
  /* Forget the trees and fields (e.g. after regridding); the root grid stays. */
  int canopy_forest_clear(canopy_forest* forest);
  /* One tree: breadth-first refinement bytes (nonzero = refined), optional mask and
   * node -> storage slot map (NULL when absent). */
  int canopy_forest_add_tree(canopy_forest* forest, int64_t root_index, const uint8_t* refinement,
                             size_t number_of_nodes, const uint8_t* masked,
                             const int64_t* storage_slots);
  /* A field with tuples packed (tuple_stride_bytes = 0) or tuple_stride_bytes apart. */
  int canopy_forest_add_field(canopy_forest* forest, const char* name, int value_type,
                              int components, const void* data, size_t tuple_stride_bytes,
                              size_t number_of_tuples, int centering);
  /* A field with one array per component (structure of arrays). */
  int canopy_forest_add_field_soa(canopy_forest* forest, const char* name, int value_type,
                                  int components, const void* const* component_data,
                                  size_t number_of_tuples, int centering);

  /* ---- the in-situ calls (collective over the communicator) ------------- */
  int canopy_open(MPI_Comm communicator, const canopy_options* options, canopy_insitu** insitu);
  /* Fortran: the communicator as an integer handle (MPI_COMM_WORLD from mpi_f08%MPI_VAL). */
  int canopy_open_f(MPI_Fint communicator, const canopy_options* options, canopy_insitu** insitu);
  /* *will_execute = 1 when some pipeline runs at this step (skip preparing data otherwise). */
  int canopy_will_execute(canopy_insitu* insitu, int64_t step, double time, int* will_execute);
  int canopy_execute(canopy_insitu* insitu, int64_t step, double time, const canopy_forest* forest);
  /* Finalizes and frees; *insitu becomes NULL. */
  int canopy_close(canopy_insitu** insitu);

#ifdef __cplusplus
}
#endif

#endif /* CANOPY_H */
