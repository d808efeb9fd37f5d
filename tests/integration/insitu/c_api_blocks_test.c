/* A block forest through Canopy's C API (compiled as C99 -pedantic): a 3D forest of
 * 2x2x1 roots, root 0 refined once, every leaf a block of 4^3 cells with ghost
 * cells, and four block fields, one for each way blocks are given:
 *   density   doubles, blocks allocated one by one ([k][j][i], 2 ghosts),
 *             canopy_forest_add_block_field;
 *   momentum  3 doubles per cell, every block in one array ([block][k][j][i][var],
 *             FLASH's unk), canopy_forest_add_block_field_array;
 *   magnetic  2 floats, each component in per-block arrays of its own,
 *             canopy_forest_add_block_field_components;
 *   pressure  doubles, one array whose blocks are laid out [i][j][k] (i slowest)
 *             with ghosts 2, 1, 3 along x, y, z, padding after each k row and
 *             after each block: strides set by hand.
 * The selection pipeline selects every leaf (a value range on density) at every
 * step; each rank decodes its own piece of the extract (the cells' points and
 * every field's values) and checks each cell against the simulation's arrays,
 * found from the cell's position by this program's own indexing: every block
 * cell, every component, exactly, and no ghost value. Step 0 takes the blocks in
 * their default order (present leaves breadth-first, tree by tree), step 1 in the
 * reverse order (canopy_forest_add_block_tree's block_index), step 2 with values
 * changed after the fields were added (borrowed arrays are read at each step).
 * Then two malformed block forests fail their steps with the core's message, and
 * refused calls leave the forest as it was. (Every argument check of the block
 * calls: c_api_argument_test.c.)
 * Usage: canopy_c_api_blocks_test SELECTION_SCRIPT OUTPUT_DIR */
#include <canopy/canopy.h>

#include <math.h>
#include <mpi.h>
#include <stdint.h>
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

enum
{
  N = 4,             /* cells per block side */
  G = 2,             /* ghost cells of density, momentum and magnetic */
  E = N + 2 * G,     /* their block arrays' extent per axis */
  CELLS = E * E * E, /* values per component of such a block */
  MAX_BLOCKS = 11,   /* 8 children of root 0, roots 1, 2 and 3 */
  ROOTS = 4,
  PX = N + 2 * 2,           /* pressure: ghosts 2 along x, */
  PY = N + 2 * 1,           /* 1 along y, */
  PZ = N + 2 * 3 + 1,       /* 3 along z, one value of padding after each k row */
  PBLOCK = PX * PY * PZ + 3 /* and 3 values after each block */
};

static const double x[3] = {0.0, 1.0, 2.5}; /* not uniform */
static const double y[3] = {0.0, 1.0, 2.0};
static const double z[2] = {-1.0, 0.0};
static const uint8_t refined[9] = {1, 0, 0, 0, 0, 0, 0, 0, 0};
static const uint8_t leaf[1] = {0};

/* This rank's blocks and arrays. Tables are indexed by the block's entry: its
 * index in the fields' block tables. */
static int owned[ROOTS];
static int blocks = 0;
static int first_block_of_root[ROOTS]; /* default order: its first block's entry */
static double* density[MAX_BLOCKS];
static double* momentum = NULL; /* [block][k][j][i][3] */
static float* magnetic[2][MAX_BLOCKS];
static double* pressure = NULL; /* [block][i][j][k], PBLOCK values per block */
static int64_t reversed_index[ROOTS][9];

static double density_at(int e, int i, int j, int k)
{
  return density[e][((k + G) * E + (j + G)) * E + (i + G)];
}
static double momentum_at(int e, int i, int j, int k, int c)
{
  return momentum[((((size_t)e * E + (k + G)) * E + (j + G)) * E + (i + G)) * 3 + c];
}
static float magnetic_at(int e, int i, int j, int k, int c)
{
  return magnetic[c][e][((k + G) * E + (j + G)) * E + (i + G)];
}
static double pressure_at(int e, int i, int j, int k)
{
  return pressure[(size_t)e * PBLOCK + ((i + 2) * PY + (j + 1)) * PZ + (k + 3)];
}

/* Fills every array: interior cells with a value naming field, entry, cell and
 * component; ghost cells (and padding) with -1e6 - field, which no check expects. */
