#include "VtkMessageCapture.h"

#include <vtkLogger.h>

#include <atomic>

namespace canopy
{
namespace
{

std::atomic<unsigned long> captures{0};

} // namespace

VtkMessageCapture::VtkMessageCapture() : Id("canopy-capture-" + std::to_string(++captures))
{
  vtkLogger::AddCallback(
      this->Id.c_str(),
      [](void* self, const vtkLogger::Message& message)
      {
        auto& capture = *static_cast<VtkMessageCapture*>(self);
        std::lock_guard<std::mutex> lock(capture.Mutex);
        capture.Messages.emplace_back(message.message ? message.message : "");
      },
      this, vtkLogger::VERBOSITY_WARNING);
}

VtkMessageCapture::~VtkMessageCapture()
{
  vtkLogger::RemoveCallback(this->Id.c_str());
}

std::vector<std::string> VtkMessageCapture::messages() const
{
  std::lock_guard<std::mutex> lock(this->Mutex);
  return this->Messages;
}

} // namespace canopy
