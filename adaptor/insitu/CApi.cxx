// The C API's entry points: thin handles over canopy::InSituOptions,
// ForestDescription and InSitu. Each runs its body through guarded() (or
// onHandle(), creating(): CApiStatus.h), so no exception crosses into C; the
// checks of their arguments are in CApiArguments.h.
#include <canopy/canopy.h>

#include "CApiArguments.h"
#include "CApiStatus.h"

#include <canopy/ForestValidation.h>
#include <canopy/InSitu.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

struct canopy_options
{
  canopy::InSituOptions options;
};

struct canopy_forest
{
  canopy::ForestDescription description;
  /// Block forests: the copied address tables of the block fields, one per field of
  /// `description` (empty for canopy_forest_add_block_field_array), which point into
  /// them. Moving a vector keeps its buffer, so they stay where the fields point.
  std::vector<std::vector<const void*>> blockTables;
};

struct canopy_insitu
{
  std::unique_ptr<canopy::InSitu> driver;
  /// The last evaluated step's values: expressions and queries, by their text.
  std::map<std::string, double> queryValues;
  bool queriesEvaluated = false;
};

using namespace canopy::capi;

namespace
{

/// Keeps the step's query values for canopy_query_value (when it evaluated them).
void keepQueryValues(canopy_insitu& handle, const canopy::StepReport& report)
{
  if (!report.queriesEvaluated)
  {
    return;
  }
  handle.queriesEvaluated = true;
  handle.queryValues = report.expressions;
  for (const auto& [text, result] : report.queries)
  {
    handle.queryValues[text] = result.value;
  }
}

/// An options call: `change` gets the options once the handle is checked.
template <typename Change>
int changeOptions(const char* function, canopy_options* options, Change&& change) noexcept
{
  return onHandle(function, CANOPY_INVALID_ARGUMENT, options, "options",
                  [&](canopy_options& handle) { return change(handle.options); });
}

/// An options call with a string argument `text` (named `what`), checked after
/// the handle and before `change` runs.
template <typename Change>
int changeOptionsWithText(const char* function, canopy_options* options, const char* what,
                          const char* text, bool mayBeEmpty, Change&& change) noexcept
{
  return changeOptions(function, options,
                       [&](canopy::InSituOptions& values)
                       {
                         if (const int status = checkString(function, what, text, mayBeEmpty))
                         {
                           return status;
                         }
                         return change(values);
                       });
}

/// Sets the string option `member` to `text` (not NULL, not empty).
int setTextOption(const char* function, canopy_options* options, const char* what, const char* text,
                  std::string canopy::InSituOptions::*member) noexcept
{
  return changeOptionsWithText(function, options, what, text, false,
                               [&](canopy::InSituOptions& values)
                               {
                                 values.*member = text;
                                 return succeed();
                               });
}

/// Both field calls: the shared checks, then `place`'s (the layout and where
/// the values are, CANOPY_OK or the refusal), then the field is added.
template <typename Place>
int addField(const char* function, canopy_forest* forest, const char* name, int valueType,
             int components, std::size_t numberOfTuples, int centering, Place&& place) noexcept
{
  return onHandle(function, CANOPY_INVALID_ARGUMENT, forest, "forest",
                  [&](canopy_forest& handle)
                  {
                    canopy::FieldDescription field;
                    if (const int status = checkField(function, name, valueType, components,
                                                      numberOfTuples, centering, field))
                    {
                      return status;
                    }
                    if (handle.description.blockCellsPerSide != 0)
                    {
                      return fail(CANOPY_INVALID_ARGUMENT,
                                  "%s: field '%s': the forest has blocks "
                                  "(canopy_forest_set_blocks): its fields are block fields "
                                  "(canopy_forest_add_block_field*)",
                                  function, name);
                    }
                    if (const int status = place(field))
                    {
                      return status;
                    }
                    handle.description.fields.push_back(std::move(field));
                    return succeed();
                  });
}

/// Every tree call (`absent` NULL: a whole tree; `blockTree`: the block forests'
/// own call, which refuses an ordinary forest).
int addTree(const char* function, canopy_forest* forest, int64_t rootIndex,
            const uint8_t* refinement, size_t numberOfNodes, const uint8_t* masked,
            const int64_t* storageSlots, const uint8_t* absent, const int64_t* blockIndex,
            bool blockTree) noexcept
{
  return onHandle(
      function, CANOPY_INVALID_ARGUMENT, forest, "forest",
      [&](canopy_forest& handle)
      {
        if (rootIndex < 0)
        {
          return fail(CANOPY_INVALID_ARGUMENT, "%s: root_index %lld is negative", function,
                      static_cast<long long>(rootIndex));
        }
        if (negativeCount(numberOfNodes))
        {
          return fail(CANOPY_INVALID_ARGUMENT,
                      "%s: root %lld: number_of_nodes %zu is negative or too large", function,
                      static_cast<long long>(rootIndex), numberOfNodes);
        }
        if (numberOfNodes == 0)
        {
          return fail(CANOPY_INVALID_ARGUMENT,
                      "%s: root %lld: number_of_nodes is 0 (a tree has at least its root)",
                      function, static_cast<long long>(rootIndex));
        }
        if (refinement == nullptr)
        {
          return fail(CANOPY_INVALID_ARGUMENT, "%s: root %lld: refinement is NULL", function,
                      static_cast<long long>(rootIndex));
        }
        const bool blocks = handle.description.blockCellsPerSide != 0;
        if (blockTree && !blocks)
        {
          return fail(CANOPY_INVALID_ARGUMENT,
                      "%s: root %lld: the forest has no blocks (call canopy_forest_set_blocks "
                      "first)",
                      function, static_cast<long long>(rootIndex));
        }
        if (blocks && storageSlots != nullptr)
        {
          return fail(CANOPY_INVALID_ARGUMENT,
                      "%s: root %lld: storage_slots must be NULL in a block forest (its fields "
                      "are per block; canopy_forest_add_block_tree's block_index orders them)",
                      function, static_cast<long long>(rootIndex));
        }
        canopy::TreeDescription tree;
        tree.rootIndex = rootIndex;
        tree.refinement = refinement;
        tree.numberOfNodes = numberOfNodes;
        tree.masked = masked;
        tree.storageSlots = storageSlots;
        tree.absent = absent;
        tree.blockIndex = blockIndex;
        handle.description.trees.push_back(tree); // strong guarantee: unchanged if it throws
        return succeed();
      });
}

/// The block field calls: the shared checks (separateComponents: the third call's
/// per-component tables), then `place`'s (where the blocks are: CANOPY_OK or the
/// refusal; it fills the field and the address table to copy), then the field is
/// added with its table.
template <typename Place>
int addBlockField(const char* function, canopy_forest* forest, const char* name, int valueType,
                  int components, std::size_t numberOfBlocks, const canopy_block_strides* strides,
                  bool separateComponents, Place&& place) noexcept
{
  return onHandle(
      function, CANOPY_INVALID_ARGUMENT, forest, "forest",
      [&](canopy_forest& handle)
      {
        canopy::ForestDescription& description = handle.description;
        canopy::FieldDescription field;
        if (const int status =
                checkBlockField(function, name, valueType, components, numberOfBlocks, strides,
                                description.dimension, separateComponents, field))
        {
          return status;
        }
        if (description.blockCellsPerSide == 0)
        {
          return fail(CANOPY_INVALID_ARGUMENT,
                      "%s: field '%s': the forest has no blocks (call canopy_forest_set_blocks "
                      "first)",
                      function, name);
        }
        std::vector<const void*> table;
        if (const int status = place(field, table))
        {
          return status;
        }
        // Both or neither: room for the table first (a failure changes nothing), then
        // the field (likewise), then the table, which cannot fail: moving a vector is
        // noexcept and keeps the buffer the field points into.
        std::vector<std::vector<const void*>>& tables = handle.blockTables;
        if (tables.size() == tables.capacity())
        {
          tables.reserve(2 * tables.size() + 1);
        }
        description.fields.push_back(std::move(field));
        tables.push_back(std::move(table));
        return succeed();
      });
}

} // namespace

