#include "RuntimePaths.h"

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>

namespace canopy
{
namespace
{

std::filesystem::path libraryDirectory()
{
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&libraryDirectory), &info) == 0 || info.dli_fname == nullptr)
  {
    return {};
  }
  return std::filesystem::path(info.dli_fname).parent_path();
}

} // namespace

std::string pluginPath()
{
  if (const char* fromEnvironment = std::getenv("CANOPY_PLUGIN"))
  {
    return fromEnvironment;
  }
  return (libraryDirectory() / "canopy-plugins" / "CanopyPlugin" / "CanopyPlugin.so").string();
}

std::string pipelinesDirectory()
{
  // Empty counts as unset, as in findScript().
  const char* fromEnvironment = std::getenv("CANOPY_PIPELINES_DIR");
  if (fromEnvironment != nullptr && *fromEnvironment != '\0')
  {
    return fromEnvironment;
  }
  return shippedPipelinesDirectory();
}

std::string shippedPipelinesDirectory()
{
  const auto installed = (libraryDirectory() / CANOPY_PIPELINES_FROM_LIBDIR).lexically_normal();
  std::error_code error;
  if (std::filesystem::exists(installed / "canopy_catalyst.py", error))
  {
    return installed.string();
  }
  return CANOPY_SOURCE_PIPELINES_DIR;
}

} // namespace canopy
