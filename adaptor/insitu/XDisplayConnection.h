// The X display connection the driver holds, which also tells whether this
// process can render: Debian's ParaView is built for X only, and creating a
// render window without an X display aborts the process.
#pragma once

#include <memory>
#include <string>

namespace canopy
{

/// An open connection to the X display, held while Canopy runs pipelines: an X
/// server such as xvfb-run's resets when its last client disconnects, and a
/// render window opened during that reset finds no server (and aborts).
class XDisplayConnection
{
public:
  /// Connects to $DISPLAY. On failure, connected() is false and why() says what
  /// is missing (DISPLAY unset, or the server it names does not answer).
  XDisplayConnection();
  ~XDisplayConnection();
  XDisplayConnection(const XDisplayConnection&) = delete;
  XDisplayConnection& operator=(const XDisplayConnection&) = delete;

  bool connected() const { return Display != nullptr; }
  const std::string& why() const { return Why; }

private:
  void* Display = nullptr;
  std::string Why;
};

} // namespace canopy
