// What a rank holds, step after step (see ResourceLog.h).
#include "ResourceLog.h"

#include <dirent.h>
#include <malloc.h>
#include <unistd.h>

#include <cstdio>

namespace miniamr
{
namespace
{

/// Resident memory in KiB, from /proc/self/statm (its second field, in pages).
long long residentKiB()
{
  long long size = 0;
  long long resident = 0;
  std::FILE* statm = std::fopen("/proc/self/statm", "r");
  if (statm == nullptr)
    return -1;
  const int read = std::fscanf(statm, "%lld %lld", &size, &resident);
  std::fclose(statm);
  return read == 2 ? resident * (sysconf(_SC_PAGESIZE) / 1024) : -1;
}

/// Open file descriptors: entries of /proc/self/fd, less the one reading it.
int openDescriptors()
{
  DIR* fds = opendir("/proc/self/fd");
  if (fds == nullptr)
    return -1;
  int count = 0;
  while (const dirent* entry = readdir(fds))
    count += entry->d_name[0] != '.';
  closedir(fds);
  return count - 1;
}

} // namespace

ResourceLog::ResourceLog(const std::string& prefix, int rank)
{
  if (!prefix.empty())
  {
    Out.open(prefix + "." + std::to_string(rank) + ".csv");
    Out << "step,leaves,resident_kib,heap_kib,descriptors\n";
  }
}

void ResourceLog::record(int step, long long leaves)
{
  if (!Out.is_open())
    return;
  const struct mallinfo2 heap = mallinfo2();
  Out << step << "," << leaves << "," << residentKiB() << ","
      << (heap.uordblks + heap.hblkhd) / 1024 << "," << openDescriptors() << "\n";
  Out.flush();
}

} // namespace miniamr
