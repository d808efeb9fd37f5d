#include "FreshMemory.h"

#include <sys/mman.h>

#include <cstdint>
#include <cstdlib>
#include <new>

namespace canopy
{

void adviseHugePages(void* data, std::size_t bytes)
{
  constexpr std::uintptr_t hugePage = std::uintptr_t(2) << 20;
  const auto begin = reinterpret_cast<std::uintptr_t>(data);
  const std::uintptr_t first = (begin + hugePage - 1) & ~(hugePage - 1);
  const std::uintptr_t last = (begin + bytes) & ~(hugePage - 1);
#ifdef MADV_HUGEPAGE
  if (data != nullptr && last > first)
  {
    // Advice only: an error (no THP support) leaves ordinary pages.
    madvise(reinterpret_cast<void*>(first), last - first, MADV_HUGEPAGE);
  }
#endif
}

void* allocateFreshMemory(std::size_t bytes)
{
  constexpr std::size_t hugePage = std::size_t(2) << 20;
  void* memory = nullptr;
  if (bytes >= hugePage / 2)
  {
    const std::size_t rounded = (bytes + hugePage - 1) / hugePage * hugePage;
    memory = std::aligned_alloc(hugePage, rounded);
    adviseHugePages(memory, rounded);
  }
  else
  {
    memory = std::malloc(bytes == 0 ? 1 : bytes);
  }
  if (memory == nullptr)
  {
    throw std::bad_alloc();
  }
  return memory;
}

void releaseFreshMemory(void* memory) noexcept
{
  std::free(memory);
}

} // namespace canopy
