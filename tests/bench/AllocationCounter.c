/* Counts the heap bytes a process allocates (malloc, calloc, realloc, the aligned
 * allocations; operator new goes through malloc), for benchmarks that compare the
 * memory two routes write: glibc's allocator does the work, this only adds up the
 * sizes asked for. Linked into the benchmark executable, whose definitions take
 * the place of glibc's for every library in the process. C, not C++: glibc
 * declares these with exception specifications C++ would have to repeat. */
#include <errno.h>
#include <stddef.h>

void* __libc_malloc(size_t size);
void* __libc_calloc(size_t count, size_t size);
void* __libc_realloc(void* pointer, size_t size);
void* __libc_memalign(size_t alignment, size_t size);
void __libc_free(void* pointer);

static unsigned long long allocated;

unsigned long long canopy_bench_allocated_bytes(void)
{
  return __atomic_load_n(&allocated, __ATOMIC_RELAXED);
}

static void count(size_t size)
{
  __atomic_fetch_add(&allocated, (unsigned long long)size, __ATOMIC_RELAXED);
}

void* malloc(size_t size)
{
  count(size);
  return __libc_malloc(size);
}

void* calloc(size_t count_, size_t size)
{
  count(count_ * size);
  return __libc_calloc(count_, size);
}

void* realloc(void* pointer, size_t size)
{
  count(size);
  return __libc_realloc(pointer, size);
}

void free(void* pointer)
{
  __libc_free(pointer);
}

void* memalign(size_t alignment, size_t size)
{
  count(size);
  return __libc_memalign(alignment, size);
}

void* aligned_alloc(size_t alignment, size_t size)
{
  count(size);
  return __libc_memalign(alignment, size);
}

int posix_memalign(void** out, size_t alignment, size_t size)
{
  count(size);
  void* pointer = __libc_memalign(alignment, size);
  if (pointer == NULL)
  {
    return ENOMEM;
  }
  *out = pointer;
  return 0;
}
