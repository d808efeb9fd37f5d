/* Canopy's C API without MPI (compiled as C99 -pedantic): every function refuses
 * bad arguments with CANOPY_INVALID_ARGUMENT and a message naming the function and
 * the argument, constructors return a status and NULL on failure, and a real
 * allocation failure (address space limited with setrlimit in a forked child, the
 * heap exhausted) comes back as CANOPY_OUT_OF_MEMORY instead of an exception
 * crossing into C (which would abort the child).
 * The block forest calls (canopy_forest_set_blocks and after) likewise, and
 * canopy_block_strides_packed's strides for both orders, byte for byte.
 * Usage: canopy_c_api_argument_test */
#define _POSIX_C_SOURCE 200809L

#include <canopy/canopy.h>

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

static int failures = 0;

static void check(int condition, const char* what)
{
  if (condition)
  {
    printf("ok: %s\n", what);
  }
  else
  {
    printf("FAILED: %s (last error: '%s')\n", what, canopy_last_error());
    ++failures;
  }
}

/* A call refused with CANOPY_INVALID_ARGUMENT and a message containing `words`. */
static void refused(int status, const char* words, const char* what)
{
  char label[512];
  snprintf(label, sizeof label, "%s -> INVALID_ARGUMENT, '%s'", what, words);
  check(status == CANOPY_INVALID_ARGUMENT && strstr(canopy_last_error(), words) != NULL, label);
}

static const double x[3] = {0.0, 1.0, 2.0};
static const double y[2] = {0.0, 1.0};
static const double z[1] = {0.0};
static const uint8_t refined[5] = {1, 0, 0, 0, 0};
static const uint8_t none_absent[5] = {0, 0, 0, 0, 0};
static double density[5] = {0.5, 1.0, 2.0, 3.0, 4.0};