static void fill(int rank)
{
  int e;
  int v;
  momentum = malloc(sizeof(double) * (size_t)(blocks > 0 ? blocks : 1) * CELLS * 3);
  pressure = malloc(sizeof(double) * (size_t)(blocks > 0 ? blocks : 1) * PBLOCK);
  for (v = 0; v < (blocks > 0 ? blocks : 1) * CELLS * 3; ++v)
  {
    momentum[v] = -1e6 - 2;
  }
  for (v = 0; v < (blocks > 0 ? blocks : 1) * PBLOCK; ++v)
  {
    pressure[v] = -1e6 - 4;
  }
  for (e = 0; e < blocks; ++e)
  {
    int c;
    int i;
    int j;
    int k;
    density[e] = malloc(sizeof(double) * CELLS);
    magnetic[0][e] = malloc(sizeof(float) * CELLS);
    magnetic[1][e] = malloc(sizeof(float) * CELLS);
    for (v = 0; v < CELLS; ++v)
    {
      density[e][v] = -1e6 - 1;
      magnetic[0][e][v] = magnetic[1][e][v] = (float)(-1e6 - 3);
    }
    for (k = 0; k < N; ++k)
    {
      for (j = 0; j < N; ++j)
      {
        for (i = 0; i < N; ++i)
        {
          const double code = 1 + i + 10 * j + 100 * k + 1000 * (e + 1) + 100000 * rank;
          const int at = ((k + G) * E + (j + G)) * E + (i + G);
          density[e][at] = code;
          for (c = 0; c < 3; ++c)
          {
            momentum[((((size_t)e * E + (k + G)) * E + (j + G)) * E + (i + G)) * 3 + c] =
                code + 0.25 * (c + 1);
          }
          magnetic[0][e][at] = (float)(-code - 0.125);
          magnetic[1][e][at] = (float)(-code - 0.375);
          pressure[(size_t)e * PBLOCK + ((i + 2) * PY + (j + 1)) * PZ + (k + 3)] = 0.5 * code;
        }
      }
    }
  }
}

/* ---- the extract: this rank's piece, decoded ---- */

static char* read_file(const char* path)
{
  FILE* file = fopen(path, "rb");
  long size;
  char* text;
  if (file == NULL)
  {
    return NULL;
  }
  fseek(file, 0, SEEK_END);
  size = ftell(file);
  fseek(file, 0, SEEK_SET);
  text = malloc((size_t)size + 1);
  if (fread(text, 1, (size_t)size, file) != (size_t)size)
  {
    size = 0;
  }
  text[size] = '\0';
  fclose(file);
  return text;
}

static int base64_value(char c)
{
  const char* alphabet = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  const char* found = c != '\0' ? strchr(alphabet, c) : NULL;
  return found ? (int)(found - alphabet) : -1;
}

/* The values of the DataArray named `name` (inline binary: base64 of a UInt64 byte
 * count and the values) as doubles; *count values, NULL when missing. */
static double* decode_array(const char* text, const char* name, size_t* count)
{
  char pattern[128];
  const char* array;
  const char* type;
  const char* p;
  unsigned char* bytes;
  size_t length = 0;
  size_t capacity;
  uint64_t payload;
  double* values;
  size_t value_size;
  size_t i;
  unsigned int bits = 0;
  int held = 0;
  *count = 0;
  snprintf(pattern, sizeof pattern, "Name=\"%s\"", name);
  array = strstr(text, pattern);
  if (array == NULL)
  {
    return NULL;
  }
  while (array > text && strncmp(array, "<DataArray", 10) != 0)
  {
    --array;
  }
  type = strstr(array, "type=\"");
  p = strchr(array, '>');
  if (type == NULL || p == NULL)
  {
    return NULL;
  }
  type += 6;
  value_size = strncmp(type, "Float32", 7) == 0 ? 4 : 8;
  capacity = strlen(p) * 3 / 4 + 8;
  bytes = malloc(capacity);
  for (++p; *p != '\0' && *p != '<'; ++p)
  {
    const int v = base64_value(*p);
    if (v < 0)
    {
      continue; /* white space, padding */
    }
    bits = (bits << 6) | (unsigned int)v;
    held += 6;
    if (held >= 8)
    {
      held -= 8;
      bytes[length++] = (unsigned char)((bits >> held) & 0xFF);
    }
  }
  if (length < 8)
  {
    free(bytes);
    return NULL;
  }
  memcpy(&payload, bytes, 8);
  if (payload > length - 8)
  {
    free(bytes);
    return NULL;
  }
  *count = (size_t)payload / value_size;
  values = malloc(sizeof(double) * (*count > 0 ? *count : 1));
  for (i = 0; i < *count; ++i)
  {
    const unsigned char* at = bytes + 8 + i * value_size;
    if (strncmp(type, "Float32", 7) == 0)
    {
      float f;
      memcpy(&f, at, 4);
      values[i] = f;
    }
    else if (strncmp(type, "Float64", 7) == 0)
    {
      memcpy(&values[i], at, 8);
    }
    else /* Int64 */
    {
      int64_t n;
      memcpy(&n, at, 8);
      values[i] = (double)n;
    }
  }
  free(bytes);
  return values;
}

