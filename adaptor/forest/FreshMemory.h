// Large tables filled right after they are allocated.
//
// The first write to each fresh 4 KiB page costs a page fault, and on virtual
// machines such faults are slow: filling a fresh 39 MB int64 table here took
// 350 ms (72 ns per entry), the same table in transparent huge pages 38 ms
// (tests/bench/canopy_bench_wrap's slot-map rows; docs/benchmarks.md). Linux
// gives huge pages only to memory advised so (its default THP mode is
// "madvise"), hence this allocator.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

namespace canopy
{

/// Advises the kernel to back the 2 MiB-aligned part of [data, data + bytes) with
/// huge pages. Does nothing for small ranges or where unsupported; never fails.
void adviseHugePages(void* data, std::size_t bytes);

/// Memory for `bytes`: from 1 MiB up, 2 MiB-aligned and advised for huge pages
/// (rounded up to whole huge pages), below that plain malloc. Throws
/// std::bad_alloc. Release with releaseFreshMemory.
void* allocateFreshMemory(std::size_t bytes);
void releaseFreshMemory(void* memory) noexcept;

/// A std::allocator for tables filled right after allocation (see above).
template <typename T>
struct FreshMemoryAllocator
{
  using value_type = T;
  FreshMemoryAllocator() = default;
  template <typename U>
  FreshMemoryAllocator(const FreshMemoryAllocator<U>&) noexcept
  {
  }
  T* allocate(std::size_t n) { return static_cast<T*>(allocateFreshMemory(n * sizeof(T))); }
  void deallocate(T* p, std::size_t) noexcept { releaseFreshMemory(p); }
  template <typename U>
  bool operator==(const FreshMemoryAllocator<U>&) const noexcept
  {
    return true;
  }
  template <typename U>
  bool operator!=(const FreshMemoryAllocator<U>&) const noexcept
  {
    return false;
  }
};

/// Cell -> slot or tuple tables, one entry per cell of a grid.
using IndexTable = std::vector<std::int64_t, FreshMemoryAllocator<std::int64_t>>;

} // namespace canopy
