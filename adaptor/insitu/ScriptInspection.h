// What Canopy can tell about a Catalyst script before running it.
#pragma once

#include <string>

namespace canopy
{

/// Whether running the script needs an X display. A script (or, for a package
/// directory, any of its .py files) renders if it creates a view or an image
/// extractor: CreateView, GetActiveViewOrCreate, CreateRenderView, SaveScreenshot,
/// the 'PNG'/'JPG'/Cinema extractors, canopy_catalyst.render_view or
/// canopy_catalyst.ImageScript. A line
/// "# canopy-renders: yes" or "# canopy-renders: no" overrides the guess. A .zip
/// cannot be inspected and counts as rendering unless the caller knows better.
bool scriptRenders(const std::string& path);

/// Whether the path names something Catalyst can load: a readable file or a directory.
bool scriptReadable(const std::string& path, std::string& why);

} // namespace canopy
