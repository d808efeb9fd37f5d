/* Canopy's C API from a C program (compiled as C99 -pedantic): a 2x1 forest whose
 * first root is refined once, a value-range selection pipeline every second step,
 * bad arguments, a malformed tree. Checks return codes, messages, the
 * extract's cell count (read from the written piece), that refused calls leave
 * the forest unchanged, that canopy_forest_add_partial_tree with a NULL absent
 * array writes the same extract as canopy_forest_add_tree, and that the
 * simulation's arrays are unchanged. (Every argument check and out-of-memory:
 * c_api_argument_test.c.)
 * Usage: canopy_c_api_test SELECTION_SCRIPT OUTPUT_DIR */
#include <canopy/canopy.h>

#include <mpi.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static int failures = 0;

#define CHECK(condition, message)                                                                  \
  do                                                                                               \
  {                                                                                                \
    if (!(condition))                                                                              \
    {                                                                                              \
      fprintf(stderr, "FAILED: %s (%s:%d): %s\n", message, __FILE__, __LINE__,                     \
              canopy_last_error());                                                                \
      ++failures;                                                                                  \
    }                                                                                              \
    else                                                                                           \
    {                                                                                              \
      printf("ok: %s\n", message);                                                                 \
    }                                                                                              \
  } while (0)

/* This rank's piece of selection_<step>.pvtu into text (NUL-terminated); 0 if absent. */
static int read_piece(const char* directory, int step, int rank, char* text, size_t size)
{
  char path[4096];
  snprintf(path, sizeof path, "%s/selection_%06d/selection_%06d_%d.vtu", directory, step, step,
           rank);
  FILE* file = fopen(path, "r");
  if (!file)
  {
    return 0;
  }
  size_t length = fread(text, 1, size - 1, file);
  fclose(file);
  text[length] = '\0';
  return 1;
}

/* NumberOfCells of a rank's piece of selection_<step>.pvtu, -1 if absent. */
static long selected_cells(const char* directory, int step, int rank)
{
  static char text[65536];
  if (!read_piece(directory, step, rank, text, sizeof text))
  {
    return -1;
  }
  const char* found = strstr(text, "NumberOfCells=\"");
  return found ? strtol(found + strlen("NumberOfCells=\""), NULL, 10) : -1;
}

/* Whether this rank's pieces of two steps hold the same cells, fields and points
 * (everything from <Piece on; only the TimeValue before it differs). */
static int same_piece(const char* directory, int step_a, int step_b, int rank)
{
  static char a[65536];
  static char b[65536];
  if (!read_piece(directory, step_a, rank, a, sizeof a) ||
      !read_piece(directory, step_b, rank, b, sizeof b))
  {
    return 0;
  }
  const char* piece_a = strstr(a, "<Piece");
  const char* piece_b = strstr(b, "<Piece");
  return piece_a != NULL && piece_b != NULL && strcmp(piece_a, piece_b) == 0;
}

static double checksum(const double* values, size_t count)
{
  double sum = 0.0;
  for (size_t i = 0; i < count; ++i)
  {
    sum += values[i] * (double)(i + 1);
  }
  return sum;
}

/* This rank's trees and field, as at every step; partial: through
 * canopy_forest_add_partial_tree with a NULL absent array. */
static void describe(canopy_forest* forest, int owns_root0, int owns_root1, int partial,
                     const unsigned char* refined, const unsigned char* leaf, const double* data,
                     size_t nodes)
{
  canopy_forest_clear(forest);
  if (owns_root0)
  {
    CHECK((partial ? canopy_forest_add_partial_tree(forest, 0, refined, 5, NULL, NULL, NULL)
                   : canopy_forest_add_tree(forest, 0, refined, 5, NULL, NULL)) == CANOPY_OK,
          "root 0 added");
  }
  if (owns_root1)
  {
    CHECK((partial ? canopy_forest_add_partial_tree(forest, 1, leaf, 1, NULL, NULL, NULL)
                   : canopy_forest_add_tree(forest, 1, leaf, 1, NULL, NULL)) == CANOPY_OK,
          "root 1 added");
  }
  CHECK(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, nodes ? data : NULL, 0, nodes,
                                CANOPY_EVERY_NODE) == CANOPY_OK,
        "field added");
  /* Refused calls add nothing: the step must still be valid (no bad tree, no
   * second 'density'). */
  CHECK(canopy_forest_add_tree(forest, -1, refined, 5, NULL, NULL) == CANOPY_INVALID_ARGUMENT,
        "a negative root index refused");
  CHECK(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, data, 0, nodes, 9) ==
            CANOPY_INVALID_ARGUMENT,
        "an unknown centering refused");
}

