// The C API: thin handles over canopy::InSituOptions, ForestDescription and
// InSitu. Every extern "C" function runs its body through guarded(), so no
// exception crosses into C (an unwinding through C frames would terminate the
// simulation); each failure leaves its message in canopy_last_error().
#include "canopy/canopy.h"

#include "canopy/ForestValidation.h"
#include "canopy/InSitu.h"

#include <cmath>
#include <cstdarg>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <new>
#include <stdexcept>
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

/// This thread's last message. Plain data on purpose: a thread_local std::string
/// registers its destructor on first use, and glibc aborts the process when that
/// registration cannot allocate, which is exactly when an out-of-memory error is
/// reported. The malloc'ed text lives as long as the thread.
struct LastError
{
  char* text;
  std::size_t capacity;
  /// Used when `text` cannot grow: the message, truncated if need be.
  char brief[192];
  bool useBrief;
};
thread_local LastError lastError{};

/// Records a printf-style message (only %s, %d, %zu, %lld...: glibc formats those
/// without allocating) and returns `status`. Never throws, never fails.
[[gnu::format(printf, 2, 3)]] int fail(int status, const char* format, ...) noexcept
{
  std::va_list arguments;
  va_start(arguments, format);
  std::va_list measuring;
  va_copy(measuring, arguments);
  const int length = std::vsnprintf(nullptr, 0, format, measuring);
  va_end(measuring);
  const std::size_t needed = length > 0 ? static_cast<std::size_t>(length) + 1 : 1;
  if (needed > lastError.capacity)
  {
    if (auto* grown = static_cast<char*>(std::realloc(lastError.text, needed)))
    {
      lastError.text = grown;
      lastError.capacity = needed;
    }
  }
  if (needed <= lastError.capacity)
  {
    std::vsnprintf(lastError.text, lastError.capacity, format, arguments);
    lastError.useBrief = false;
  }
  else
  {
    std::vsnprintf(lastError.brief, sizeof lastError.brief, format, arguments);
    lastError.useBrief = true;
  }
  va_end(arguments);
  return status;
}

int succeed() noexcept
{
  if (lastError.text != nullptr)
  {
    lastError.text[0] = '\0';
  }
  lastError.useBrief = false;
  return CANOPY_OK;
}

/// Runs a function's body; any exception becomes a status and a message.
/// `otherStatus` is the status for exceptions other than allocation failures.
template <typename Body>
int guarded(const char* function, int otherStatus, Body&& body) noexcept
{
  try
  {
    return body();
  }
  catch (const std::bad_alloc&)
  {
    return fail(CANOPY_OUT_OF_MEMORY, "%s: out of memory", function);
  }
  catch (const std::length_error&)
  {
    // A container asked for more than it can ever hold: an allocation failure too.
    return fail(CANOPY_OUT_OF_MEMORY, "%s: out of memory (a size beyond what can be allocated)",
                function);
  }
  catch (const std::exception& error)
  {
    return fail(otherStatus, "%s: %s", function, error.what());
  }
  catch (...)
  {
    return fail(otherStatus, "%s: unknown error", function);
  }
}

/// size_t counts above PTRDIFF_MAX are negative numbers converted (Fortran's
/// c_size_t is signed) rather than real sizes.
bool negativeCount(std::size_t count)
{
  return count > static_cast<std::size_t>(PTRDIFF_MAX);
}

/// Checks a NUL-terminated string argument; CANOPY_OK or the refusal.
int checkString(const char* function, const char* what, const char* text, bool mayBeEmpty)
{
  if (text == nullptr)
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: %s is NULL", function, what);
  }
  if (!mayBeEmpty && *text == '\0')
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: %s is empty", function, what);
  }
  return CANOPY_OK;
}

int nullHandle(const char* function, const char* what)
{
  return fail(CANOPY_INVALID_ARGUMENT, "%s: the %s handle is NULL", function, what);
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

/// Checks shared by both field calls and fills what they share; CANOPY_OK or the refusal.
int checkField(const char* function, const canopy_forest* forest, const char* name, int valueType,
               int components, std::size_t numberOfTuples, int centering,
               canopy::FieldDescription& field)
{
  if (forest == nullptr)
  {
    return nullHandle(function, "forest");
  }
  if (const int status = checkString(function, "the field name", name, false))
  {
    return status;
  }
  if (!valueTypeFromC(valueType, field.type))
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: field '%s': unknown value type %d (use CANOPY_FLOAT32/FLOAT64/INT32/INT64)",
                function, name, valueType);
  }
  if (!centeringFromC(centering, field.centering))
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: field '%s': unknown centering %d (use CANOPY_EVERY_NODE or "
                "CANOPY_LEAVES_ONLY)",
                function, name, centering);
  }
  if (components < 1)
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: field '%s': components must be at least 1, got %d",
                function, name, components);
  }
  if (negativeCount(numberOfTuples))
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: field '%s': number_of_tuples %zu is negative or too large", function, name,
                numberOfTuples);
  }
  field.name = name; // may throw bad_alloc: the caller is guarded
  field.components = components;
  field.numberOfTuples = numberOfTuples;
  return CANOPY_OK;
}

