#include "CApiStatus.h"

#include <cstdarg>
#include <cstddef>
#include <cstdio>
#include <cstdlib>

namespace canopy::capi
{
namespace
{

/// This thread's last message. Plain data on purpose: a thread_local std::string
/// registers its destructor on first use, and glibc aborts the process when that
/// registration cannot allocate, which is exactly when an out-of-memory error is
/// reported. The malloc'ed text lives as long as the thread.
struct LastError
{
  char* text;
  std::size_t capacity;
  /// Used when `text` cannot grow: the message, truncated if need be.
  char brief[192];
  bool useBrief;
};
thread_local LastError lastError{};

} // namespace

int fail(int status, const char* format, ...) noexcept
{
  std::va_list arguments;
  va_start(arguments, format);
  std::va_list measuring;
  va_copy(measuring, arguments);
  const int length = std::vsnprintf(nullptr, 0, format, measuring);
  va_end(measuring);
  const std::size_t needed = length > 0 ? static_cast<std::size_t>(length) + 1 : 1;
  if (needed > lastError.capacity)
  {
    if (auto* grown = static_cast<char*>(std::realloc(lastError.text, needed)))
    {
      lastError.text = grown;
      lastError.capacity = needed;
    }
  }
  if (needed <= lastError.capacity)
  {
    std::vsnprintf(lastError.text, lastError.capacity, format, arguments);
    lastError.useBrief = false;
  }
  else
  {
    std::vsnprintf(lastError.brief, sizeof lastError.brief, format, arguments);
    lastError.useBrief = true;
  }
  va_end(arguments);
  return status;
}

int succeed() noexcept
{
  if (lastError.text != nullptr)
  {
    lastError.text[0] = '\0';
  }
  lastError.useBrief = false;
  return CANOPY_OK;
}

int nullHandle(const char* function, const char* what) noexcept
{
  return fail(CANOPY_INVALID_ARGUMENT, "%s: the %s handle is NULL", function, what);
}

} // namespace canopy::capi

extern "C" const char* canopy_last_error(void)
{
  using canopy::capi::lastError;
  if (lastError.useBrief)
  {
    return lastError.brief;
  }
  return lastError.text != nullptr ? lastError.text : "";
}
