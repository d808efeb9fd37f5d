// The C API: thin handles over canopy::InSituOptions, ForestDescription and
// InSitu. No exception crosses into C; each failure leaves its message in
// canopy_last_error().
#include "canopy/canopy.h"

#include "canopy/InSitu.h"

#include <cmath>
#include <memory>
#include <new>
#include <string>

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

namespace
{

thread_local std::string lastError;

int failWith(int status, std::string message)
{
  lastError = std::move(message);
  return status;
}

/// Runs an allocating step; false if it threw (no exception may reach C).
template <typename Step>
bool withoutThrowing(Step step)
{
  try
  {
    step();
    return true;
  }
  catch (...)
  {
    return false;
  }
}

int succeed()
{
  lastError.clear();
  return CANOPY_OK;
}

bool valueTypeFromC(int code, canopy::ValueType& type)
{
  switch (code)
  {
  case CANOPY_FLOAT32:
    type = canopy::ValueType::Float32;
    return true;
  case CANOPY_FLOAT64:
    type = canopy::ValueType::Float64;
    return true;
  case CANOPY_INT32:
    type = canopy::ValueType::Int32;
    return true;
  case CANOPY_INT64:
    type = canopy::ValueType::Int64;
    return true;
  default:
    return false;
  }
}

bool centeringFromC(int code, canopy::Centering& centering)
{
  if (code == CANOPY_EVERY_NODE || code == CANOPY_LEAVES_ONLY)
  {
    centering =
        code == CANOPY_EVERY_NODE ? canopy::Centering::EveryNode : canopy::Centering::LeavesOnly;
    return true;
  }
  return false;
}

/// Checks shared by both field calls; empty when fine.
std::string fieldArgumentProblem(const canopy_forest* forest, const char* name, int valueType,
                                 int components, int centering, canopy::FieldDescription& field)
{
  if (forest == nullptr)
  {
    return "the forest handle is NULL";
  }
  if (name == nullptr || *name == '\0')
  {
    return "the field name is NULL or empty";
  }
  if (!valueTypeFromC(valueType, field.type))
  {
    return "field '" + std::string(name) + "': unknown value type " + std::to_string(valueType) +
           " (use CANOPY_FLOAT32/FLOAT64/INT32/INT64)";
  }
  if (!centeringFromC(centering, field.centering))
  {
    return "field '" + std::string(name) + "': unknown centering " + std::to_string(centering) +
           " (use CANOPY_EVERY_NODE or CANOPY_LEAVES_ONLY)";
  }
  if (components < 1)
  {
    return "field '" + std::string(name) + "': components must be at least 1";
  }
  field.name = name;
  field.components = components;
  return {};
}

} // namespace

