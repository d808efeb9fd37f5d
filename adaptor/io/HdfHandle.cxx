#include "HdfHandle.h"

#include <vector>

namespace canopy::io
{
namespace
{

herr_t collect(unsigned int, const H5E_error2_t* error, void* data)
{
  auto* messages = static_cast<std::vector<std::string>*>(data);
  if (error->desc != nullptr && *error->desc != '\0')
  {
    messages->emplace_back(error->desc);
  }
  return 0;
}

} // namespace

std::string hdfErrorText()
{
  std::vector<std::string> messages;
  // Downward: from the API call to the innermost cause (e.g. the system's error).
  H5Ewalk2(H5E_DEFAULT, H5E_WALK_DOWNWARD, collect, &messages);
  H5Eclear2(H5E_DEFAULT);
  if (messages.empty())
  {
    return {};
  }
  std::string text = messages.back();
  if (messages.size() > 1 && messages[messages.size() - 2] != text)
  {
    text = messages[messages.size() - 2] + ": " + text;
  }
  return text;
}

} // namespace canopy::io
