// A planted leak, for showing that the sanitizer runs report leaks in code of
// this project reached the way Canopy's filters and writers are: from a
// pipeline script (Python calls it, here through ctypes). Built only in the
// sanitizer build; loaded by tests/sanitizers/leaking_script.py. A suppression
// list naming Python's library as a whole hides it (docs/testing.md,
// "Suppressions").
#include <cstring>

namespace
{

// Each allocation's only pointer is overwritten: lost for good.
char* volatile Dropped = nullptr;

} // namespace

extern "C"
{
  /// Leaks `bytes` bytes now.
  void canopy_leak_probe_leak(int bytes)
  {
    Dropped = new char[static_cast<unsigned>(bytes)];
    std::memset(Dropped, 1, static_cast<unsigned>(bytes));
    Dropped = nullptr;
  }
}