extern "C"
{

  int canopy_options_create(canopy_options** options)
  {
    return creating("canopy_options_create", CANOPY_INVALID_ARGUMENT, options,
                    [&]
                    {
                      *options = new canopy_options();
                      return succeed();
                    });
  }

  void canopy_options_destroy(canopy_options* options)
  {
    delete options;
  }

  int canopy_options_add_script(canopy_options* options, const char* path)
  {
    return changeOptionsWithText("canopy_options_add_script", options, "the script path", path,
                                 false,
                                 [&](canopy::InSituOptions& values)
                                 {
                                   values.scripts.push_back({path, {}});
                                   return succeed();
                                 });
  }

  int canopy_options_add_script_argument(canopy_options* options, const char* argument)
  {
    static const char* const function = "canopy_options_add_script_argument";
    return changeOptionsWithText(function, options, "the argument", argument, true,
                                 [&](canopy::InSituOptions& values)
                                 {
                                   if (values.scripts.empty())
                                   {
                                     return fail(CANOPY_INVALID_ARGUMENT, "%s: add a script first",
                                                 function);
                                   }
                                   values.scripts.back().arguments.emplace_back(argument);
                                   return succeed();
                                 });
  }

  int canopy_options_set_output_directory(canopy_options* options, const char* directory)
  {
    return setTextOption("canopy_options_set_output_directory", options, "the output directory",
                         directory, &canopy::InSituOptions::outputDirectory);
  }

  int canopy_options_set_channel(canopy_options* options, const char* channel)
  {
    return setTextOption("canopy_options_set_channel", options, "the channel", channel,
                         &canopy::InSituOptions::channel);
  }

  int canopy_options_set_verbosity(canopy_options* options, int verbosity)
  {
    return changeOptions("canopy_options_set_verbosity", options,
                         [&](canopy::InSituOptions& values)
                         {
                           values.verbosity = verbosity;
                           return succeed();
                         });
  }

  int canopy_options_set_step_summary(canopy_options* options, int enabled)
  {
    return changeOptions("canopy_options_set_step_summary", options,
                         [&](canopy::InSituOptions& values)
                         {
                           values.stepSummary = enabled != 0;
                           return succeed();
                         });
  }

  int canopy_options_set_step_time_limit(canopy_options* options, double seconds)
  {
    static const char* const function = "canopy_options_set_step_time_limit";
    return changeOptions(function, options,
                         [&](canopy::InSituOptions& values)
                         {
                           if (!(seconds >= 0.0) || seconds == HUGE_VAL)
                           {
                             return fail(CANOPY_INVALID_ARGUMENT,
                                         "%s: seconds must be a finite number >= 0, got %g",
                                         function, seconds);
                           }
                           values.stepTimeLimitSeconds = seconds;
                           return succeed();
                         });
  }

  int canopy_options_add_query(canopy_options* options, const char* expression)
  {
    static const char* const function = "canopy_options_add_query";
    return changeOptionsWithText(function, options, "expression", expression, false,
                                 [&](canopy::InSituOptions& values)
                                 {
                                   values.queries.emplace_back(expression);
                                   return succeed();
                                 });
  }

  int canopy_options_add_field_name(canopy_options* options, const char* name)
  {
    static const char* const function = "canopy_options_add_field_name";
    return changeOptionsWithText(function, options, "name", name, false,
                                 [&](canopy::InSituOptions& values)
                                 {
                                   values.fields.emplace_back(name);
                                   return succeed();
                                 });
  }

  int canopy_forest_create(int dimension, int branch_factor, int max_levels, const double* x,
                           size_t points_x, const double* y, size_t points_y, const double* z,
                           size_t points_z, canopy_forest** forest)
  {
    static const char* const function = "canopy_forest_create";
    return creating(
        function, CANOPY_INVALID_ARGUMENT, forest,
        [&]
        {
          if (dimension < 1 || dimension > 3)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: dimension must be 1, 2 or 3, got %d",
                        function, dimension);
          }
          if (branch_factor != 2 && branch_factor != 3)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: branch_factor must be 2 or 3, got %d",
                        function, branch_factor);
          }
          if (max_levels < 1 || max_levels > canopy::maxSupportedLevels(branch_factor))
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: max_levels must be in [1, %d], got %d",
                        function, canopy::maxSupportedLevels(branch_factor), max_levels);
          }
          for (const auto& [axis, coordinates, points] :
               {std::tuple{'x', x, points_x}, std::tuple{'y', y, points_y},
                std::tuple{'z', z, points_z}})
          {
            if (const int status = checkAxis(function, axis, coordinates, points))
            {
              return status;
            }
          }
          auto created = std::make_unique<canopy_forest>();
          created->description.dimension = dimension;
          created->description.branchFactor = branch_factor;
          created->description.maxLevels = max_levels;
          created->description.rootGrid = {x, y, z, points_x, points_y, points_z};
          *forest = created.release();
          return succeed();
        });
  }

  void canopy_forest_destroy(canopy_forest* forest)
  {
    delete forest;
  }

  int canopy_forest_clear(canopy_forest* forest)
  {
    return onHandle("canopy_forest_clear", CANOPY_INVALID_ARGUMENT, forest, "forest",
                    [](canopy_forest& handle)
                    {
                      handle.description.trees.clear();
                      handle.description.fields.clear();
                      handle.blockTables.clear();
                      return succeed();
                    });
  }

  int canopy_forest_add_tree(canopy_forest* forest, int64_t root_index, const uint8_t* refinement,
                             size_t number_of_nodes, const uint8_t* masked,
                             const int64_t* storage_slots)
  {
    return addTree("canopy_forest_add_tree", forest, root_index, refinement, number_of_nodes,
                   masked, storage_slots, nullptr, nullptr, false);
  }

  int canopy_forest_add_partial_tree(canopy_forest* forest, int64_t root_index,
                                     const uint8_t* refinement, size_t number_of_nodes,
                                     const uint8_t* masked, const int64_t* storage_slots,
                                     const uint8_t* absent)
  {
    return addTree("canopy_forest_add_partial_tree", forest, root_index, refinement,
                   number_of_nodes, masked, storage_slots, absent, nullptr, false);
  }

  int canopy_forest_add_field(canopy_forest* forest, const char* name, int value_type,
                              int components, const void* data, size_t tuple_stride_bytes,
                              size_t number_of_tuples, int centering)
  {
    static const char* const function = "canopy_forest_add_field";
    return addField(
        function, forest, name, value_type, components, number_of_tuples, centering,
        [&](canopy::FieldDescription& field) -> int
        {
          if (data == nullptr && number_of_tuples > 0)
          {
            return fail(CANOPY_INVALID_ARGUMENT,
                        "%s: field '%s': data is NULL but number_of_tuples is %zu", function, name,
                        number_of_tuples);
          }
          const std::size_t valueSize = canopy::sizeOf(field.type);
          const std::size_t packed = static_cast<std::size_t>(components) * valueSize;
          if (tuple_stride_bytes != 0 &&
              (tuple_stride_bytes < packed || negativeCount(tuple_stride_bytes)))
          {
            return fail(CANOPY_INVALID_ARGUMENT,
                        "%s: field '%s': tuple_stride_bytes %zu is smaller than one tuple (%zu "
                        "bytes) or negative",
                        function, name, tuple_stride_bytes, packed);
          }
          if (tuple_stride_bytes % valueSize != 0)
          {
            return fail(CANOPY_INVALID_ARGUMENT,
                        "%s: field '%s': tuple_stride_bytes %zu is not a multiple of the value "
                        "size %zu",
                        function, name, tuple_stride_bytes, valueSize);
          }
          field.data = data;
          if (tuple_stride_bytes == 0 || tuple_stride_bytes == packed)
          {
            field.layout = canopy::Layout::AoS;
          }
          else
          {
            field.layout = canopy::Layout::Strided;
            field.tupleStrideBytes = tuple_stride_bytes;
          }
          return CANOPY_OK;
        });
  }

  int canopy_forest_add_field_soa(canopy_forest* forest, const char* name, int value_type,
                                  int components, const void* const* component_data,
                                  size_t number_of_tuples, int centering)
  {
    static const char* const function = "canopy_forest_add_field_soa";
    return addField(function, forest, name, value_type, components, number_of_tuples, centering,
                    [&](canopy::FieldDescription& field) -> int
                    {
                      if (component_data == nullptr)
                      {
                        return fail(CANOPY_INVALID_ARGUMENT,
                                    "%s: field '%s': component_data is NULL", function, name);
                      }
                      for (int c = 0; c < components; ++c)
                      {
                        if (component_data[c] == nullptr && number_of_tuples > 0)
                        {
                          return fail(CANOPY_INVALID_ARGUMENT,
                                      "%s: field '%s': component %d's data is NULL "
                                      "but number_of_tuples is %zu",
                                      function, name, c, number_of_tuples);
                        }
                      }
                      field.layout = canopy::Layout::SoA;
                      field.componentData.assign(component_data, component_data + components);
                      return CANOPY_OK;
                    });
  }

  int canopy_forest_set_blocks(canopy_forest* forest, int cells_per_side)
  {
    static const char* const function = "canopy_forest_set_blocks";
    return onHandle(function, CANOPY_INVALID_ARGUMENT, forest, "forest",
                    [&](canopy_forest& handle)
                    {
                      canopy::ForestDescription& description = handle.description;
                      if (const int status =
                              checkBlockSize(function, cells_per_side, description.branchFactor,
                                             description.maxLevels))
                      {
                        return status;
                      }
                      if (!description.trees.empty() || !description.fields.empty())
                      {
                        return fail(CANOPY_INVALID_ARGUMENT,
                                    "%s: the forest already has %zu trees and %zu fields: set "
                                    "the block size right after canopy_forest_create or "
                                    "canopy_forest_clear",
                                    function, description.trees.size(), description.fields.size());
                      }
                      description.blockCellsPerSide = cells_per_side;
                      return succeed();
                    });
  }

  int canopy_forest_add_block_tree(canopy_forest* forest, int64_t root_index,
                                   const uint8_t* refinement, size_t number_of_nodes,
                                   const uint8_t* masked, const uint8_t* absent,
                                   const int64_t* block_index)
  {
    return addTree("canopy_forest_add_block_tree", forest, root_index, refinement, number_of_nodes,
                   masked, nullptr, absent, block_index, true);
  }

  int canopy_block_strides_packed(int dimension, int cells_per_side, int ghost_cells,
                                  int components, int value_type, int order,
                                  canopy_block_strides* strides, size_t* block_bytes)
  {
    static const char* const function = "canopy_block_strides_packed";
    return guarded(
        function, CANOPY_INVALID_ARGUMENT,
        [&]
        {
          canopy::ValueType type = canopy::ValueType::Float64;
          if (dimension < 1 || dimension > 3)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: dimension must be 1, 2 or 3, got %d",
                        function, dimension);
          }
          if (cells_per_side < 1)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: cells_per_side must be at least 1, got %d",
                        function, cells_per_side);
          }
          if (ghost_cells < 0)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: ghost_cells %d is negative", function,
                        ghost_cells);
          }
          if (components < 1)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: components must be at least 1, got %d",
                        function, components);
          }
          if (!valueTypeFromC(value_type, type))
          {
            return fail(CANOPY_INVALID_ARGUMENT,
                        "%s: unknown value type %d (use CANOPY_FLOAT32/FLOAT64/INT32/INT64)",
                        function, value_type);
          }
          if (order != CANOPY_VARIABLE_OUTERMOST && order != CANOPY_VARIABLE_INNERMOST)
          {
            return fail(CANOPY_INVALID_ARGUMENT,
                        "%s: unknown order %d (use CANOPY_VARIABLE_OUTERMOST or "
                        "CANOPY_VARIABLE_INNERMOST)",
                        function, order);
          }
          if (strides == nullptr)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: strides is NULL", function);
          }
          // The whole block's bytes, refused when beyond what can be addressed.
          const auto extent =
              static_cast<std::size_t>(cells_per_side) + 2 * static_cast<std::size_t>(ghost_cells);
          std::size_t bytes = canopy::sizeOf(type) * static_cast<std::size_t>(components);
          for (int a = 0; a < dimension; ++a)
          {
            if (bytes > static_cast<std::size_t>(PTRDIFF_MAX) / extent)
            {
              return fail(CANOPY_INVALID_ARGUMENT,
                          "%s: a block of (%d + 2 x %d)^%d cells of %d components is too large "
                          "to address",
                          function, cells_per_side, ghost_cells, dimension, components);
            }
            bytes *= extent;
          }
          // The core's own two orders (one value size per type: the layout is all bytes).
          const bool outermost = order == CANOPY_VARIABLE_OUTERMOST;
          const bool wide = canopy::sizeOf(type) == 8;
          const canopy::BlockStrides packed =
              outermost ? (wide ? canopy::BlockStrides::variableOutermost<double>(
                                      dimension, cells_per_side, ghost_cells)
                                : canopy::BlockStrides::variableOutermost<float>(
                                      dimension, cells_per_side, ghost_cells))
                        : (wide ? canopy::BlockStrides::variableInnermost<double>(
                                      dimension, cells_per_side, ghost_cells, components)
                                : canopy::BlockStrides::variableInnermost<float>(
                                      dimension, cells_per_side, ghost_cells, components));
          for (std::size_t a = 0; a < 3; ++a)
          {
            strides->cell_bytes[a] = packed.cellBytes[a];
            strides->ghost_cells[a] = packed.ghostCells[a];
          }
          strides->component_bytes = packed.componentBytes;
          if (block_bytes != nullptr)
          {
            *block_bytes = bytes;
          }
          return succeed();
        });
  }

  int canopy_forest_add_block_field(canopy_forest* forest, const char* name, int value_type,
                                    int components, const void* const* block_addresses,
                                    size_t number_of_blocks, const canopy_block_strides* strides)
  {
    static const char* const function = "canopy_forest_add_block_field";
    return addBlockField(
        function, forest, name, value_type, components, number_of_blocks, strides, false,
        [&](canopy::FieldDescription& field, std::vector<const void*>& table) -> int
        {
          if (const int status = checkBlockAddresses(function, name, "block_addresses",
                                                     block_addresses, number_of_blocks,
                                                     number_of_blocks, canopy::sizeOf(field.type)))
          {
            return status;
          }
          if (number_of_blocks > 0)
          {
            table.assign(block_addresses, block_addresses + number_of_blocks);
            field.blockAddresses = table.data();
          }
          return CANOPY_OK;
        });
  }

  int canopy_forest_add_block_field_array(canopy_forest* forest, const char* name, int value_type,
                                          int components, const void* first_block,
                                          size_t block_stride_bytes, size_t number_of_blocks,
                                          const canopy_block_strides* strides)
  {
    static const char* const function = "canopy_forest_add_block_field_array";
    return addBlockField(
        function, forest, name, value_type, components, number_of_blocks, strides, false,
        [&](canopy::FieldDescription& field, std::vector<const void*>&) -> int
        {
          const std::size_t valueSize = canopy::sizeOf(field.type);
          if (first_block == nullptr && number_of_blocks > 0)
          {
            return fail(CANOPY_INVALID_ARGUMENT,
                        "%s: field '%s': first_block is NULL but number_of_blocks is %zu", function,
                        name, number_of_blocks);
          }
          if (misaligned(first_block, valueSize))
          {
            return fail(CANOPY_INVALID_ARGUMENT,
                        "%s: field '%s': first_block is not aligned to the value size %zu",
                        function, name, valueSize);
          }
          if (number_of_blocks > 1 &&
              (negativeCount(block_stride_bytes) || block_stride_bytes == 0 ||
               block_stride_bytes % valueSize != 0))
          {
            return fail(CANOPY_INVALID_ARGUMENT,
                        "%s: field '%s': block_stride_bytes %zu is not a nonzero multiple of "
                        "the value size %zu (or is negative), with %zu blocks",
                        function, name, block_stride_bytes, valueSize, number_of_blocks);
          }
          field.data = first_block;
          field.blockStrideBytes = number_of_blocks > 1 ? block_stride_bytes : 0;
          return CANOPY_OK;
        });
  }

  int canopy_forest_add_block_field_components(canopy_forest* forest, const char* name,
                                               int value_type, int components,
                                               const void* const* block_addresses,
                                               size_t number_of_blocks,
                                               const canopy_block_strides* strides)
  {
    static const char* const function = "canopy_forest_add_block_field_components";
    return addBlockField(
        function, forest, name, value_type, components, number_of_blocks, strides, true,
        [&](canopy::FieldDescription& field, std::vector<const void*>& table) -> int
        {
          const auto count = static_cast<std::size_t>(components);
          if (number_of_blocks > static_cast<std::size_t>(PTRDIFF_MAX) / count)
          {
            return fail(CANOPY_INVALID_ARGUMENT,
                        "%s: field '%s': %d components x %zu blocks are too many addresses",
                        function, name, components, number_of_blocks);
          }
          if (const int status = checkBlockAddresses(function, name, "block_addresses",
                                                     block_addresses, count * number_of_blocks,
                                                     number_of_blocks, canopy::sizeOf(field.type)))
          {
            return status;
          }
          if (number_of_blocks > 0)
          {
            table.assign(block_addresses, block_addresses + count * number_of_blocks);
          }
          // One table per component (null without blocks: nothing to read).
          for (std::size_t c = 0; c < count; ++c)
          {
            field.componentBlockAddresses.push_back(
                number_of_blocks > 0 ? table.data() + c * number_of_blocks : nullptr);
          }
          return CANOPY_OK;
        });
  }

  int canopy_open(MPI_Comm communicator, const canopy_options* options, canopy_insitu** insitu)
  {
    static const char* const function = "canopy_open";
    return creating(
        function, CANOPY_OPEN_FAILED, insitu,
        [&]
        {
          if (options == nullptr)
          {
            return nullHandle(function, "options");
          }
          if (communicator == MPI_COMM_NULL)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: the communicator is MPI_COMM_NULL", function);
          }
          auto handle = std::make_unique<canopy_insitu>();
          try
          {
            handle->driver = std::make_unique<canopy::InSitu>(communicator, options->options);
          }
          catch (const canopy::InSituError& error)
          {
            // Its message already names every rank's problem.
            return fail(CANOPY_OPEN_FAILED, "%s", error.what());
          }
          *insitu = handle.release();
          return succeed();
        });
  }

  int canopy_open_f(MPI_Fint communicator, const canopy_options* options, canopy_insitu** insitu)
  {
    const MPI_Comm converted = MPI_Comm_f2c(communicator);
    // Open MPI returns a null pointer (not MPI_COMM_NULL) for an unknown handle;
    // MPICH's handle 0 is invalid as well.
    if (converted == MPI_Comm{})
    {
      if (insitu != nullptr)
      {
        *insitu = nullptr;
      }
      return fail(CANOPY_INVALID_ARGUMENT, "canopy_open_f: %d is not a Fortran communicator handle",
                  communicator);
    }
    return canopy_open(converted, options, insitu);
  }

  int canopy_will_execute(canopy_insitu* insitu, int64_t step, double time, int* will_execute)
  {
    static const char* const function = "canopy_will_execute";
    return onHandle(function, CANOPY_STEP_FAILED, insitu, "insitu",
                    [&](canopy_insitu& handle)
                    {
                      // Collective: asked even when the result pointer is NULL, so
                      // that the other ranks are not left waiting.
                      const bool will = handle.driver->willExecute(step, time);
                      if (will_execute == nullptr)
                      {
                        return fail(CANOPY_INVALID_ARGUMENT, "%s: the result pointer is NULL",
                                    function);
                      }
                      *will_execute = will ? 1 : 0;
                      return succeed();
                    });
  }

  int canopy_execute(canopy_insitu* insitu, int64_t step, double time, const canopy_forest* forest)
  {
    return onHandle("canopy_execute", CANOPY_STEP_FAILED, insitu, "insitu",
                    [&](canopy_insitu& handle)
                    {
                      // Collective: a NULL forest still takes part (as an empty, invalid one)
                      // so that every rank skips the step together.
                      static const canopy::ForestDescription nothing{};
                      const auto report = handle.driver->execute(
                          step, time, forest ? forest->description : nothing);
                      keepQueryValues(handle, report);
                      std::string message =
                          forest ? "" : "canopy_execute: the forest handle is NULL on this rank";
                      for (const auto& failure : report.failures)
                      {
                        message += (message.empty() ? "" : "\n") + failure;
                      }
                      if (forest == nullptr)
                      {
                        return fail(CANOPY_INVALID_ARGUMENT, "%s", message.c_str());
                      }
                      return report.failures.empty()
                                 ? succeed()
                                 : fail(CANOPY_STEP_FAILED, "%s", message.c_str());
                    });
  }

  int canopy_will_execute_forest(canopy_insitu* insitu, int64_t step, double time,
                                 const canopy_forest* forest, int* will_execute)
  {
    static const char* const function = "canopy_will_execute_forest";
    return onHandle(
        function, CANOPY_STEP_FAILED, insitu, "insitu",
        [&](canopy_insitu& handle)
        {
          // Collective whatever the arguments, like canopy_execute.
          static const canopy::ForestDescription nothing{};
          const bool will =
              handle.driver->willExecute(step, time, forest ? forest->description : nothing);
          if (will_execute == nullptr)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: the result pointer is NULL", function);
          }
          *will_execute = will ? 1 : 0;
          return succeed();
        });
  }

  int canopy_query_value(canopy_insitu* insitu, const char* expression, double* value)
  {
    static const char* const function = "canopy_query_value";
    return onHandle(function, CANOPY_INVALID_ARGUMENT, insitu, "insitu",
                    [&](canopy_insitu& handle)
                    {
                      if (expression == nullptr || value == nullptr)
                      {
                        return fail(CANOPY_INVALID_ARGUMENT,
                                    "%s: the expression or the value pointer is NULL", function);
                      }
                      *value = std::numeric_limits<double>::quiet_NaN();
                      const auto found = handle.queryValues.find(expression);
                      if (found == handle.queryValues.end())
                      {
                        return handle.queriesEvaluated
                                   ? fail(CANOPY_INVALID_ARGUMENT,
                                          "%s: '%s' is neither a query nor an expression of "
                                          "this run",
                                          function, expression)
                                   : succeed();
                      }
                      *value = found->second;
                      return succeed();
                    });
  }

  int canopy_close(canopy_insitu** insitu)
  {
    static const char* const function = "canopy_close";
    if (insitu == nullptr)
    {
      return fail(CANOPY_INVALID_ARGUMENT, "%s: the pointer to the handle is NULL", function);
    }
    if (*insitu == nullptr)
    {
      return fail(CANOPY_INVALID_ARGUMENT, "%s: the handle is NULL (never opened, or closed)",
                  function);
    }
    const int status = guarded(function, CANOPY_STEP_FAILED,
                               [&]
                               {
                                 (*insitu)->driver->close();
                                 return succeed();
                               });
    // Freed whatever close() did: the handle is unusable either way.
    delete *insitu;
    *insitu = nullptr;
    return status;
  }

} // extern "C"