extern "C"
{

  const char* canopy_last_error(void)
  {
    return lastError.c_str();
  }

  canopy_options* canopy_options_create(void)
  {
    return new canopy_options();
  }

  void canopy_options_destroy(canopy_options* options)
  {
    delete options;
  }

  int canopy_options_add_script(canopy_options* options, const char* path)
  {
    if (options == nullptr || path == nullptr || *path == '\0')
    {
      return failWith(CANOPY_INVALID_ARGUMENT,
                      "canopy_options_add_script: NULL options or empty script path");
    }
    if (!withoutThrowing([&] { options->options.scripts.push_back({path, {}}); }))
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_options_add_script: out of memory");
    }
    return succeed();
  }

  int canopy_options_add_script_argument(canopy_options* options, const char* argument)
  {
    if (options == nullptr || argument == nullptr)
    {
      return failWith(CANOPY_INVALID_ARGUMENT,
                      "canopy_options_add_script_argument: NULL options or argument");
    }
    if (options->options.scripts.empty())
    {
      return failWith(CANOPY_INVALID_ARGUMENT,
                      "canopy_options_add_script_argument: add a script first");
    }
    if (!withoutThrowing([&] { options->options.scripts.back().arguments.emplace_back(argument); }))
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_options_add_script_argument: out of memory");
    }
    return succeed();
  }

  int canopy_options_set_output_directory(canopy_options* options, const char* directory)
  {
    if (options == nullptr || directory == nullptr || *directory == '\0')
    {
      return failWith(CANOPY_INVALID_ARGUMENT,
                      "canopy_options_set_output_directory: NULL options or empty directory");
    }
    options->options.outputDirectory = directory;
    return succeed();
  }

  int canopy_options_set_channel(canopy_options* options, const char* channel)
  {
    if (options == nullptr || channel == nullptr || *channel == '\0')
    {
      return failWith(CANOPY_INVALID_ARGUMENT,
                      "canopy_options_set_channel: NULL options or empty channel");
    }
    options->options.channel = channel;
    return succeed();
  }

  int canopy_options_set_verbosity(canopy_options* options, int verbosity)
  {
    if (options == nullptr)
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_options_set_verbosity: NULL options");
    }
    options->options.verbosity = verbosity;
    return succeed();
  }

  int canopy_options_set_step_summary(canopy_options* options, int enabled)
  {
    if (options == nullptr)
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_options_set_step_summary: NULL options");
    }
    options->options.stepSummary = enabled != 0;
    return succeed();
  }

  int canopy_options_set_step_time_limit(canopy_options* options, double seconds)
  {
    if (options == nullptr || !(seconds >= 0.0) || seconds == HUGE_VAL)
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_options_set_step_time_limit: NULL options "
                                               "or not a finite number of seconds >= 0");
    }
    options->options.stepTimeLimitSeconds = seconds;
    return succeed();
  }

  canopy_forest* canopy_forest_create(int dimension, int branch_factor, int max_levels,
                                      const double* x, size_t points_x, const double* y,
                                      size_t points_y, const double* z, size_t points_z)
  {
    // The values are checked (with every other problem) when the forest is used.
    auto* forest = new canopy_forest();
    forest->description.dimension = dimension;
    forest->description.branchFactor = branch_factor;
    forest->description.maxLevels = max_levels;
    forest->description.rootGrid = {x, y, z, points_x, points_y, points_z};
    return forest;
  }

  void canopy_forest_destroy(canopy_forest* forest)
  {
    delete forest;
  }

  int canopy_forest_clear(canopy_forest* forest)
  {
    if (forest == nullptr)
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_forest_clear: the forest handle is NULL");
    }
    forest->description.trees.clear();
    forest->description.fields.clear();
    return succeed();
  }

  int canopy_forest_add_tree(canopy_forest* forest, int64_t root_index, const uint8_t* refinement,
                             size_t number_of_nodes, const uint8_t* masked,
                             const int64_t* storage_slots)
  {
    if (forest == nullptr)
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_forest_add_tree: the forest handle is NULL");
    }
    if (!withoutThrowing(
            [&]
            {
              forest->description.trees.push_back(
                  {root_index, refinement, number_of_nodes, masked, storage_slots});
            }))
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_forest_add_tree: out of memory");
    }
    return succeed();
  }

  int canopy_forest_add_field(canopy_forest* forest, const char* name, int value_type,
                              int components, const void* data, size_t tuple_stride_bytes,
                              size_t number_of_tuples, int centering)
  {
    canopy::FieldDescription field;
    const std::string problem =
        fieldArgumentProblem(forest, name, value_type, components, centering, field);
    if (!problem.empty())
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_forest_add_field: " + problem);
    }
    field.data = data;
    field.numberOfTuples = number_of_tuples;
    const std::size_t packed = static_cast<std::size_t>(components) * canopy::sizeOf(field.type);
    if (tuple_stride_bytes == 0 || tuple_stride_bytes == packed)
    {
      field.layout = canopy::Layout::AoS;
    }
    else
    {
      field.layout = canopy::Layout::Strided;
      field.tupleStrideBytes = tuple_stride_bytes;
    }
    if (!withoutThrowing([&] { forest->description.fields.push_back(std::move(field)); }))
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_forest_add_field: out of memory");
    }
    return succeed();
  }

  int canopy_forest_add_field_soa(canopy_forest* forest, const char* name, int value_type,
                                  int components, const void* const* component_data,
                                  size_t number_of_tuples, int centering)
  {
    canopy::FieldDescription field;
    std::string problem =
        fieldArgumentProblem(forest, name, value_type, components, centering, field);
    if (problem.empty() && component_data == nullptr)
    {
      problem = "field '" + std::string(name) + "': component_data is NULL";
    }
    if (!problem.empty())
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_forest_add_field_soa: " + problem);
    }
    field.layout = canopy::Layout::SoA;
    field.componentData.assign(component_data, component_data + components);
    field.numberOfTuples = number_of_tuples;
    if (!withoutThrowing([&] { forest->description.fields.push_back(std::move(field)); }))
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_forest_add_field_soa: out of memory");
    }
    return succeed();
  }

  int canopy_open(MPI_Comm communicator, const canopy_options* options, canopy_insitu** insitu)
  {
    if (options == nullptr || insitu == nullptr)
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_open: NULL options or NULL result pointer");
    }
    *insitu = nullptr;
    try
    {
      auto handle = std::make_unique<canopy_insitu>();
      handle->driver = std::make_unique<canopy::InSitu>(communicator, options->options);
      *insitu = handle.release();
      return succeed();
    }
    catch (const std::exception& error)
    {
      return failWith(CANOPY_OPEN_FAILED, error.what());
    }
  }

  int canopy_open_f(MPI_Fint communicator, const canopy_options* options, canopy_insitu** insitu)
  {
    return canopy_open(MPI_Comm_f2c(communicator), options, insitu);
  }

  int canopy_will_execute(canopy_insitu* insitu, int64_t step, double time, int* will_execute)
  {
    if (insitu == nullptr)
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_will_execute: NULL handle");
    }
    try
    {
      // Collective: asked even when the result pointer is NULL, so that the
      // other ranks are not left waiting.
      const bool will = insitu->driver->willExecute(step, time);
      if (will_execute == nullptr)
      {
        return failWith(CANOPY_INVALID_ARGUMENT, "canopy_will_execute: NULL result pointer");
      }
      *will_execute = will ? 1 : 0;
      return succeed();
    }
    catch (const std::exception& error)
    {
      return failWith(CANOPY_STEP_FAILED, std::string("canopy_will_execute: ") + error.what());
    }
    catch (...)
    {
      return failWith(CANOPY_STEP_FAILED, "canopy_will_execute: unknown error");
    }
  }

  int canopy_execute(canopy_insitu* insitu, int64_t step, double time, const canopy_forest* forest)
  {
    if (insitu == nullptr)
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_execute: NULL handle");
    }
    try
    {
      // Collective: a NULL forest still takes part (as an empty, invalid one) so
      // that every rank skips the step together.
      static const canopy::ForestDescription nothing{};
      const auto report =
          insitu->driver->execute(step, time, forest ? forest->description : nothing);
      std::string message = forest ? "" : "canopy_execute: NULL forest on this rank";
      for (const auto& failure : report.failures)
      {
        message += (message.empty() ? "" : "\n") + failure;
      }
      if (forest == nullptr)
      {
        return failWith(CANOPY_INVALID_ARGUMENT, message);
      }
      return report.failures.empty() ? succeed() : failWith(CANOPY_STEP_FAILED, message);
    }
    catch (const std::exception& error)
    {
      return failWith(CANOPY_STEP_FAILED, std::string("canopy_execute: ") + error.what());
    }
    catch (...)
    {
      return failWith(CANOPY_STEP_FAILED, "canopy_execute: unknown error");
    }
  }

  int canopy_close(canopy_insitu** insitu)
  {
    if (insitu == nullptr || *insitu == nullptr)
    {
      return failWith(CANOPY_INVALID_ARGUMENT, "canopy_close: NULL handle");
    }
    int status = CANOPY_OK;
    try
    {
      (*insitu)->driver->close();
    }
    catch (...)
    {
      status = failWith(CANOPY_STEP_FAILED, "canopy_close: error while finalizing Catalyst");
    }
    delete *insitu;
    *insitu = nullptr;
    return status == CANOPY_OK ? succeed() : status;
  }

} // extern "C"
