// The errors and warnings VTK and ParaView log while a script runs. Writers
// report a full disk or a file they cannot open only this way (never through a
// return value), so Canopy turns them into the script's failure.
#pragma once

#include <mutex>
#include <string>
#include <vector>

namespace canopy
{

class VtkMessageCapture
{
public:
  /// Starts collecting (vtkLogger messages of WARNING or ERROR verbosity, from
  /// any thread; they are still printed as before).
  VtkMessageCapture();
  /// Stops collecting.
  ~VtkMessageCapture();
  VtkMessageCapture(const VtkMessageCapture&) = delete;
  VtkMessageCapture& operator=(const VtkMessageCapture&) = delete;

  /// The messages so far, oldest first.
  std::vector<std::string> messages() const;

private:
  std::string Id;
  mutable std::mutex Mutex;
  std::vector<std::string> Messages;
};

} // namespace canopy
