// How every C API call ends: a status code, and its message in
// canopy_last_error(). No exception may leave a call (an unwinding through C
// frames would terminate the simulation), so each call's body runs guarded().
#pragma once

#include <canopy/canopy.h>

#include <new>
#include <stdexcept>

namespace canopy::capi
{

/// Records a printf-style message for canopy_last_error() (only %s, %d, %zu,
/// %lld...: glibc formats those without allocating) and returns `status`. Never
/// throws, never fails.
[[gnu::format(printf, 2, 3)]] int fail(int status, const char* format, ...) noexcept;

/// Clears the message and returns CANOPY_OK.
int succeed() noexcept;

/// "<function>: the <what> handle is NULL", CANOPY_INVALID_ARGUMENT.
int nullHandle(const char* function, const char* what) noexcept;

/// Runs a call's body; any exception becomes a status and a message.
/// `otherStatus` is the status for exceptions other than allocation failures.
template <typename Body>
int guarded(const char* function, int otherStatus, Body&& body) noexcept
{
  try
  {
    return body();
  }
  catch (const std::bad_alloc&)
  {
    return fail(CANOPY_OUT_OF_MEMORY, "%s: out of memory", function);
  }
  catch (const std::length_error&)
  {
    // A container asked for more than it can ever hold: an allocation failure too.
    return fail(CANOPY_OUT_OF_MEMORY, "%s: out of memory (a size beyond what can be allocated)",
                function);
  }
  catch (const std::exception& error)
  {
    return fail(otherStatus, "%s: %s", function, error.what());
  }
  catch (...)
  {
    return fail(otherStatus, "%s: unknown error", function);
  }
}

/// The body of a call on `handle`, guarded: a NULL handle is refused (named
/// `what`: "the <what> handle is NULL") before `body(*handle)` runs.
template <typename Handle, typename Body>
int onHandle(const char* function, int otherStatus, Handle* handle, const char* what,
             Body&& body) noexcept
{
  return guarded(function, otherStatus,
                 [&]
                 {
                   if (handle == nullptr)
                   {
                     return nullHandle(function, what);
                   }
                   return body(*handle);
                 });
}

/// The body of a call that creates a handle in `*result`, guarded: a NULL
/// `result` is refused, and `*result` is NULL (what a failed call leaves) before
/// `body()` runs.
template <typename Handle, typename Body>
int creating(const char* function, int otherStatus, Handle** result, Body&& body) noexcept
{
  return guarded(function, otherStatus,
                 [&]
                 {
                   if (result == nullptr)
                   {
                     return fail(CANOPY_INVALID_ARGUMENT, "%s: the result pointer is NULL",
                                 function);
                   }
                   *result = nullptr;
                   return body();
                 });
}

} // namespace canopy::capi