static void arguments(void)
{
  const size_t negative = (size_t)-1; /* what a negative Fortran c_size_t becomes */
  canopy_options* options = NULL;
  canopy_forest* forest = NULL;

  /* ---- options ---- */
  refused(canopy_options_create(NULL), "canopy_options_create: the result pointer is NULL",
          "options_create(NULL)");
  check(canopy_options_create(&options) == CANOPY_OK && options != NULL, "options_create");
  check(strcmp(canopy_last_error(), "") == 0, "a successful call clears the message");
  refused(canopy_options_add_script(NULL, "a.py"),
          "canopy_options_add_script: the options handle is NULL", "add_script(NULL options)");
  refused(canopy_options_add_script(options, NULL),
          "canopy_options_add_script: the script path is NULL", "add_script(NULL path)");
  refused(canopy_options_add_script(options, ""),
          "canopy_options_add_script: the script path is empty", "add_script(\"\")");
  refused(canopy_options_add_script_argument(options, "--x=1"),
          "canopy_options_add_script_argument: add a script first", "argument before a script");
  check(canopy_options_add_script(options, "a.py") == CANOPY_OK, "add_script");
  refused(canopy_options_add_script_argument(NULL, "--x=1"),
          "canopy_options_add_script_argument: the options handle is NULL",
          "add_script_argument(NULL options)");
  refused(canopy_options_add_script_argument(options, NULL),
          "canopy_options_add_script_argument: the argument is NULL",
          "add_script_argument(NULL argument)");
  check(canopy_options_add_script_argument(options, "") == CANOPY_OK, "an empty argument is fine");
  refused(canopy_options_set_output_directory(NULL, "out"),
          "canopy_options_set_output_directory: the options handle is NULL",
          "set_output_directory(NULL options)");
  refused(canopy_options_set_output_directory(options, NULL),
          "canopy_options_set_output_directory: the output directory is NULL",
          "set_output_directory(NULL)");
  refused(canopy_options_set_output_directory(options, ""),
          "canopy_options_set_output_directory: the output directory is empty",
          "set_output_directory(\"\")");
  refused(canopy_options_set_channel(NULL, "grid"),
          "canopy_options_set_channel: the options handle is NULL", "set_channel(NULL options)");
  refused(canopy_options_set_channel(options, NULL),
          "canopy_options_set_channel: the channel is NULL", "set_channel(NULL)");
  refused(canopy_options_set_channel(options, ""),
          "canopy_options_set_channel: the channel is empty", "set_channel(\"\")");
  refused(canopy_options_set_verbosity(NULL, 0),
          "canopy_options_set_verbosity: the options handle is NULL", "set_verbosity(NULL)");
  refused(canopy_options_set_step_summary(NULL, 1),
          "canopy_options_set_step_summary: the options handle is NULL", "set_step_summary(NULL)");

  /* ---- the in-situ calls: refused before anything collective ---- */
  {
    canopy_insitu* insitu = (canopy_insitu*)&failures; /* must be reset to NULL */
    refused(canopy_open(MPI_COMM_NULL, options, &insitu),
            "canopy_open: the communicator is MPI_COMM_NULL", "open(MPI_COMM_NULL)");
    check(insitu == NULL, "a refused open sets the handle to NULL");
    refused(canopy_open(MPI_COMM_WORLD, NULL, &insitu), "canopy_open: the options handle is NULL",
            "open(NULL options)");
    refused(canopy_open(MPI_COMM_WORLD, options, NULL), "canopy_open: the result pointer is NULL",
            "open(NULL result)");
    refused(canopy_will_execute(NULL, 0, 0.0, NULL),
            "canopy_will_execute: the insitu handle is NULL", "will_execute(NULL)");
    refused(canopy_execute(NULL, 0, 0.0, NULL), "canopy_execute: the insitu handle is NULL",
            "execute(NULL)");
    refused(canopy_close(NULL), "canopy_close: the pointer to the handle is NULL", "close(NULL)");
    insitu = NULL;
    refused(canopy_close(&insitu), "canopy_close: the handle is NULL", "close(&NULL)");
  }

  /* ---- forest ---- */
  forest = (canopy_forest*)&failures; /* must be reset to NULL */
  refused(canopy_forest_create(4, 2, 8, x, 3, y, 2, z, 1, &forest),
          "canopy_forest_create: dimension must be 1, 2 or 3, got 4", "forest_create(dimension 4)");
  check(forest == NULL, "a refused forest_create sets the handle to NULL");
  refused(canopy_forest_create(2, 5, 8, x, 3, y, 2, z, 1, &forest),
          "canopy_forest_create: branch_factor must be 2 or 3, got 5", "forest_create(branch 5)");
  refused(canopy_forest_create(2, 2, -1, x, 3, y, 2, z, 1, &forest),
          "canopy_forest_create: max_levels must be in [1, 62], got -1",
          "forest_create(max_levels -1)");
  refused(canopy_forest_create(2, 2, 63, x, 3, y, 2, z, 1, &forest),
          "max_levels must be in [1, 62], got 63", "forest_create(max_levels 63)");
  refused(canopy_forest_create(2, 3, 40, x, 3, y, 2, z, 1, &forest),
          "max_levels must be in [1, 39], got 40", "forest_create(ternary, max_levels 40)");
  refused(canopy_forest_create(2, 2, 8, NULL, 3, y, 2, z, 1, &forest),
          "canopy_forest_create: x is NULL but points_x is 3", "forest_create(NULL x)");
  refused(canopy_forest_create(2, 2, 8, x, 3, y, 0, z, 1, &forest),
          "canopy_forest_create: points_y is 0", "forest_create(0 points on y)");
  refused(canopy_forest_create(2, 2, 8, x, 3, y, 2, z, negative, &forest),
          "canopy_forest_create: points_z 18446744073709551615 is negative or too large",
          "forest_create(negative points_z)");
  refused(canopy_forest_create(2, 2, 8, x, 3, y, 2, z, 1, NULL),
          "canopy_forest_create: the result pointer is NULL", "forest_create(NULL result)");
  check(canopy_forest_create(2, 2, 8, x, 3, y, 2, z, 1, &forest) == CANOPY_OK && forest != NULL,
        "forest_create");
  {
    /* A 1D forest: a line of roots along y (one point on x and z). */
    canopy_forest* line = NULL;
    refused(canopy_forest_create(0, 2, 8, z, 1, x, 3, z, 1, &line),
            "canopy_forest_create: dimension must be 1, 2 or 3, got 0",
            "forest_create(dimension 0)");
    check(canopy_forest_create(1, 3, 8, z, 1, x, 3, z, 1, &line) == CANOPY_OK && line != NULL,
          "forest_create(dimension 1)");
    canopy_forest_destroy(line);
  }

  refused(canopy_forest_clear(NULL), "canopy_forest_clear: the forest handle is NULL",
          "forest_clear(NULL)");
  refused(canopy_forest_add_tree(NULL, 0, refined, 5, NULL, NULL),
          "canopy_forest_add_tree: the forest handle is NULL", "add_tree(NULL forest)");
  refused(canopy_forest_add_tree(forest, -1, refined, 5, NULL, NULL),
          "canopy_forest_add_tree: root_index -1 is negative", "add_tree(root -1)");
  refused(canopy_forest_add_tree(forest, 0, NULL, 5, NULL, NULL),
          "canopy_forest_add_tree: root 0: refinement is NULL", "add_tree(NULL refinement)");
  refused(canopy_forest_add_tree(forest, 0, refined, 0, NULL, NULL),
          "canopy_forest_add_tree: root 0: number_of_nodes is 0", "add_tree(0 nodes)");
  refused(canopy_forest_add_tree(forest, 0, refined, negative, NULL, NULL),
          "canopy_forest_add_tree: root 0: number_of_nodes 18446744073709551615 is negative",
          "add_tree(negative nodes)");

  /* The partial tree takes the same checks, under its own name; NULL absent is fine. */
  refused(canopy_forest_add_partial_tree(NULL, 0, refined, 5, NULL, NULL, none_absent),
          "canopy_forest_add_partial_tree: the forest handle is NULL",
          "add_partial_tree(NULL forest)");
  refused(canopy_forest_add_partial_tree(forest, -3, refined, 5, NULL, NULL, none_absent),
          "canopy_forest_add_partial_tree: root_index -3 is negative", "add_partial_tree(root -3)");
  refused(canopy_forest_add_partial_tree(forest, 0, NULL, 5, NULL, NULL, none_absent),
          "canopy_forest_add_partial_tree: root 0: refinement is NULL",
          "add_partial_tree(NULL refinement)");
  refused(canopy_forest_add_partial_tree(forest, 0, refined, 0, NULL, NULL, none_absent),
          "canopy_forest_add_partial_tree: root 0: number_of_nodes is 0",
          "add_partial_tree(0 nodes)");
  refused(canopy_forest_add_partial_tree(forest, 0, refined, negative, NULL, NULL, NULL),
          "canopy_forest_add_partial_tree: root 0: number_of_nodes 18446744073709551615 is "
          "negative",
          "add_partial_tree(negative nodes)");
  check(canopy_forest_add_partial_tree(forest, 0, refined, 5, NULL, NULL, NULL) == CANOPY_OK,
        "add_partial_tree with NULL absent");
  check(canopy_forest_add_partial_tree(forest, 1, refined, 5, NULL, NULL, none_absent) == CANOPY_OK,
        "add_partial_tree with an absent array");

  refused(
      canopy_forest_add_field(NULL, "density", CANOPY_FLOAT64, 1, density, 0, 5, CANOPY_EVERY_NODE),
      "canopy_forest_add_field: the forest handle is NULL", "add_field(NULL forest)");
  refused(
      canopy_forest_add_field(forest, NULL, CANOPY_FLOAT64, 1, density, 0, 5, CANOPY_EVERY_NODE),
      "canopy_forest_add_field: the field name is NULL", "add_field(NULL name)");
  refused(canopy_forest_add_field(forest, "", CANOPY_FLOAT64, 1, density, 0, 5, CANOPY_EVERY_NODE),
          "canopy_forest_add_field: the field name is empty", "add_field(\"\")");
  refused(canopy_forest_add_field(forest, "density", 42, 1, density, 0, 5, CANOPY_EVERY_NODE),
          "canopy_forest_add_field: field 'density': unknown value type 42",
          "add_field(value type 42)");
  refused(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, density, 0, 5, -1),
          "canopy_forest_add_field: field 'density': unknown centering -1",
          "add_field(centering -1)");
  refused(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 0, density, 0, 5,
                                  CANOPY_EVERY_NODE),
          "field 'density': components must be at least 1, got 0", "add_field(0 components)");
  refused(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, -2, density, 0, 5,
                                  CANOPY_EVERY_NODE),
          "field 'density': components must be at least 1, got -2", "add_field(-2 components)");
  refused(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, density, 0, negative,
                                  CANOPY_EVERY_NODE),
          "field 'density': number_of_tuples 18446744073709551615 is negative",
          "add_field(negative tuples)");
  refused(
      canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, NULL, 0, 5, CANOPY_EVERY_NODE),
      "field 'density': data is NULL but number_of_tuples is 5", "add_field(NULL data)");
  check(canopy_forest_add_field(forest, "empty", CANOPY_FLOAT64, 1, NULL, 0, 0,
                                CANOPY_EVERY_NODE) == CANOPY_OK,
        "NULL data with 0 tuples is fine (a rank without trees)");
  refused(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 2, density, 12, 2,
                                  CANOPY_EVERY_NODE),
          "field 'density': tuple_stride_bytes 12 is smaller than one tuple (16 bytes)",
          "add_field(stride below a tuple)");
  refused(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, density, 12, 2,
                                  CANOPY_EVERY_NODE),
          "field 'density': tuple_stride_bytes 12 is not a multiple of the value size 8",
          "add_field(misaligned stride)");
  {
    const void* components[2] = {density, NULL};
    refused(
        canopy_forest_add_field_soa(NULL, "v", CANOPY_FLOAT64, 2, components, 5, CANOPY_EVERY_NODE),
        "canopy_forest_add_field_soa: the forest handle is NULL", "add_field_soa(NULL forest)");
    refused(canopy_forest_add_field_soa(forest, NULL, CANOPY_FLOAT64, 2, components, 5,
                                        CANOPY_EVERY_NODE),
            "canopy_forest_add_field_soa: the field name is NULL", "add_field_soa(NULL name)");
    refused(canopy_forest_add_field_soa(forest, "v", CANOPY_INT64 + 1, 2, components, 5,
                                        CANOPY_EVERY_NODE),
            "canopy_forest_add_field_soa: field 'v': unknown value type 4",
            "add_field_soa(value type 4)");
    refused(canopy_forest_add_field_soa(forest, "v", CANOPY_FLOAT64, 2, components, 5, 7),
            "canopy_forest_add_field_soa: field 'v': unknown centering 7",
            "add_field_soa(centering 7)");
    refused(canopy_forest_add_field_soa(forest, "v", CANOPY_FLOAT64, -1, components, 5,
                                        CANOPY_EVERY_NODE),
            "field 'v': components must be at least 1, got -1", "add_field_soa(-1 components)");
    refused(canopy_forest_add_field_soa(forest, "v", CANOPY_FLOAT64, 2, NULL, 5, CANOPY_EVERY_NODE),
            "canopy_forest_add_field_soa: field 'v': component_data is NULL",
            "add_field_soa(NULL component_data)");
    refused(canopy_forest_add_field_soa(forest, "v", CANOPY_FLOAT64, 2, components, 5,
                                        CANOPY_EVERY_NODE),
            "field 'v': component 1's data is NULL but number_of_tuples is 5",
            "add_field_soa(NULL component 1)");
    components[1] = density;
    check(canopy_forest_add_field_soa(forest, "v", CANOPY_FLOAT64, 2, components, 5,
                                      CANOPY_LEAVES_ONLY) == CANOPY_OK,
          "add_field_soa");
  }
  check(canopy_forest_clear(forest) == CANOPY_OK, "forest_clear");
  canopy_forest_destroy(forest);
  canopy_forest_destroy(NULL); /* like free(NULL) */
  canopy_options_destroy(options);
  canopy_options_destroy(NULL);
}