int checkAxis(const char* function, char axis, const double* coordinates, std::size_t points)
{
  if (negativeCount(points))
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: points_%c %zu is negative or too large", function,
                axis, points);
  }
  if (points == 0)
  {
    return fail(CANOPY_INVALID_ARGUMENT,
                "%s: points_%c is 0 (every axis has at least 1 point; a flat axis exactly 1)",
                function, axis);
  }
  if (coordinates == nullptr)
  {
    return fail(CANOPY_INVALID_ARGUMENT, "%s: %c is NULL but points_%c is %zu", function, axis,
                axis, points);
  }
  return CANOPY_OK;
}

int addTree(const char* function, canopy_forest* forest, int64_t rootIndex,
            const uint8_t* refinement, size_t numberOfNodes, const uint8_t* masked,
            const int64_t* storageSlots, const uint8_t* absent)
{
  if (forest == nullptr)
  {
    return nullHandle(function, "forest");
  }
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
                "%s: root %lld: number_of_nodes is 0 (a tree has at least its root)", function,
                static_cast<long long>(rootIndex));
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
  forest->description.trees.push_back(tree); // strong guarantee: unchanged if it throws
  return succeed();
}

} // namespace

extern "C"
{

  const char* canopy_last_error(void)
  {
    if (lastError.useBrief)
    {
      return lastError.brief;
    }
    return lastError.text != nullptr ? lastError.text : "";
  }

  int canopy_options_create(canopy_options** options)
  {
    static const char* const function = "canopy_options_create";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     if (options == nullptr)
                     {
                       return fail(CANOPY_INVALID_ARGUMENT, "%s: the result pointer is NULL",
                                   function);
                     }
                     *options = nullptr;
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
    static const char* const function = "canopy_options_add_script";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     if (options == nullptr)
                     {
                       return nullHandle(function, "options");
                     }
                     if (const int status = checkString(function, "the script path", path, false))
                     {
                       return status;
                     }
                     options->options.scripts.push_back({path, {}});
                     return succeed();
                   });
  }

  int canopy_options_add_script_argument(canopy_options* options, const char* argument)
  {
    static const char* const function = "canopy_options_add_script_argument";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     if (options == nullptr)
                     {
                       return nullHandle(function, "options");
                     }
                     if (const int status = checkString(function, "the argument", argument, true))
                     {
                       return status;
                     }
                     if (options->options.scripts.empty())
                     {
                       return fail(CANOPY_INVALID_ARGUMENT, "%s: add a script first", function);
                     }
                     options->options.scripts.back().arguments.emplace_back(argument);
                     return succeed();
                   });
  }

  int canopy_options_set_output_directory(canopy_options* options, const char* directory)
  {
    static const char* const function = "canopy_options_set_output_directory";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     if (options == nullptr)
                     {
                       return nullHandle(function, "options");
                     }
                     if (const int status =
                             checkString(function, "the output directory", directory, false))
                     {
                       return status;
                     }
                     options->options.outputDirectory = directory;
                     return succeed();
                   });
  }

  int canopy_options_set_channel(canopy_options* options, const char* channel)
  {
    static const char* const function = "canopy_options_set_channel";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     if (options == nullptr)
                     {
                       return nullHandle(function, "options");
                     }
                     if (const int status = checkString(function, "the channel", channel, false))
                     {
                       return status;
                     }
                     options->options.channel = channel;
                     return succeed();
                   });
  }

  int canopy_options_set_verbosity(canopy_options* options, int verbosity)
  {
    static const char* const function = "canopy_options_set_verbosity";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     if (options == nullptr)
                     {
                       return nullHandle(function, "options");
                     }
                     options->options.verbosity = verbosity;
                     return succeed();
                   });
  }

  int canopy_options_set_step_summary(canopy_options* options, int enabled)
  {
    static const char* const function = "canopy_options_set_step_summary";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     if (options == nullptr)
                     {
                       return nullHandle(function, "options");
                     }
                     options->options.stepSummary = enabled != 0;
                     return succeed();
                   });
  }

  int canopy_options_set_step_time_limit(canopy_options* options, double seconds)
  {
    static const char* const function = "canopy_options_set_step_time_limit";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     if (options == nullptr)
                     {
                       return nullHandle(function, "options");
                     }
                     if (!(seconds >= 0.0) || seconds == HUGE_VAL)
                     {
                       return fail(CANOPY_INVALID_ARGUMENT,
                                   "%s: seconds must be a finite number >= 0, got %g", function,
                                   seconds);
                     }
                     options->options.stepTimeLimitSeconds = seconds;
                     return succeed();
                   });
  }

  int canopy_forest_create(int dimension, int branch_factor, int max_levels, const double* x,
                           size_t points_x, const double* y, size_t points_y, const double* z,
                           size_t points_z, canopy_forest** forest)
  {
    static const char* const function = "canopy_forest_create";
    return guarded(
        function, CANOPY_INVALID_ARGUMENT,
        [&]
        {
          if (forest == nullptr)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: the result pointer is NULL", function);
          }
          *forest = nullptr;
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
          if (const int status = checkAxis(function, 'x', x, points_x))
          {
            return status;
          }
          if (const int status = checkAxis(function, 'y', y, points_y))
          {
            return status;
          }
          if (const int status = checkAxis(function, 'z', z, points_z))
          {
            return status;
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
    if (forest == nullptr)
    {
      return nullHandle("canopy_forest_clear", "forest");
    }
    forest->description.trees.clear();
    forest->description.fields.clear();
    return succeed();
  }

  int canopy_forest_add_tree(canopy_forest* forest, int64_t root_index, const uint8_t* refinement,
                             size_t number_of_nodes, const uint8_t* masked,
                             const int64_t* storage_slots)
  {
    static const char* const function = "canopy_forest_add_tree";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     return addTree(function, forest, root_index, refinement, number_of_nodes,
                                    masked, storage_slots, nullptr);
                   });
  }

  int canopy_forest_add_partial_tree(canopy_forest* forest, int64_t root_index,
                                     const uint8_t* refinement, size_t number_of_nodes,
                                     const uint8_t* masked, const int64_t* storage_slots,
                                     const uint8_t* absent)
  {
    static const char* const function = "canopy_forest_add_partial_tree";
    return guarded(function, CANOPY_INVALID_ARGUMENT,
                   [&]
                   {
                     return addTree(function, forest, root_index, refinement, number_of_nodes,
                                    masked, storage_slots, absent);
                   });
  }

  int canopy_forest_add_field(canopy_forest* forest, const char* name, int value_type,
                              int components, const void* data, size_t tuple_stride_bytes,
                              size_t number_of_tuples, int centering)
  {
    static const char* const function = "canopy_forest_add_field";
    return guarded(
        function, CANOPY_INVALID_ARGUMENT,
        [&]
        {
          canopy::FieldDescription field;
          if (const int status = checkField(function, forest, name, value_type, components,
                                            number_of_tuples, centering, field))
          {
            return status;
          }
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
          forest->description.fields.push_back(std::move(field));
          return succeed();
        });
  }

  int canopy_forest_add_field_soa(canopy_forest* forest, const char* name, int value_type,
                                  int components, const void* const* component_data,
                                  size_t number_of_tuples, int centering)
  {
    static const char* const function = "canopy_forest_add_field_soa";
    return guarded(
        function, CANOPY_INVALID_ARGUMENT,
        [&]
        {
          canopy::FieldDescription field;
          if (const int status = checkField(function, forest, name, value_type, components,
                                            number_of_tuples, centering, field))
          {
            return status;
          }
          if (component_data == nullptr)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: field '%s': component_data is NULL", function,
                        name);
          }
          for (int c = 0; c < components; ++c)
          {
            if (component_data[c] == nullptr && number_of_tuples > 0)
            {
              return fail(CANOPY_INVALID_ARGUMENT,
                          "%s: field '%s': component %d's data is NULL but number_of_tuples is "
                          "%zu",
                          function, name, c, number_of_tuples);
            }
          }
          field.layout = canopy::Layout::SoA;
          field.componentData.assign(component_data, component_data + components);
          forest->description.fields.push_back(std::move(field));
          return succeed();
        });
  }

  int canopy_open(MPI_Comm communicator, const canopy_options* options, canopy_insitu** insitu)
  {
    static const char* const function = "canopy_open";
    return guarded(
        function, CANOPY_OPEN_FAILED,
        [&]
        {
          if (insitu == nullptr)
          {
            return fail(CANOPY_INVALID_ARGUMENT, "%s: the result pointer is NULL", function);
          }
          *insitu = nullptr;
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
    return guarded(function, CANOPY_STEP_FAILED,
                   [&]
                   {
                     if (insitu == nullptr)
                     {
                       return nullHandle(function, "insitu");
                     }
                     // Collective: asked even when the result pointer is NULL, so
                     // that the other ranks are not left waiting.
                     const bool will = insitu->driver->willExecute(step, time);
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
    static const char* const function = "canopy_execute";
    return guarded(function, CANOPY_STEP_FAILED,
                   [&]
                   {
                     if (insitu == nullptr)
                     {
                       return nullHandle(function, "insitu");
                     }
                     // Collective: a NULL forest still takes part (as an empty, invalid one) so
                     // that every rank skips the step together.
                     static const canopy::ForestDescription nothing{};
                     const auto report = insitu->driver->execute(
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
