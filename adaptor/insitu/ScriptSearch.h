// Where a pipeline script named in InSituOptions::scripts is: an absolute path
// as given; a relative one in the working directory, then CANOPY_PIPELINES_DIR,
// then the pipelines shipped with Canopy, so that a bare "surface_image.py"
// works from any working directory.
#pragma once

#include <string>
#include <vector>

namespace canopy
{

struct ScriptLocation
{
  /// The script's absolute, normalized path; empty when it was not found.
  std::string path;
  /// The candidates looked at, in search order, up to the one found (absolute paths).
  std::vector<std::string> searched;

  bool found() const { return !this->path.empty(); }
  /// Why the script was not found, naming every place searched.
  std::string notFoundReason() const;
};

/// The first existing candidate (a file or a package directory); readability is
/// the caller's check. A relative CANOPY_PIPELINES_DIR counts from the working
/// directory; an empty one is ignored.
ScriptLocation findScript(const std::string& path);

} // namespace canopy