/* ---- block forests ---- */

static const double z2[2] = {0.0, 1.0};
static const int64_t block_order[5] = {-1, 3, 2, 1, 0};
static double blocks_data[4][64];

/* Whether `s` holds exactly these strides. */
static int strides_are(const canopy_block_strides* s, size_t i, size_t j, size_t k,
                       size_t component, int gi, int gj, int gk)
{
  return s->cell_bytes[0] == i && s->cell_bytes[1] == j && s->cell_bytes[2] == k &&
         s->component_bytes == component && s->ghost_cells[0] == gi && s->ghost_cells[1] == gj &&
         s->ghost_cells[2] == gk;
}

static void block_arguments(void)
{
  const size_t negative = (size_t)-1;
  canopy_forest* forest = NULL;
  canopy_forest* plain = NULL;
  canopy_forest* ternary = NULL;
  canopy_block_strides strides;
  canopy_block_strides kept;
  canopy_block_strides s2d; /* 2D, 4 cells across, no ghosts: [j][i] */
  size_t bytes = 0;
  const void* addresses[4] = {blocks_data[0], blocks_data[1], blocks_data[2], blocks_data[3]};
  const void* holes[4] = {blocks_data[0], NULL, blocks_data[2], blocks_data[3]};
  const void* misaligned[4] = {(const char*)blocks_data[0] + 4, blocks_data[1], blocks_data[2],
                               blocks_data[3]};
  /* components: [component][block], component 1 of block 0 missing */
  const void* component_holes[4] = {blocks_data[0], blocks_data[1], NULL, blocks_data[3]};

  /* ---- canopy_block_strides_packed: the two orders, exactly ---- */
  check(canopy_block_strides_packed(3, 4, 2, 3, CANOPY_FLOAT64, CANOPY_VARIABLE_INNERMOST, &strides,
                                    &bytes) == CANOPY_OK &&
            strides_are(&strides, 24, 192, 1536, 8, 2, 2, 2) && bytes == 12288,
        "strides_packed: [k][j][i][3] doubles, 4 + 2 x 2 per side");
  check(canopy_block_strides_packed(3, 4, 2, 3, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST, &strides,
                                    &bytes) == CANOPY_OK &&
            strides_are(&strides, 8, 64, 512, 4096, 2, 2, 2) && bytes == 12288,
        "strides_packed: [3][k][j][i] doubles");
  check(canopy_block_strides_packed(2, 8, 1, 2, CANOPY_FLOAT32, CANOPY_VARIABLE_OUTERMOST, &strides,
                                    &bytes) == CANOPY_OK &&
            strides_are(&strides, 4, 40, 0, 400, 1, 1, 0) && bytes == 800,
        "strides_packed: 2D [2][j][i] floats, 8 + 2 x 1 per side");
  check(canopy_block_strides_packed(1, 2, 0, 1, CANOPY_FLOAT64, CANOPY_VARIABLE_INNERMOST, &strides,
                                    NULL) == CANOPY_OK &&
            strides_are(&strides, 8, 0, 0, 8, 0, 0, 0),
        "strides_packed: 1D, no ghosts, block_bytes NULL");
  kept = strides;
  refused(canopy_block_strides_packed(0, 4, 2, 1, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST,
                                      &strides, &bytes),
          "canopy_block_strides_packed: dimension must be 1, 2 or 3, got 0",
          "strides_packed(dimension 0)");
  refused(canopy_block_strides_packed(3, 0, 2, 1, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST,
                                      &strides, &bytes),
          "canopy_block_strides_packed: cells_per_side must be at least 1, got 0",
          "strides_packed(0 cells)");
  refused(canopy_block_strides_packed(3, 4, -1, 1, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST,
                                      &strides, &bytes),
          "canopy_block_strides_packed: ghost_cells -1 is negative", "strides_packed(ghosts -1)");
  refused(canopy_block_strides_packed(3, 4, 2, 0, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST,
                                      &strides, &bytes),
          "canopy_block_strides_packed: components must be at least 1, got 0",
          "strides_packed(0 components)");
  refused(canopy_block_strides_packed(3, 4, 2, 1, 9, CANOPY_VARIABLE_OUTERMOST, &strides, &bytes),
          "canopy_block_strides_packed: unknown value type 9", "strides_packed(value type 9)");
  refused(canopy_block_strides_packed(3, 4, 2, 1, CANOPY_FLOAT64, 2, &strides, &bytes),
          "canopy_block_strides_packed: unknown order 2", "strides_packed(order 2)");
  refused(canopy_block_strides_packed(3, 4, 2, 1, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST, NULL,
                                      &bytes),
          "canopy_block_strides_packed: strides is NULL", "strides_packed(NULL strides)");
  refused(canopy_block_strides_packed(3, 2000000000, 2000000000, 1000, CANOPY_FLOAT64,
                                      CANOPY_VARIABLE_INNERMOST, &strides, &bytes),
          "is too large to address", "strides_packed(a block beyond the address space)");
  check(memcmp(&strides, &kept, sizeof strides) == 0 && bytes == 800,
        "refused strides_packed calls leave strides and block_bytes unchanged");
  canopy_block_strides_packed(2, 4, 0, 1, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST, &s2d, NULL);

  /* ---- canopy_forest_set_blocks ---- */
  canopy_forest_create(2, 2, 4, x, 3, y, 2, z, 1, &forest);
  canopy_forest_create(2, 2, 4, x, 3, y, 2, z, 1, &plain);
  canopy_forest_create(3, 3, 4, x, 3, y, 2, z2, 2, &ternary);
  refused(canopy_forest_set_blocks(NULL, 4), "canopy_forest_set_blocks: the forest handle is NULL",
          "set_blocks(NULL forest)");
  refused(canopy_forest_set_blocks(forest, 12),
          "canopy_forest_set_blocks: cells_per_side must be 0 (no blocks) or a power of the branch "
          "factor 2 (2, 4, 8, 16, ...), got 12",
          "set_blocks(12)");
  refused(canopy_forest_set_blocks(forest, -4),
          "a power of the branch factor 2 (2, 4, 8, 16, ...), "
          "got -4",
          "set_blocks(-4)");
  refused(canopy_forest_set_blocks(forest, 1), "got 1", "set_blocks(1): no level inside a block");
  refused(canopy_forest_set_blocks(ternary, 4),
          "a power of the branch factor 3 (3, 9, 27, 81, ...), got 4", "set_blocks(ternary, 4)");
  check(canopy_forest_set_blocks(ternary, 27) == CANOPY_OK, "set_blocks(ternary, 27)");
  refused(canopy_forest_set_blocks(forest, 16),
          "canopy_forest_set_blocks: blocks of 16 cells across add 4 levels below each block's "
          "root, more than the max_levels 4 of canopy_forest_create allows",
          "set_blocks(16) with max_levels 4");
  check(canopy_forest_set_blocks(forest, 8) == CANOPY_OK, "set_blocks(8) with max_levels 4");
  check(canopy_forest_set_blocks(forest, 0) == CANOPY_OK, "set_blocks(0): no blocks again");
  check(canopy_forest_set_blocks(forest, 4) == CANOPY_OK, "set_blocks(4)");

  /* ---- trees ---- */
  refused(canopy_forest_add_block_tree(NULL, 0, refined, 5, NULL, NULL, block_order),
          "canopy_forest_add_block_tree: the forest handle is NULL", "add_block_tree(NULL forest)");
  refused(canopy_forest_add_block_tree(plain, 0, refined, 5, NULL, NULL, block_order),
          "canopy_forest_add_block_tree: root 0: the forest has no blocks (call "
          "canopy_forest_set_blocks first)",
          "add_block_tree(a forest without blocks)");
  refused(canopy_forest_add_block_tree(forest, -2, refined, 5, NULL, NULL, block_order),
          "canopy_forest_add_block_tree: root_index -2 is negative", "add_block_tree(root -2)");
  refused(canopy_forest_add_block_tree(forest, 0, NULL, 5, NULL, NULL, block_order),
          "canopy_forest_add_block_tree: root 0: refinement is NULL",
          "add_block_tree(NULL refinement)");
  refused(canopy_forest_add_block_tree(forest, 0, refined, 0, NULL, NULL, block_order),
          "canopy_forest_add_block_tree: root 0: number_of_nodes is 0", "add_block_tree(0 nodes)");
  refused(canopy_forest_add_block_tree(forest, 0, refined, negative, NULL, NULL, block_order),
          "canopy_forest_add_block_tree: root 0: number_of_nodes 18446744073709551615 is negative",
          "add_block_tree(negative nodes)");
  refused(canopy_forest_add_tree(forest, 0, refined, 5, NULL, block_order),
          "canopy_forest_add_tree: root 0: storage_slots must be NULL in a block forest",
          "add_tree(storage slots) in a block forest");
  refused(canopy_forest_add_partial_tree(forest, 0, refined, 5, NULL, block_order, none_absent),
          "canopy_forest_add_partial_tree: root 0: storage_slots must be NULL in a block forest",
          "add_partial_tree(storage slots) in a block forest");
  check(canopy_forest_add_block_tree(forest, 0, refined, 5, NULL, none_absent, block_order) ==
            CANOPY_OK,
        "add_block_tree");
  check(canopy_forest_add_block_tree(forest, 1, refined, 5, NULL, NULL, NULL) == CANOPY_OK,
        "add_block_tree without block_index");
  check(canopy_forest_add_tree(forest, 2, refined, 5, NULL, NULL) == CANOPY_OK,
        "add_tree in a block forest");
  refused(canopy_forest_set_blocks(forest, 8),
          "canopy_forest_set_blocks: the forest already has 3 trees and 0 fields",
          "set_blocks on a forest with trees");

  /* ---- fields ---- */
  refused(
      canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, density, 0, 5,
                              CANOPY_LEAVES_ONLY),
      "canopy_forest_add_field: field 'density': the forest has blocks (canopy_forest_set_blocks)",
      "add_field in a block forest");
  {
    const void* components[1] = {density};
    refused(canopy_forest_add_field_soa(forest, "density", CANOPY_FLOAT64, 1, components, 5,
                                        CANOPY_LEAVES_ONLY),
            "canopy_forest_add_field_soa: field 'density': the forest has blocks",
            "add_field_soa in a block forest");
  }
  refused(canopy_forest_add_block_field(NULL, "rho", CANOPY_FLOAT64, 1, addresses, 4, &s2d),
          "canopy_forest_add_block_field: the forest handle is NULL",
          "add_block_field(NULL forest)");
  refused(canopy_forest_add_block_field(forest, NULL, CANOPY_FLOAT64, 1, addresses, 4, &s2d),
          "canopy_forest_add_block_field: the field name is NULL", "add_block_field(NULL name)");
  refused(canopy_forest_add_block_field(forest, "", CANOPY_FLOAT64, 1, addresses, 4, &s2d),
          "canopy_forest_add_block_field: the field name is empty", "add_block_field(\"\")");
  refused(canopy_forest_add_block_field(forest, "rho", 42, 1, addresses, 4, &s2d),
          "canopy_forest_add_block_field: field 'rho': unknown value type 42",
          "add_block_field(value type 42)");
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_INT64, 1, addresses, 4, &s2d),
          "canopy_forest_add_block_field: field 'rho': a block field is CANOPY_FLOAT32 or "
          "CANOPY_FLOAT64 (its coarse cells are volume averages), got value type 3",
          "add_block_field(int64)");
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 0, addresses, 4, &s2d),
          "field 'rho': components must be at least 1, got 0", "add_block_field(0 components)");
  refused(
      canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, addresses, negative, &s2d),
      "canopy_forest_add_block_field: field 'rho': number_of_blocks 18446744073709551615 is "
      "negative or too large",
      "add_block_field(negative blocks)");
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, addresses, 4, NULL),
          "canopy_forest_add_block_field: field 'rho': strides is NULL",
          "add_block_field(NULL strides)");
  strides = s2d;
  strides.cell_bytes[1] = 0;
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, addresses, 4, &strides),
          "field 'rho': strides->cell_bytes[1] 0 is not a nonzero multiple of the value size 8",
          "add_block_field(cell_bytes[1] 0)");
  strides = s2d;
  strides.cell_bytes[0] = 12;
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, addresses, 4, &strides),
          "field 'rho': strides->cell_bytes[0] 12 is not a nonzero multiple of the value size 8",
          "add_block_field(cell_bytes[0] 12)");
  strides = s2d;
  strides.cell_bytes[0] = (size_t)-8;
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, addresses, 4, &strides),
          "strides->cell_bytes[0] 18446744073709551608 is not a nonzero multiple of the value "
          "size 8 (or is negative)",
          "add_block_field(negative cell_bytes[0])");
  strides = s2d;
  strides.ghost_cells[1] = -1;
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, addresses, 4, &strides),
          "canopy_forest_add_block_field: field 'rho': strides->ghost_cells[1] -1 is negative",
          "add_block_field(ghost_cells[1] -1)");
  strides = s2d;
  strides.component_bytes = 0;
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 2, addresses, 4, &strides),
          "field 'rho': strides->component_bytes 0 is not a nonzero multiple of the value size 8 "
          "(or is negative), with 2 components",
          "add_block_field(2 components, component_bytes 0)");
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, NULL, 4, &s2d),
          "canopy_forest_add_block_field: field 'rho': block_addresses is NULL but "
          "number_of_blocks is 4",
          "add_block_field(NULL block_addresses)");
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, holes, 4, &s2d),
          "canopy_forest_add_block_field: field 'rho': block_addresses[1] (block 1) is NULL",
          "add_block_field(block 1 NULL)");
  refused(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, misaligned, 4, &s2d),
          "field 'rho': block_addresses[0] (block 0) is not aligned to the value size",
          "add_block_field(block 0 misaligned)");
  refused(canopy_forest_add_block_field(plain, "rho", CANOPY_FLOAT64, 1, addresses, 4, &s2d),
          "canopy_forest_add_block_field: field 'rho': the forest has no blocks (call "
          "canopy_forest_set_blocks first)",
          "add_block_field(a forest without blocks)");
  strides = s2d;
  strides.cell_bytes[2] = 3; /* a flat axis: ignored */
  strides.ghost_cells[2] = -5;
  strides.component_bytes = 0; /* one component: unused */
  check(canopy_forest_add_block_field(forest, "rho", CANOPY_FLOAT64, 1, addresses, 4, &strides) ==
            CANOPY_OK,
        "add_block_field (the flat axis' strides ignored)");
  check(canopy_forest_add_block_field(forest, "none", CANOPY_FLOAT32, 1, NULL, 0, &s2d) ==
            CANOPY_OK,
        "add_block_field: NULL block_addresses with 0 blocks (a rank without trees)");

  refused(
      canopy_forest_add_block_field_array(NULL, "u", CANOPY_FLOAT64, 1, blocks_data, 512, 4, &s2d),
      "canopy_forest_add_block_field_array: the forest handle is NULL",
      "add_block_field_array(NULL forest)");
  refused(
      canopy_forest_add_block_field_array(forest, "u", CANOPY_INT32, 1, blocks_data, 512, 4, &s2d),
      "canopy_forest_add_block_field_array: field 'u': a block field is CANOPY_FLOAT32 or "
      "CANOPY_FLOAT64",
      "add_block_field_array(int32)");
  refused(canopy_forest_add_block_field_array(forest, "u", CANOPY_FLOAT64, 1, NULL, 512, 4, &s2d),
          "canopy_forest_add_block_field_array: field 'u': first_block is NULL but "
          "number_of_blocks is 4",
          "add_block_field_array(NULL first_block)");
  refused(canopy_forest_add_block_field_array(forest, "u", CANOPY_FLOAT64, 1,
                                              (const char*)blocks_data + 2, 512, 4, &s2d),
          "canopy_forest_add_block_field_array: field 'u': first_block is not aligned to the "
          "value size 8",
          "add_block_field_array(misaligned first_block)");
  refused(
      canopy_forest_add_block_field_array(forest, "u", CANOPY_FLOAT64, 1, blocks_data, 0, 4, &s2d),
      "canopy_forest_add_block_field_array: field 'u': block_stride_bytes 0 is not a nonzero "
      "multiple of the value size 8 (or is negative), with 4 blocks",
      "add_block_field_array(block stride 0)");
  refused(canopy_forest_add_block_field_array(forest, "u", CANOPY_FLOAT64, 1, blocks_data, 516, 4,
                                              &s2d),
          "field 'u': block_stride_bytes 516 is not a nonzero multiple of the value size 8",
          "add_block_field_array(block stride 516)");
  refused(canopy_forest_add_block_field_array(forest, "u", CANOPY_FLOAT64, 1, blocks_data, negative,
                                              4, &s2d),
          "field 'u': block_stride_bytes 18446744073709551615 is not a nonzero multiple",
          "add_block_field_array(negative block stride)");
  refused(canopy_forest_add_block_field_array(forest, "u", CANOPY_FLOAT64, 1, blocks_data, 512,
                                              negative, &s2d),
          "canopy_forest_add_block_field_array: field 'u': number_of_blocks 18446744073709551615 "
          "is negative",
          "add_block_field_array(negative blocks)");
  check(canopy_forest_add_block_field_array(forest, "u", CANOPY_FLOAT64, 1, blocks_data, 512, 4,
                                            &s2d) == CANOPY_OK,
        "add_block_field_array");
  check(canopy_forest_add_block_field_array(forest, "u1", CANOPY_FLOAT64, 1, blocks_data, 0, 1,
                                            &s2d) == CANOPY_OK,
        "add_block_field_array: any block stride with 1 block");
  check(canopy_forest_add_block_field_array(forest, "u0", CANOPY_FLOAT64, 1, NULL, 0, 0, &s2d) ==
            CANOPY_OK,
        "add_block_field_array: NULL first_block with 0 blocks");

  refused(
      canopy_forest_add_block_field_components(NULL, "b", CANOPY_FLOAT64, 2, addresses, 2, &s2d),
      "canopy_forest_add_block_field_components: the forest handle is NULL",
      "add_block_field_components(NULL forest)");
  refused(
      canopy_forest_add_block_field_components(forest, "b", CANOPY_FLOAT64, -1, addresses, 2, &s2d),
      "canopy_forest_add_block_field_components: field 'b': components must be at least 1, "
      "got -1",
      "add_block_field_components(-1 components)");
  refused(canopy_forest_add_block_field_components(forest, "b", CANOPY_FLOAT64, 2, NULL, 2, &s2d),
          "canopy_forest_add_block_field_components: field 'b': block_addresses is NULL but "
          "number_of_blocks is 2",
          "add_block_field_components(NULL block_addresses)");
  refused(canopy_forest_add_block_field_components(forest, "b", CANOPY_FLOAT64, 2, component_holes,
                                                   2, &s2d),
          "canopy_forest_add_block_field_components: field 'b': block_addresses[2] (component 1, "
          "block 0) is NULL",
          "add_block_field_components(component 1 of block 0 NULL)");
  refused(canopy_forest_add_block_field_components(forest, "b", CANOPY_FLOAT64, 3, addresses,
                                                   (size_t)(PTRDIFF_MAX / 2), &s2d),
          "canopy_forest_add_block_field_components: field 'b': 3 components x "
          "4611686018427387903 blocks are too many addresses",
          "add_block_field_components(too many addresses)");
  strides = s2d;
  strides.ghost_cells[0] = -3;
  refused(canopy_forest_add_block_field_components(forest, "b", CANOPY_FLOAT64, 2, addresses, 2,
                                                   &strides),
          "field 'b': strides->ghost_cells[0] -3 is negative",
          "add_block_field_components(ghost_cells[0] -3)");
  refused(
      canopy_forest_add_block_field_components(plain, "b", CANOPY_FLOAT64, 2, addresses, 2, &s2d),
      "canopy_forest_add_block_field_components: field 'b': the forest has no blocks",
      "add_block_field_components(a forest without blocks)");
  strides = s2d;
  strides.component_bytes = 0; /* unused: the components are separate arrays */
  check(canopy_forest_add_block_field_components(forest, "b", CANOPY_FLOAT64, 2, addresses, 2,
                                                 &strides) == CANOPY_OK,
        "add_block_field_components (component_bytes unused)");
  check(canopy_forest_add_block_field_components(forest, "b0", CANOPY_FLOAT32, 3, NULL, 0, &s2d) ==
            CANOPY_OK,
        "add_block_field_components: NULL block_addresses with 0 blocks");

  /* clear keeps the block size; set_blocks(0) makes an ordinary forest again. */
  check(canopy_forest_clear(forest) == CANOPY_OK, "clear the block forest");
  refused(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, density, 0, 5,
                                  CANOPY_EVERY_NODE),
          "the forest has blocks", "clear keeps the blocks: add_field still refused");
  check(canopy_forest_add_block_tree(forest, 0, refined, 5, NULL, NULL, NULL) == CANOPY_OK,
        "and add_block_tree still taken");
  check(canopy_forest_clear(forest) == CANOPY_OK &&
            canopy_forest_set_blocks(forest, 0) == CANOPY_OK,
        "set_blocks(0) after clear");
  check(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, density, 0, 5,
                                CANOPY_EVERY_NODE) == CANOPY_OK,
        "an ordinary forest again: add_field taken");
  canopy_forest_destroy(forest);
  canopy_forest_destroy(plain);
  canopy_forest_destroy(ternary);
}

