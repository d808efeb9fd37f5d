#include "DisplayProbe.h"

#include <X11/Xlib.h>

#include <cstdlib>

namespace canopy
{

bool xDisplayReachable(std::string& why)
{
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || *name == '\0')
  {
    why = "DISPLAY is not set";
    return false;
  }
  Display* display = XOpenDisplay(name);
  if (display == nullptr)
  {
    why = std::string("cannot open the X display '") + name + "'";
    return false;
  }
  XCloseDisplay(display);
  return true;
}

} // namespace canopy
