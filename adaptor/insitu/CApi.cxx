// The C API's entry points: thin handles over canopy::InSituOptions,
// ForestDescription and InSitu. Each runs its body through guarded() (or
// onHandle(), creating(): CApiStatus.h), so no exception crosses into C; the
// checks of their arguments are in CApiArguments.h.
#include "canopy/canopy.h"

#include "CApiArguments.h"
#include "CApiStatus.h"

#include "canopy/ForestValidation.h"
#include "canopy/InSitu.h"

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <tuple>

struct canopy_options
{
  canopy::InSituOptions options;
};

struct canopy_forest
{
  canopy::ForestDescription description;
};

struct canopy_insitu
{
  std::unique_ptr<canopy::InSitu> driver;
};

using namespace canopy::capi;

namespace
{

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
                    if (const int status = place(field))
                    {
                      return status;
                    }
                    handle.description.fields.push_back(std::move(field));
                    return succeed();
                  });
}

/// Both tree calls (`absent` NULL: a whole tree).
int addTree(const char* function, canopy_forest* forest, int64_t rootIndex,
            const uint8_t* refinement, size_t numberOfNodes, const uint8_t* masked,
            const int64_t* storageSlots, const uint8_t* absent) noexcept
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
        canopy::TreeDescription tree;
        tree.rootIndex = rootIndex;
        tree.refinement = refinement;
        tree.numberOfNodes = numberOfNodes;
        tree.masked = masked;
        tree.storageSlots = storageSlots;
        tree.absent = absent;
        handle.description.trees.push_back(tree); // strong guarantee: unchanged if it throws
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
                      return succeed();
                    });
  }

  int canopy_forest_add_tree(canopy_forest* forest, int64_t root_index, const uint8_t* refinement,
                             size_t number_of_nodes, const uint8_t* masked,
                             const int64_t* storage_slots)
  {
    return addTree("canopy_forest_add_tree", forest, root_index, refinement, number_of_nodes,
                   masked, storage_slots, nullptr);
  }

  int canopy_forest_add_partial_tree(canopy_forest* forest, int64_t root_index,
                                     const uint8_t* refinement, size_t number_of_nodes,
                                     const uint8_t* masked, const int64_t* storage_slots,
                                     const uint8_t* absent)
  {
    return addTree("canopy_forest_add_partial_tree", forest, root_index, refinement,
                   number_of_nodes, masked, storage_slots, absent);
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