/* ---- out of memory ---- */

enum oom_case
{
  OOM_OPTIONS_CREATE,
  OOM_ADD_SCRIPT,          /* string copy and vector growth */
  OOM_ADD_SCRIPT_ARGUMENT, /* string copy into a vector */
  OOM_SET_OUTPUT_DIRECTORY,
  OOM_SET_CHANNEL,
  OOM_FOREST_CREATE,
  OOM_ADD_TREE, /* vector growth: the forest holds 4 trees, capacity 4 */
  OOM_ADD_PARTIAL_TREE,
  OOM_ADD_FIELD_LONG_NAME, /* string copy */
  OOM_ADD_FIELD,           /* vector growth: the forest holds 4 fields */
  OOM_ADD_FIELD_SOA,
  OOM_LONG_MESSAGE,    /* a refusal whose message cannot be stored whole: kept truncated */
  OOM_ADD_BLOCK_TREE,  /* vector growth: the block forest holds 4 trees */
  OOM_ADD_BLOCK_FIELD, /* the copy of the address table */
  OOM_ADD_BLOCK_FIELD_LONG_NAME,  /* string copy */
  OOM_ADD_BLOCK_FIELD_ARRAY,      /* vector growth: the block forest holds 4 fields and tables */
  OOM_ADD_BLOCK_FIELD_COMPONENTS, /* the copy of the address tables */
  OOM_CASES
};