int main(int argc, char** argv)
{
  if (argc != 3)
  {
    fprintf(stderr, "usage: canopy_c_api_test SELECTION_SCRIPT OUTPUT_DIR\n");
    return 2;
  }
  MPI_Init(&argc, &argv);
  int rank = 0;
  int size = 1;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);

  /* The simulation's arrays: a 2x1 root grid, root 0 refined into 4 leaves;
   * rank r owns the roots with index % size == r (with more than 2 ranks,
   * some own nothing). Nodes stored breadth-first, trees back to back. */
  const double x[3] = {0.0, 1.0, 2.0};
  const double y[2] = {0.0, 1.0};
  const double z[1] = {0.0};
  const unsigned char refined[5] = {1, 0, 0, 0, 0};
  const unsigned char leaf[1] = {0};
  double density[6] = {0.5, 1.0, 2.0, 3.0, 4.0, /* root 0: coarse value, 4 leaves */
                       2.5};                    /* root 1 */
  const int owns_root0 = rank == 0;
  const int owns_root1 = rank == 1 % size;
  const double* my_density = owns_root0 ? density : density + 5;
  const size_t my_nodes = (owns_root0 ? 5 : 0) + (owns_root1 ? 1 : 0);
  const double before = checksum(density, 6);

  /* Bad arguments are refused with a message, nothing done. */
  CHECK(canopy_options_add_script(NULL, "x.py") == CANOPY_INVALID_ARGUMENT, "NULL options refused");
  CHECK(strstr(canopy_last_error(), "the options handle is NULL") != NULL,
        "and the message says so");
  canopy_options* options = NULL;
  CHECK(canopy_options_create(&options) == CANOPY_OK && options != NULL, "options created");
  CHECK(canopy_options_add_script_argument(options, "--x=1") == CANOPY_INVALID_ARGUMENT,
        "an argument before any script refused");
  CHECK(canopy_options_add_script(options, argv[1]) == CANOPY_OK, "script added");
  canopy_options_add_script_argument(options, "--selection=range");
  canopy_options_add_script_argument(options, "--value-field=density");
  canopy_options_add_script_argument(options, "--value-range=1.5,3.5");
  canopy_options_add_script_argument(options, "--frequency=2");
  CHECK(canopy_options_set_output_directory(options, argv[2]) == CANOPY_OK, "output directory");
  CHECK(canopy_options_set_channel(options, "") == CANOPY_INVALID_ARGUMENT,
        "an empty channel refused");
  CHECK(canopy_options_set_step_time_limit(options, -1.0) == CANOPY_INVALID_ARGUMENT,
        "a negative time limit refused");
  CHECK(canopy_options_set_step_time_limit(options, 120.0) == CANOPY_OK, "a time limit");
  CHECK(canopy_options_add_query(options, "") == CANOPY_INVALID_ARGUMENT, "an empty query refused");
  CHECK(canopy_options_add_query(options, "max(density)") == CANOPY_OK, "a query");
  CHECK(canopy_options_add_query(options, "volume(density, 1.5, 3.5) * 2") == CANOPY_OK,
        "an expression");
  CHECK(canopy_options_add_field_name(options, "density") == CANOPY_OK, "a field name");

  canopy_insitu* insitu = NULL;
  CHECK(canopy_open(MPI_COMM_NULL, options, &insitu) == CANOPY_INVALID_ARGUMENT && insitu == NULL,
        "MPI_COMM_NULL refused before anything collective");
  CHECK(canopy_open_f(MPI_Comm_c2f(MPI_COMM_NULL), options, &insitu) == CANOPY_INVALID_ARGUMENT,
        "and as a Fortran handle");
  CHECK(canopy_open(MPI_COMM_WORLD, options, &insitu) == CANOPY_OK && insitu != NULL, "open");
  canopy_options_destroy(options);

  canopy_forest* forest = NULL;
  CHECK(canopy_forest_create(2, 2, 8, x, 3, y, 2, z, 1, &forest) == CANOPY_OK && forest != NULL,
        "forest created");
  CHECK(canopy_forest_add_field(forest, "density", 42, 1, density, 0, 5, CANOPY_EVERY_NODE) ==
            CANOPY_INVALID_ARGUMENT,
        "an unknown value type refused");
  CHECK(strstr(canopy_last_error(), "unknown value type 42") != NULL, "and named");

  /* Steps 0-3 with canopy_forest_add_tree, 4-5 with canopy_forest_add_partial_tree
   * and a NULL absent array: the script runs at steps 0, 2 and 4. */
  for (int step = 0; step < 6; ++step)
  {
    describe(forest, owns_root0, owns_root1, step >= 4, refined, leaf, my_density, my_nodes);
    int will = -1;
    if (step < 3)
      CHECK(canopy_will_execute(insitu, step, 0.5 * step, &will) == CANOPY_OK, "will_execute");
    else /* with the forest: the queries run there, execute reuses them */
      CHECK(canopy_will_execute_forest(insitu, step, 0.5 * step, forest, &will) == CANOPY_OK,
            "will_execute_forest");
    /* Step 0 imports the script; then every second step. */
    CHECK(will == (step % 2 == 0), "will_execute says whether the pipeline runs");
    CHECK(canopy_execute(insitu, step, 0.5 * step, forest) == CANOPY_OK, "execute");
  }
  /* The queries of step 5, on every rank: leaves only (the coarse 0.5 is not one). */
  double value = 0.0;
  CHECK(canopy_query_value(insitu, "max(density)", &value) == CANOPY_OK && value == 4.0,
        "max(density) is the largest leaf");
  /* Leaves 2.0 and 3.0 (a quarter of root 0 each) and 2.5 (root 1) in [1.5, 3.5]. */
  CHECK(canopy_query_value(insitu, "volume(density, 1.5, 3.5) * 2", &value) == CANOPY_OK &&
            value == 3.0,
        "an expression's value");
  CHECK(canopy_query_value(insitu, "volume(density, 1.5, 3.5)", &value) == CANOPY_OK &&
            value == 1.5,
        "and its query's, by its text");
  CHECK(canopy_query_value(insitu, "min(density)", &value) == CANOPY_INVALID_ARGUMENT &&
            value != value,
        "an expression not asked for is refused (NaN)");
  /* Leaves 2.0, 3.0 and 2.5 are in [1.5, 3.5]; the coarse 0.5 and leaves 1.0, 4.0 are not. */
  long total = 0;
  for (int r = 0; r < size; ++r)
  {
    long cells = selected_cells(argv[2], 2, r);
    total += cells > 0 ? cells : 0;
  }
  if (rank == 0)
  {
    CHECK(total == 3, "3 cells selected at step 2 over all ranks");
    CHECK(selected_cells(argv[2], 1, 0) == -1, "nothing written at step 1");
  }
  CHECK(same_piece(argv[2], 2, 4, rank),
        "a partial tree without absent nodes writes the same piece as a whole tree");

  /* A malformed tree on rank 0: every rank skips the step, the call says why. */
  canopy_forest_clear(forest);
  if (owns_root0)
  {
    canopy_forest_add_tree(forest, 0, refined, 3, NULL, NULL); /* 3 of its 5 nodes */
  }
  if (owns_root1)
  {
    canopy_forest_add_tree(forest, 1, leaf, 1, NULL, NULL);
  }
  canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, my_nodes ? my_density : NULL, 0,
                          my_nodes, CANOPY_EVERY_NODE);
  CHECK(canopy_execute(insitu, 6, 3.0, forest) == CANOPY_STEP_FAILED, "a malformed tree fails");
  CHECK(strstr(canopy_last_error(), "rank 0, step 6: invalid forest") != NULL,
        "naming rank and step");
  CHECK(canopy_execute(NULL, 7, 3.5, forest) == CANOPY_INVALID_ARGUMENT, "NULL handle refused");
  /* A NULL forest on the last rank: every rank still takes part and skips the step. */
  const int status = canopy_execute(insitu, 8, 4.0, rank == size - 1 ? NULL : forest);
  CHECK(status == (rank == size - 1 ? CANOPY_INVALID_ARGUMENT : CANOPY_STEP_FAILED),
        "a NULL forest fails the step on every rank, without a hang");

  CHECK(checksum(density, 6) == before, "the simulation's arrays are unchanged");
  CHECK(canopy_close(&insitu) == CANOPY_OK && insitu == NULL, "close");
  /* ParaView 5.11's Catalyst cannot start twice in a process: a clear error. */
  canopy_options* again = NULL;
  canopy_options_create(&again);
  canopy_options_add_script(again, argv[1]);
  CHECK(canopy_open(MPI_COMM_WORLD, again, &insitu) == CANOPY_OPEN_FAILED && insitu == NULL,
        "a second open is refused");
  CHECK(strstr(canopy_last_error(), "cannot start it again") != NULL, "saying why");
  canopy_options_destroy(again);
  canopy_forest_destroy(forest);
  MPI_Finalize();
  return failures == 0 ? 0 : 1;
}