/* Which block entry, node of its tree and cell a leaf cell of the grid is, from
 * its bounds; 0 when it is no block cell of this rank (or not the size of one). */
static int locate(const double* low, const double* high, int reverse, int* entry, int cell[3])
{
  const double* axes[3] = {x, y, z};
  int root[3];
  double u[3];
  int a;
  int node = 0;
  int root_index;
  int levels;
  for (a = 0; a < 3; ++a)
  {
    const double center = 0.5 * (low[a] + high[a]);
    root[a] = a < 2 && center > axes[a][1] ? 1 : 0;
    u[a] = (center - axes[a][root[a]]) / (axes[a][root[a] + 1] - axes[a][root[a]]);
  }
  root_index = root[0] + 2 * root[1];
  if (!owned[root_index])
  {
    return 0;
  }
  levels = root_index == 0 ? 2 : 1; /* root 0's blocks are its children */
  if (root_index == 0)
  {
    int child = 0;
    for (a = 0; a < 3; ++a)
    {
      const int half = u[a] >= 0.5;
      child += half << a;
      u[a] = 2.0 * u[a] - half;
    }
    node = 1 + child;
  }
  for (a = 0; a < 3; ++a)
  {
    const double width = (axes[a][root[a] + 1] - axes[a][root[a]]) / (levels * N);
    cell[a] = (int)floor(u[a] * N);
    if (fabs((high[a] - low[a]) - width) > 1e-12 || cell[a] < 0 || cell[a] >= N)
    {
      return 0;
    }
  }
  *entry = first_block_of_root[root_index] + (root_index == 0 ? node - 1 : 0);
  if (reverse)
  {
    *entry = blocks - 1 - *entry;
  }
  return 1;
}