static const char* const oom_functions[OOM_CASES] = {"canopy_options_create",
                                                     "canopy_options_add_script",
                                                     "canopy_options_add_script_argument",
                                                     "canopy_options_set_output_directory",
                                                     "canopy_options_set_channel",
                                                     "canopy_forest_create",
                                                     "canopy_forest_add_tree",
                                                     "canopy_forest_add_partial_tree",
                                                     "canopy_forest_add_field",
                                                     "canopy_forest_add_field",
                                                     "canopy_forest_add_field_soa",
                                                     "canopy_forest_add_field",
                                                     "canopy_forest_add_block_tree",
                                                     "canopy_forest_add_block_field",
                                                     "canopy_forest_add_block_field",
                                                     "canopy_forest_add_block_field_array",
                                                     "canopy_forest_add_block_field_components"};

static char long_text[4096];

static int oom_call(int which, canopy_options* options, canopy_forest* forest,
                    canopy_forest* block_forest, canopy_options** new_options,
                    canopy_forest** new_forest)
{
  const void* components[2] = {density, density};
  const void* addresses[4] = {blocks_data[0], blocks_data[1], blocks_data[2], blocks_data[3]};
  canopy_block_strides strides;
  canopy_block_strides_packed(2, 4, 0, 2, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST, &strides,
                              NULL);
  switch (which)
  {
  case OOM_OPTIONS_CREATE:
    return canopy_options_create(new_options);
  case OOM_ADD_SCRIPT:
    return canopy_options_add_script(options, long_text);
  case OOM_ADD_SCRIPT_ARGUMENT:
    return canopy_options_add_script_argument(options, long_text);
  case OOM_SET_OUTPUT_DIRECTORY:
    return canopy_options_set_output_directory(options, long_text);
  case OOM_SET_CHANNEL:
    return canopy_options_set_channel(options, long_text);
  case OOM_FOREST_CREATE:
    return canopy_forest_create(2, 2, 8, x, 3, y, 2, z, 1, new_forest);
  case OOM_ADD_TREE:
    return canopy_forest_add_tree(forest, 0, refined, 5, NULL, NULL);
  case OOM_ADD_PARTIAL_TREE:
    return canopy_forest_add_partial_tree(forest, 0, refined, 5, NULL, NULL, none_absent);
  case OOM_ADD_FIELD_LONG_NAME:
    return canopy_forest_add_field(forest, long_text, CANOPY_FLOAT64, 1, density, 0, 5,
                                   CANOPY_EVERY_NODE);
  case OOM_ADD_FIELD:
    return canopy_forest_add_field(forest, "d", CANOPY_FLOAT64, 1, density, 0, 5,
                                   CANOPY_EVERY_NODE);
  case OOM_ADD_FIELD_SOA:
    return canopy_forest_add_field_soa(forest, "v", CANOPY_FLOAT64, 2, components, 5,
                                       CANOPY_EVERY_NODE);
  case OOM_ADD_BLOCK_TREE:
    return canopy_forest_add_block_tree(block_forest, 9, refined, 5, NULL, NULL, NULL);
  case OOM_ADD_BLOCK_FIELD:
    return canopy_forest_add_block_field(block_forest, "b", CANOPY_FLOAT64, 1, addresses, 4,
                                         &strides);
  case OOM_ADD_BLOCK_FIELD_LONG_NAME:
    return canopy_forest_add_block_field(block_forest, long_text, CANOPY_FLOAT64, 1, addresses, 4,
                                         &strides);
  case OOM_ADD_BLOCK_FIELD_ARRAY:
    return canopy_forest_add_block_field_array(block_forest, "a", CANOPY_FLOAT64, 2, blocks_data,
                                               sizeof blocks_data[0], 4, &strides);
  case OOM_ADD_BLOCK_FIELD_COMPONENTS:
    return canopy_forest_add_block_field_components(block_forest, "c", CANOPY_FLOAT64, 2, addresses,
                                                    2, &strides);
  default:
    return canopy_forest_add_field(forest, long_text, 42, 1, density, 0, 5, CANOPY_EVERY_NODE);
  }
}

