// Whether this process can render: Debian's ParaView is built for X only, and
// creating a render window without an X display aborts the process.
#pragma once

#include <string>

namespace canopy
{

/// True when an X display can be opened. Otherwise `why` says what is missing
/// (DISPLAY unset, or the server it names does not answer).
bool xDisplayReachable(std::string& why);

} // namespace canopy