/* Every cell of this rank's piece of step `step` against the arrays. */
static void check_piece(const char* directory, int step, int rank, int reverse)
{
  char path[4096];
  char label[256];
  char* text;
  size_t counts[7];
  double* points;
  double* connectivity;
  double* offsets;
  double* values[4];
  const char* names[4] = {"density", "momentum", "magnetic", "pressure"};
  const size_t components[4] = {1, 3, 2, 1};
  size_t cells;
  size_t c;
  int f;
  int bad_position = 0;
  int bad_value = 0;
  int seen[MAX_BLOCKS * N * N * N];
  int seen_twice = 0;
  memset(seen, 0, sizeof seen);
  snprintf(path, sizeof path, "%s/selection_%06d/selection_%06d_%d.vtu", directory, step, step,
           rank);
  text = read_file(path);
  snprintf(label, sizeof label, "step %d: rank %d's piece of the extract is written", step, rank);
  CHECK(text != NULL, label);
  if (text == NULL)
  {
    return;
  }
  points = decode_array(text, "Points", &counts[0]);
  connectivity = decode_array(text, "connectivity", &counts[1]);
  offsets = decode_array(text, "offsets", &counts[2]);
  for (f = 0; f < 4; ++f)
  {
    values[f] = decode_array(text, names[f], &counts[3 + f]);
  }
  cells = counts[2];
  snprintf(label, sizeof label, "step %d: %zu cells, every block cell of this rank's %d blocks",
           step, cells, blocks);
  CHECK(cells == (size_t)blocks * N * N * N && points && connectivity && offsets, label);
  for (f = 0; f < 4; ++f)
  {
    snprintf(label, sizeof label, "step %d: field %s has %zu values for %zu cells", step, names[f],
             counts[3 + f], cells);
    CHECK(values[f] != NULL && counts[3 + f] == cells * components[f], label);
  }
  if (!points || !connectivity || !offsets || !values[0] || !values[1] || !values[2] ||
      !values[3] || counts[3] != cells || counts[4] != 3 * cells || counts[5] != 2 * cells ||
      counts[6] != cells)
  {
    cells = 0; /* reported above */
  }
  for (c = 0; c < cells; ++c)
  {
    double low[3] = {1e300, 1e300, 1e300};
    double high[3] = {-1e300, -1e300, -1e300};
    size_t v;
    int a;
    int e = 0;
    int cell[3];
    for (v = c == 0 ? 0 : (size_t)offsets[c - 1]; v < (size_t)offsets[c]; ++v)
    {
      const size_t point = (size_t)connectivity[v];
      for (a = 0; a < 3; ++a)
      {
        low[a] = fmin(low[a], points[3 * point + (size_t)a]);
        high[a] = fmax(high[a], points[3 * point + (size_t)a]);
      }
    }
    if (!locate(low, high, reverse, &e, cell))
    {
      if (bad_position++ < 3)
      {
        fprintf(stderr, "  cell %zu at [%g %g] x [%g %g] x [%g %g] is no block cell of rank %d\n",
                c, low[0], high[0], low[1], high[1], low[2], high[2], rank);
      }
      continue;
    }
    seen_twice += seen[((e * N + cell[2]) * N + cell[1]) * N + cell[0]]++ > 0;
    {
      const int i = cell[0];
      const int j = cell[1];
      const int k = cell[2];
      const double expected[7] = {density_at(e, i, j, k),     momentum_at(e, i, j, k, 0),
                                  momentum_at(e, i, j, k, 1), momentum_at(e, i, j, k, 2),
                                  magnetic_at(e, i, j, k, 0), magnetic_at(e, i, j, k, 1),
                                  pressure_at(e, i, j, k)};
      const double got[7] = {values[0][c],         values[1][3 * c], values[1][3 * c + 1],
                             values[1][3 * c + 2], values[2][2 * c], values[2][2 * c + 1],
                             values[3][c]};
      for (v = 0; v < 7; ++v)
      {
        if (got[v] != expected[v] && bad_value++ < 5)
        {
          fprintf(stderr,
                  "  step %d rank %d: block %d cell (%d, %d, %d): value %zu is %.17g, the "
                  "array has %.17g\n",
                  step, rank, e, i, j, k, v, got[v], expected[v]);
        }
      }
    }
  }
  snprintf(label, sizeof label, "step %d: every cell is a block cell of this rank, once", step);
  CHECK(bad_position == 0 && seen_twice == 0, label);
  snprintf(label, sizeof label,
           "step %d: every value of every field is the array's (block order %s)", step,
           reverse ? "reversed" : "default");
  CHECK(bad_value == 0, label);
  free(points);
  free(connectivity);
  free(offsets);
  for (f = 0; f < 4; ++f)
  {
    free(values[f]);
  }
  free(text);
}

/* The trees and the four fields. reverse: through canopy_forest_add_block_tree with
 * the reversed block order. Refused calls in between must change nothing. */