/* Limits the address space to what is mapped now plus a little, then takes every
 * byte malloc can still give. Returns the list of blocks (each starts with the
 * address of the next). */
static void* exhaust_memory(void)
{
  long pages = 0;
  FILE* statm = fopen("/proc/self/statm", "r");
  if (statm == NULL || fscanf(statm, "%ld", &pages) != 1)
  {
    return NULL;
  }
  fclose(statm);
  struct rlimit limit;
  getrlimit(RLIMIT_AS, &limit);
  limit.rlim_cur = (rlim_t)pages * (rlim_t)sysconf(_SC_PAGESIZE) + ((rlim_t)16 << 20);
  if (setrlimit(RLIMIT_AS, &limit) != 0)
  {
    return NULL;
  }
  void* blocks = NULL;
  size_t size;
  for (size = (size_t)1 << 26; size >= sizeof(void*); size /= 2)
  {
    void* block;
    while ((block = malloc(size)) != NULL)
    {
      *(void**)block = blocks;
      blocks = block;
    }
  }
  /* glibc keeps small freed chunks in per-size lists (tcache, fast and small
   * bins) that serve only their own size: empty every one of them. */
  for (size = 24; size <= 1032; size += 16)
  {
    void* block;
    while ((block = malloc(size)) != NULL)
    {
      *(void**)block = blocks;
      blocks = block;
    }
  }
  return blocks;
}

