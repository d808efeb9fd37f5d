#include "ScriptSearch.h"

#include "RuntimePaths.h"

#include <cstdlib>
#include <filesystem>

namespace canopy
{

std::string ScriptLocation::notFoundReason() const
{
  if (this->searched.empty())
  {
    return "the path is empty";
  }
  if (this->searched.size() == 1)
  {
    return "no such file or directory";
  }
  std::string places;
  for (const auto& candidate : this->searched)
  {
    places += (places.empty() ? "" : ", ") + candidate;
  }
  return "no such file or directory; looked for " + places;
}

ScriptLocation findScript(const std::string& path)
{
  namespace fs = std::filesystem;
  ScriptLocation location;
  if (path.empty())
  {
    return location; // absolute("") would be the working directory itself
  }
  std::error_code error;
  std::vector<fs::path> candidates;
  const fs::path given(path);
  if (given.is_absolute())
  {
    candidates.push_back(given);
  }
  else
  {
    candidates.push_back(fs::absolute(given, error));
    const char* fromEnvironment = std::getenv("CANOPY_PIPELINES_DIR");
    if (fromEnvironment != nullptr && *fromEnvironment != '\0')
    {
      candidates.push_back(fs::absolute(fs::path(fromEnvironment) / given, error));
    }
    candidates.push_back(fs::path(shippedPipelinesDirectory()) / given);
  }
  for (const auto& candidate : candidates)
  {
    location.searched.push_back(candidate.lexically_normal().string());
    if (fs::exists(candidate, error))
    {
      location.path = location.searched.back();
      break;
    }
  }
  return location;
}

} // namespace canopy
