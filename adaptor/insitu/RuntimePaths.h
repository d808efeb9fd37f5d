// Where Canopy's runtime companions are: the ParaView plugin that pipeline
// scripts load, and the pipelines folder with the canopy_catalyst helper module.
// Both are found next to the library itself, so the build tree and an install
// work without configuration; environment variables override.
#pragma once

#include <string>

namespace canopy
{

/// CANOPY_PLUGIN if set; else <libdir>/canopy-plugins/CanopyPlugin/CanopyPlugin.so.
std::string pluginPath();

/// CANOPY_PIPELINES_DIR if set (and not empty); else shippedPipelinesDirectory().
std::string pipelinesDirectory();

/// The pipelines shipped with Canopy, whatever CANOPY_PIPELINES_DIR says:
/// <datadir>/canopy/pipelines of the prefix the library is installed in; else
/// the source tree's pipelines/ (build tree).
std::string shippedPipelinesDirectory();

} // namespace canopy