static void release_memory(void* blocks)
{
  struct rlimit limit;
  while (blocks != NULL)
  {
    void* next = *(void**)blocks;
    free(blocks);
    blocks = next;
  }
  getrlimit(RLIMIT_AS, &limit);
  limit.rlim_cur = limit.rlim_max;
  setrlimit(RLIMIT_AS, &limit);
}

/* In the child: prepares the objects, makes the call with the heap exhausted,
 * then (memory back) checks status, message and that the objects still work.
 * Exit code: 0 when all is as expected. */
static int oom_child(int which)
{
  canopy_options* options = NULL;
  canopy_forest* forest = NULL;
  canopy_forest* block_forest = NULL;
  canopy_options* new_options = (canopy_options*)&failures; /* must become NULL */
  canopy_forest* new_forest = (canopy_forest*)&failures;
  char message[512];
  int status;
  int bad = 0;
  int i;
  void* blocks;
  if (canopy_options_create(&options) != CANOPY_OK ||
      canopy_options_add_script(options, "a.py") != CANOPY_OK ||
      canopy_forest_create(2, 2, 8, x, 3, y, 2, z, 1, &forest) != CANOPY_OK ||
      canopy_forest_create(2, 2, 8, x, 3, y, 2, z, 1, &block_forest) != CANOPY_OK ||
      canopy_forest_set_blocks(block_forest, 4) != CANOPY_OK)
  {
    printf("FAILED: setup: %s\n", canopy_last_error());
    return 1;
  }
  for (i = 1; i <= 4; ++i) /* capacity 4, full: the next one must grow the vectors */
  {
    char name[16]; /* room for any int: gcc -O1 (the sanitizer build) warns otherwise */
    const void* addresses[4] = {blocks_data[0], blocks_data[1], blocks_data[2], blocks_data[3]};
    canopy_block_strides strides;
    canopy_block_strides_packed(2, 4, 0, 1, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST, &strides,
                                NULL);
    snprintf(name, sizeof name, "f%d", i);
    canopy_forest_add_tree(forest, i, refined, 5, NULL, NULL);
    canopy_forest_add_field(forest, name, CANOPY_FLOAT64, 1, density, 0, 5, CANOPY_EVERY_NODE);
    canopy_forest_add_block_tree(block_forest, i, refined, 5, NULL, NULL, NULL);
    if (canopy_forest_add_block_field(block_forest, name, CANOPY_FLOAT64, 1, addresses, 4,
                                      &strides) != CANOPY_OK)
    {
      printf("FAILED: setup: %s\n", canopy_last_error());
      return 1;
    }
  }
  fflush(stdout);
  blocks = exhaust_memory();
  if (blocks == NULL)
  {
    printf("FAILED: could not limit and exhaust the address space\n");
    return 1;
  }
  status = oom_call(which, options, forest, block_forest, &new_options, &new_forest);
  strncpy(message, canopy_last_error(), sizeof message - 1); /* no allocation */
  message[sizeof message - 1] = '\0';
  release_memory(blocks);

  printf("  %s with the heap exhausted: status %d, '%.100s'\n", oom_functions[which], status,
         message);
  if (which == OOM_LONG_MESSAGE)
  {
    bad += status != CANOPY_INVALID_ARGUMENT;
    bad += strncmp(message, "canopy_forest_add_field: field 'aaaa", 36) != 0;
  }
  else
  {
    bad += status != CANOPY_OUT_OF_MEMORY;
    bad +=
        strstr(message, oom_functions[which]) == NULL || strstr(message, "out of memory") == NULL;
  }
  if (which == OOM_OPTIONS_CREATE)
  {
    bad += new_options != NULL;
  }
  if (which == OOM_FOREST_CREATE)
  {
    bad += new_forest != NULL;
  }
  /* With memory back, the same call works: the failed one left the objects usable. */
  new_options = NULL;
  new_forest = NULL;
  status = oom_call(which, options, forest, block_forest, &new_options, &new_forest);
  if (which == OOM_LONG_MESSAGE)
  {
    /* Now the whole message fits. */
    bad += status != CANOPY_INVALID_ARGUMENT ||
           strstr(canopy_last_error(), "unknown value type 42") == NULL;
  }
  else if (status != CANOPY_OK)
  {
    printf("  and afterwards: status %d, '%s'\n", status, canopy_last_error());
    ++bad;
  }
  canopy_options_destroy(new_options);
  canopy_forest_destroy(new_forest);
  canopy_forest_destroy(forest);
  canopy_forest_destroy(block_forest);
  canopy_options_destroy(options);
  return bad == 0 ? 0 : 1;
}