static void describe(canopy_forest* forest, int reverse)
{
  int r;
  canopy_block_strides strides;
  canopy_block_strides pressure_strides;
  size_t block_bytes = 0;
  const void* magnetic_addresses[2 * MAX_BLOCKS];
  const void* density_addresses[MAX_BLOCKS];
  const size_t nb = (size_t)blocks;
  int e;
  CHECK(canopy_forest_clear(forest) == CANOPY_OK, "clear");
  for (r = 0; r < ROOTS; ++r)
  {
    if (!owned[r])
    {
      continue;
    }
    if (reverse)
    {
      CHECK(canopy_forest_add_block_tree(forest, r, r == 0 ? refined : leaf, r == 0 ? 9 : 1, NULL,
                                         NULL, reversed_index[r]) == CANOPY_OK,
            "a block tree with its block_index");
    }
    else
    {
      CHECK(canopy_forest_add_tree(forest, r, r == 0 ? refined : leaf, r == 0 ? 9 : 1, NULL,
                                   NULL) == CANOPY_OK,
            "a tree of the block forest");
    }
  }
  CHECK(canopy_forest_add_tree(forest, 3, leaf, 1, NULL, reversed_index[0]) ==
            CANOPY_INVALID_ARGUMENT,
        "storage slots in a block forest refused");
  for (e = 0; e < blocks; ++e)
  {
    density_addresses[e] = density[e];
    magnetic_addresses[e] = magnetic[0][e];
    magnetic_addresses[nb + (size_t)e] = magnetic[1][e];
  }

  CHECK(canopy_block_strides_packed(3, N, G, 1, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST, &strides,
                                    NULL) == CANOPY_OK,
        "strides of [k][j][i]");
  CHECK(canopy_forest_add_block_field(forest, "density", CANOPY_FLOAT64, 1,
                                      blocks ? density_addresses : NULL, nb, &strides) == CANOPY_OK,
        "density: blocks allocated one by one");
  CHECK(canopy_block_strides_packed(3, N, G, 3, CANOPY_FLOAT64, CANOPY_VARIABLE_INNERMOST, &strides,
                                    &block_bytes) == CANOPY_OK,
        "strides of [k][j][i][var]");
  CHECK(block_bytes == sizeof(double) * CELLS * 3, "and the block's bytes");
  CHECK(canopy_forest_add_block_field_array(forest, "momentum", CANOPY_FLOAT64, 3, momentum,
                                            block_bytes, nb, &strides) == CANOPY_OK,
        "momentum: every block in one array");
  CHECK(canopy_block_strides_packed(3, N, G, 1, CANOPY_FLOAT32, CANOPY_VARIABLE_OUTERMOST, &strides,
                                    NULL) == CANOPY_OK,
        "strides of one float component's [k][j][i]");
  CHECK(canopy_forest_add_block_field_components(forest, "magnetic", CANOPY_FLOAT32, 2,
                                                 blocks ? magnetic_addresses : NULL, nb,
                                                 &strides) == CANOPY_OK,
        "magnetic: each component in arrays of its own");
  /* [i][j][k], ghosts 2, 1, 3, a padded k row: strides by hand. */
  pressure_strides.cell_bytes[0] = sizeof(double) * PY * PZ;
  pressure_strides.cell_bytes[1] = sizeof(double) * PZ;
  pressure_strides.cell_bytes[2] = sizeof(double);
  pressure_strides.component_bytes = 0; /* one component: unused */
  pressure_strides.ghost_cells[0] = 2;
  pressure_strides.ghost_cells[1] = 1;
  pressure_strides.ghost_cells[2] = 3;
  CHECK(canopy_forest_add_block_field_array(forest, "pressure", CANOPY_FLOAT64, 1, pressure,
                                            sizeof(double) * PBLOCK, nb,
                                            &pressure_strides) == CANOPY_OK,
        "pressure: strides set by hand");

  /* Refused: nothing added (a second 'density' or a field without blocks would fail the step). */
  CHECK(canopy_forest_add_field(forest, "density", CANOPY_FLOAT64, 1, momentum, 0, 1,
                                CANOPY_LEAVES_ONLY) == CANOPY_INVALID_ARGUMENT,
        "a field of tuples refused in a block forest");
  CHECK(canopy_forest_add_block_field(forest, "density", CANOPY_FLOAT64, 1, NULL, 3, &strides) ==
            CANOPY_INVALID_ARGUMENT,
        "a NULL block table refused");
  CHECK(canopy_forest_add_block_field(forest, "density", CANOPY_INT32, 1, density_addresses, nb,
                                      &strides) == CANOPY_INVALID_ARGUMENT,
        "an integer block field refused");
  CHECK(canopy_forest_set_blocks(forest, 2) == CANOPY_INVALID_ARGUMENT &&
            strstr(canopy_last_error(), "already has") != NULL,
        "the block size of a forest with trees cannot change");
}

