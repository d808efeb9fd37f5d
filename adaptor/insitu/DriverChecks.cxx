#include "DriverChecks.h"

#include "CatalystSession.h"
#include "LiveConnection.h"
#include "ScriptInspection.h"
#include "ScriptSearch.h"

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <set>

namespace canopy
{

void requireUsableMpi(MPI_Comm communicator)
{
  int initialized = 0;
  MPI_Initialized(&initialized);
  int finalized = 0;
  MPI_Finalized(&finalized);
  if (!initialized || finalized)
  {
    throw InSituError("canopy::InSitu: MPI must be initialized (and not finalized) before open");
  }
  if (communicator == MPI_COMM_NULL)
  {
    throw InSituError("canopy::InSitu: the communicator is MPI_COMM_NULL");
  }
}

std::vector<std::string> normalizeAndCheckOptions(InSituOptions& options)
{
  std::vector<std::string> problems;
  const std::string session = CatalystSession::whyNotStartable();
  if (!session.empty())
  {
    problems.push_back(session);
  }
  if (options.scripts.empty())
  {
    problems.push_back("no pipeline script given");
  }
  if (options.channel.empty())
  {
    problems.push_back("the channel name is empty");
  }
  if (options.outputDirectory.empty())
  {
    problems.push_back("the output directory is empty");
  }
  if (!std::isfinite(options.stepTimeLimitSeconds) || options.stepTimeLimitSeconds < 0.0)
  {
    problems.push_back("the step time limit must be a finite number of seconds >= 0 (0: none)");
  }
  if (!options.liveUrl.empty())
  {
    LiveConnection::Settings live;
    std::string error;
    if (!LiveConnection::parseUrl(options.liveUrl, live, error))
    {
      problems.push_back(error);
    }
  }
  if (std::isnan(options.livePauseLimitSeconds))
  {
    problems.push_back("the Live pause limit must be a number of seconds (<= 0: none)");
  }
  if (!std::isfinite(options.liveStallSeconds) || options.liveStallSeconds <= 0.0)
  {
    problems.push_back("the Live stall limit must be a finite number of seconds > 0");
  }
  std::error_code ignored;
  options.outputDirectory = std::filesystem::absolute(options.outputDirectory, ignored).string();
  std::set<std::string> seen;
  for (auto& script : options.scripts)
  {
    // A relative path is also looked for among the pipelines (ScriptSearch.h).
    const ScriptLocation location = findScript(script.path);
    if (!location.found())
    {
      problems.push_back("pipeline script '" + script.path + "': " + location.notFoundReason());
      continue;
    }
    script.path = location.path;
    std::string why;
    if (!scriptReadable(script.path, why))
    {
      problems.push_back("pipeline script '" + script.path + "': " + why);
    }
    if (!seen.insert(script.path).second)
    {
      problems.push_back("pipeline script '" + script.path +
                         "' is given twice (copy it to run it with other arguments)");
    }
  }
  return problems;
}

std::string prepareOutputDirectory(const std::string& directory)
{
  std::error_code error;
  std::filesystem::create_directories(directory, error);
  if (!std::filesystem::is_directory(directory, error))
  {
    return "the output directory '" + directory + "' does not exist and cannot be created";
  }
  if (access(directory.c_str(), W_OK | X_OK) != 0)
  {
    return "the output directory '" + directory + "' is not writable";
  }
  return {};
}

} // namespace canopy