static void out_of_memory(void)
{
  int which;
  memset(long_text, 'a', sizeof long_text - 1); /* beyond any short-string buffer */
  for (which = 0; which < OOM_CASES; ++which)
  {
    char label[256];
    int wstatus = 0;
    pid_t child;
    fflush(stdout);
    child = fork();
    if (child == 0)
    {
      const int code = oom_child(which);
      fflush(stdout);
      _exit(code);
    }
    snprintf(label, sizeof label,
             which == OOM_LONG_MESSAGE
                 ? "%s (case %d) refused with the heap exhausted: INVALID_ARGUMENT, message "
                   "truncated, whole afterwards"
                 : "%s (case %d) out of memory: CANOPY_OUT_OF_MEMORY, message, NULL result, "
                   "usable afterwards",
             oom_functions[which], which);
    if (child < 0 || waitpid(child, &wstatus, 0) != child)
    {
      check(0, "fork");
      continue;
    }
    if (WIFSIGNALED(wstatus))
    {
      printf("  the child died of signal %d: an exception crossed the C API?\n", WTERMSIG(wstatus));
    }
    check(WIFEXITED(wstatus) && WEXITSTATUS(wstatus) == 0, label);
  }
}

int main(void)
{
  arguments();
  block_arguments();
  out_of_memory();
  printf("%d failures\n", failures);
  return failures == 0 ? 0 : 1;
}