int main(int argc, char** argv)
{
  int rank = 0;
  int size = 1;
  int r;
  int step;
  canopy_options* options = NULL;
  canopy_insitu* insitu = NULL;
  canopy_forest* forest = NULL;
  if (argc != 3)
  {
    fprintf(stderr, "usage: canopy_c_api_blocks_test SELECTION_SCRIPT OUTPUT_DIR\n");
    return 2;
  }
  MPI_Init(&argc, &argv);
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);

  /* Rank r owns the roots whose index % size == r; blocks in the default order:
   * present leaves breadth-first, tree by tree (root 0's 8 children first). */
  for (r = 0; r < ROOTS; ++r)
  {
    owned[r] = r % size == rank;
    first_block_of_root[r] = blocks;
    if (owned[r])
    {
      blocks += r == 0 ? 8 : 1;
    }
  }
  for (r = 0; r < ROOTS; ++r)
  {
    int n;
    reversed_index[r][0] = r == 0 ? -1 : blocks - 1 - first_block_of_root[r];
    for (n = 1; n < 9; ++n)
    {
      reversed_index[r][n] = r == 0 ? blocks - 1 - (first_block_of_root[0] + n - 1) : -1;
    }
  }
  fill(rank);

  CHECK(canopy_options_create(&options) == CANOPY_OK, "options");
  CHECK(canopy_options_add_script(options, argv[1]) == CANOPY_OK, "script");
  canopy_options_add_script_argument(options, "--selection=range");
  canopy_options_add_script_argument(options, "--value-field=density");
  canopy_options_add_script_argument(options, "--value-range=0,1e9");
  canopy_options_set_output_directory(options, argv[2]);
  canopy_options_set_step_time_limit(options, 120.0);
  CHECK(canopy_open(MPI_COMM_WORLD, options, &insitu) == CANOPY_OK, "open");
  canopy_options_destroy(options);

  /* 2 levels of trees and 2 inside each block of 4 cells across: max_levels 4. */
  CHECK(canopy_forest_create(3, 2, 4, x, 3, y, 3, z, 2, &forest) == CANOPY_OK, "forest created");
  CHECK(canopy_forest_set_blocks(forest, 6) == CANOPY_INVALID_ARGUMENT &&
            strstr(canopy_last_error(), "power of the branch factor 2") != NULL,
        "6 cells per side refused: not a power of 2");
  CHECK(canopy_forest_set_blocks(forest, 16) == CANOPY_INVALID_ARGUMENT &&
            strstr(canopy_last_error(), "add 4 levels") != NULL &&
            strstr(canopy_last_error(), "max_levels 4") != NULL,
        "16 cells per side refused: 4 levels and the root's are more than max_levels 4");
  CHECK(canopy_forest_set_blocks(forest, N) == CANOPY_OK, "blocks of 4^3 cells");

  for (step = 0; step < 3; ++step)
  {
    describe(forest, step == 1);
    if (step == 2 && blocks > 0)
    {
      /* After the calls that borrowed them, before the step reads them. */
      density[0][((1 + G) * E + (2 + G)) * E + (3 + G)] = 0.5;
      momentum[((((size_t)(blocks - 1) * E + G) * E + G) * E + G) * 3 + 2] = -42.0;
      magnetic[1][blocks - 1][(G * E + G) * E + (1 + G)] = 7.75f;
      pressure[3 * PZ + 1] = 1e6; /* a ghost of block 0's pressure: never read */
    }
    CHECK(canopy_execute(insitu, step, 0.5 * step, forest) == CANOPY_OK, "execute");
    check_piece(argv[2], step, rank, step == 1);
  }

  /* Malformed block forests: every rank skips the step, the message says why. */
  describe(forest, 0);
  if (rank == 0)
  {
    const void* one[1] = {density[0]};
    canopy_block_strides strides;
    canopy_block_strides_packed(3, N, G, 1, CANOPY_FLOAT64, CANOPY_VARIABLE_OUTERMOST, &strides,
                                NULL);
    CHECK(canopy_forest_add_block_field(forest, "short", CANOPY_FLOAT64, 1, one, 1, &strides) ==
              CANOPY_OK,
          "a field of 1 block (the forest has more)");
  }
  CHECK(canopy_execute(insitu, 3, 1.5, forest) == CANOPY_STEP_FAILED, "too few blocks fail");
  CHECK(rank != 0 || strstr(canopy_last_error(), "1 blocks given but the forest has") != NULL,
        "saying how many blocks the field has");
  describe(forest, 1);
  if (rank == 0)
  {
    reversed_index[0][2] = reversed_index[0][1]; /* two leaves, one block */
  }
  CHECK(canopy_execute(insitu, 4, 2.0, forest) == CANOPY_STEP_FAILED,
        "a block_index that is no permutation fails");
  CHECK(rank != 0 || strstr(canopy_last_error(), "reuses blockIndex") != NULL,
        "naming the reused block");

  CHECK(canopy_close(&insitu) == CANOPY_OK, "close");
  canopy_forest_destroy(forest);
  for (r = 0; r < blocks; ++r)
  {
    free(density[r]);
    free(magnetic[0][r]);
    free(magnetic[1][r]);
  }
  free(momentum);
  free(pressure);
  MPI_Finalize();
  return failures == 0 ? 0 : 1;
}
