// What a rank holds, step after step: resident memory, heap in use and open
// file descriptors, one CSV line per step in a file of its own. The soak tests
// read it to see that nothing grows after warm-up (docs/testing.md, "Soak").
#pragma once

#include <fstream>
#include <string>

namespace miniamr
{

class ResourceLog
{
public:
  /// Writes `prefix`.<rank>.csv (the folder must exist); an empty prefix logs nothing.
  ResourceLog(const std::string& prefix, int rank);
  /// Appends `step`'s line: step, the rank's leaves (what its memory follows),
  /// resident KiB, heap KiB in use, open descriptors.
  void record(int step, long long leaves);

private:
  std::ofstream Out;
};

} // namespace miniamr
