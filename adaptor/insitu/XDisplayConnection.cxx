#include "XDisplayConnection.h"

#include <X11/Xlib.h>

#include <cstdlib>

namespace canopy
{

XDisplayConnection::XDisplayConnection()
{
  const char* name = std::getenv("DISPLAY");
  if (name == nullptr || *name == '\0')
  {
    this->Why = "DISPLAY is not set";
    return;
  }
  this->Display = XOpenDisplay(name);
  if (this->Display == nullptr)
  {
    this->Why = std::string("cannot open the X display '") + name + "'";
  }
}

XDisplayConnection::~XDisplayConnection()
{
  if (this->Display != nullptr)
  {
    XCloseDisplay(static_cast<::Display*>(this->Display));
  }
}

} // namespace canopy
