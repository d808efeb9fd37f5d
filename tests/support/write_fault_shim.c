/* Write faults on demand, for any process, without privileges (LD_PRELOAD).
 *
 * Tests need a disk that fills up or fails in the middle of a run: mounting a
 * small tmpfs needs root, and a test that skips without it proves nothing on
 * most machines. This library stands between a process and libc for files
 * under one folder:
 *
 *   CANOPY_WRITE_FAULT_DIR      the folder (absolute); other files are untouched
 *   CANOPY_WRITE_FAULT_CONTROL  a file whose presence turns faults on; it holds
 *                               "ERRNO BYTES [statvfs]", e.g. "ENOSPC 24576 statvfs":
 *                               after BYTES more bytes written under the folder
 *                               (counted by this process since the control file
 *                               changed), writes fail with ERRNO (ENOSPC, EIO or
 *                               EFBIG); with "statvfs", statvfs/statfs of the folder
 *                               report what is left as the free space, as a disk
 *                               that is that full would. fsync fails with ERRNO once
 *                               the bytes are used up.
 *
 * Words after BYTES aim the fault at one kind of write (a disk that goes bad
 * there and stays bad: once one write has failed, every later one to the files
 * aimed at fails too):
 *   rank=R      only the process of MPI rank R (OMPI_COMM_WORLD_RANK, PMIX_RANK
 *               or PMI_RANK) has faults; the others write normally
 *   only=TEXT   only files whose path contains TEXT count and fail
 *   min=N       only writes of at least N bytes count (data, not metadata)
 *   overwrite   only writes into bytes the file had when it was opened count
 *               (a file format's metadata, rewritten in place)
 *   at=OFFSET   only writes covering byte OFFSET count (at=0: a header at the
 *               file's start, often written last, when the file is closed)
 *   skip=N      the first N writes aimed at succeed (a disk failing later)
 *   fsync       writes succeed; fsync and fdatasync fail (a disk whose errors
 *               show when the data is made durable)
 *
 * Writes are seen where libraries make them: write/pwrite/writev (libstdc++'s
 * streams, HDF5, MPI-IO) and fwrite (stdio, libpng), for descriptors and
 * streams opened under the folder by open/openat/creat/fopen. The budget is per
 * process (each MPI rank has its own).
 */
#define _GNU_SOURCE
#include <dlfcn.h>
#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <pthread.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <sys/statfs.h>
#include <sys/statvfs.h>
#include <sys/uio.h>
#include <unistd.h>

#define MAX_TRACKED_FD 65536

static pthread_mutex_t lock = PTHREAD_MUTEX_INITIALIZER;
static unsigned char tracked[MAX_TRACKED_FD]; /* fd -> opened under the folder */
static struct
{
  int known; /* the control file was read at this (inode, mtime, size) */
  ino_t inode;
  struct timespec mtime;
  off_t size;
  int active;     /* faults on */
  int error;      /* errno to fail with */
  long long left; /* bytes still allowed */
  int statvfs;    /* report `left` as the free space */
  int rank;       /* the only MPI rank with faults; -1: every process */
  char only[128]; /* only paths containing this count ("": all) */
  long long min;  /* only writes of at least this many bytes count */
  int overwrite;  /* only writes into a file's bytes at its opening count */
  int sync_only;  /* only fsync/fdatasync fail */
  long long at;   /* only writes covering this byte count (-1: any) */
  long long skip; /* aimed writes still to let through */
  int tripped;    /* a write has failed: every later one fails */
} fault;
static char* paths[MAX_TRACKED_FD];       /* fd -> its path, for only= */
static off_t opened_size[MAX_TRACKED_FD]; /* fd -> its size when opened, for overwrite */

/* This process's MPI rank, -1 when not started by an MPI launcher. */
static int mpi_rank(void)
{
  const char* names[] = {"OMPI_COMM_WORLD_RANK", "PMIX_RANK", "PMI_RANK"};
  for (size_t i = 0; i < sizeof names / sizeof names[0]; ++i)
  {
    const char* value = getenv(names[i]);
    if (value && *value)
      return atoi(value);
  }
  return -1;
}

static const char* folder(void)
{
  const char* dir = getenv("CANOPY_WRITE_FAULT_DIR");
  return dir && dir[0] == '/' ? dir : NULL;
}

/* Whether `path` (relative to the working directory unless absolute) lies
 * under the folder. */
static int under_folder(const char* path)
{
  const char* dir = folder();
  if (!dir || !path)
    return 0;
  char absolute[PATH_MAX];
  if (path[0] != '/')
  {
    if (!getcwd(absolute, sizeof absolute))
      return 0;
    size_t n = strlen(absolute);
    snprintf(absolute + n, sizeof absolute - n, "/%s", path);
    path = absolute;
  }
  size_t n = strlen(dir);
  while (n > 1 && dir[n - 1] == '/')
    --n;
  return strncmp(path, dir, n) == 0 && (path[n] == '/' || path[n] == '\0');
}

static int errno_named(const char* name)
{
  if (strcmp(name, "EIO") == 0)
    return EIO;
  if (strcmp(name, "EFBIG") == 0)
    return EFBIG;
  return ENOSPC;
}

/* Re-reads the control file when it appeared, changed or went away. Called
 * with the lock held. */
static void refresh(void)
{
  const char* control = getenv("CANOPY_WRITE_FAULT_CONTROL");
  struct stat st;
  static int (*real_stat)(const char*, struct stat*);
  if (!real_stat)
    real_stat = (int (*)(const char*, struct stat*))dlsym(RTLD_NEXT, "stat");
  if (!control || !real_stat || real_stat(control, &st) != 0)
  {
    fault.known = 0;
    fault.active = 0;
    return;
  }
  if (fault.known && st.st_ino == fault.inode && st.st_size == fault.size &&
      st.st_mtim.tv_sec == fault.mtime.tv_sec && st.st_mtim.tv_nsec == fault.mtime.tv_nsec)
    return;
  fault.known = 1;
  fault.inode = st.st_ino;
  fault.mtime = st.st_mtim;
  fault.size = st.st_size;
  fault.active = 0;
  static FILE* (*real_fopen)(const char*, const char*);
  if (!real_fopen)
    real_fopen = (FILE * (*)(const char*, const char*)) dlsym(RTLD_NEXT, "fopen");
  FILE* file = real_fopen ? real_fopen(control, "r") : NULL;
  if (!file)
    return;
  char name[16] = "";
  long long bytes = 0;
  const int read = fscanf(file, "%15s %lld", name, &bytes);
  fault.statvfs = 0;
  fault.rank = -1;
  fault.only[0] = '\0';
  fault.min = 0;
  fault.overwrite = 0;
  fault.sync_only = 0;
  fault.at = -1;
  fault.skip = 0;
  fault.tripped = 0;
  char word[120];
  while (read == 2 && fscanf(file, "%119s", word) == 1)
  {
    if (strcmp(word, "statvfs") == 0)
      fault.statvfs = 1;
    else if (strcmp(word, "overwrite") == 0)
      fault.overwrite = 1;
    else if (strcmp(word, "fsync") == 0)
      fault.sync_only = 1;
    else if (strncmp(word, "rank=", 5) == 0)
      fault.rank = atoi(word + 5);
    else if (strncmp(word, "min=", 4) == 0)
      fault.min = atoll(word + 4);
    else if (strncmp(word, "at=", 3) == 0)
      fault.at = atoll(word + 3);
    else if (strncmp(word, "skip=", 5) == 0)
      fault.skip = atoll(word + 5);
    else if (strncmp(word, "only=", 5) == 0)
      snprintf(fault.only, sizeof fault.only, "%s", word + 5);
  }
  fclose(file);
  if (read == 2 && (fault.rank < 0 || fault.rank == mpi_rank()))
  {
    fault.active = 1;
    fault.error = errno_named(name);
    fault.left = bytes < 0 ? 0 : bytes;
  }
}

/* Whether `fd`'s file is one the control file aims at (only=). Called with the
 * lock held. */
static int file_aimed_at(int fd)
{
  return !fault.only[0] || (paths[fd] && strstr(paths[fd], fault.only));
}

/* Whether a write of `count` bytes at `offset` (-1: unknown) to `fd` is of the
 * kind the control file aims at. Called with the lock held. */
static int aimed_at(int fd, size_t count, off_t offset)
{
  if ((long long)count < fault.min)
    return 0;
  if (fault.overwrite && !(offset >= 0 && offset < opened_size[fd]))
    return 0;
  if (fault.at >= 0 && !(offset >= 0 && offset <= fault.at && fault.at < offset + (off_t)count))
    return 0;
  if (fault.skip > 0)
  {
    --fault.skip;
    return 0;
  }
  return 1;
}

/* How many of `count` bytes to `fd` at `offset` (-1: unknown) may be written;
 * 0 with `refused` set: none. */
static size_t allowed(int fd, size_t count, off_t offset, int* refused)
{
  *refused = 0;
  if (fd < 0 || fd >= MAX_TRACKED_FD || !tracked[fd] || count == 0)
    return count;
  pthread_mutex_lock(&lock);
  refresh();
  size_t granted = count;
  if (fault.active && !fault.sync_only && file_aimed_at(fd) &&
      (fault.tripped || aimed_at(fd, count, offset)))
  {
    if (fault.tripped || fault.left <= 0)
    {
      granted = 0;
      *refused = fault.error;
      fault.tripped = 1;
    }
    else if ((long long)count > fault.left)
    {
      granted = (size_t)fault.left; /* a short write, then the error */
    }
    fault.left -= (long long)granted;
  }
  pthread_mutex_unlock(&lock);
  return granted;
}

static int tracked_fd(int fd)
{
  return fd >= 0 && fd < MAX_TRACKED_FD && tracked[fd];
}

/* Where the next write() to `fd` goes. */
static off_t position_of(int fd)
{
  return lseek(fd, 0, SEEK_CUR);
}

static void track(int fd, const char* path)
{
  if (fd < 0 || fd >= MAX_TRACKED_FD)
    return;
  pthread_mutex_lock(&lock);
  tracked[fd] = (unsigned char)under_folder(path);
  free(paths[fd]);
  paths[fd] = tracked[fd] ? strdup(path) : NULL;
  struct stat st;
  opened_size[fd] = tracked[fd] && fstat(fd, &st) == 0 ? st.st_size : 0;
  pthread_mutex_unlock(&lock);
}

/* The next definition of `name` (libc's), looked up once. */
#define REAL(name)                                                                                 \
  static __typeof__(name)* real_##name;                                                            \
  if (!real_##name)                                                                                \
  real_##name = (__typeof__(name)*)dlsym(RTLD_NEXT, #name)

/* ---- opening and closing ---- */

static mode_t mode_of(int flags, va_list args)
{
  return (flags & O_CREAT) || (flags & O_TMPFILE) == O_TMPFILE ? (mode_t)va_arg(args, int) : 0;
}

int open(const char* path, int flags, ...)
{
  REAL(open);
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_of(flags, args);
  va_end(args);
  const int fd = real_open(path, flags, mode);
  track(fd, path);
  return fd;
}

int open64(const char* path, int flags, ...)
{
  REAL(open64);
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_of(flags, args);
  va_end(args);
  const int fd = real_open64(path, flags, mode);
  track(fd, path);
  return fd;
}

int openat(int dirfd, const char* path, int flags, ...)
{
  REAL(openat);
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_of(flags, args);
  va_end(args);
  const int fd = real_openat(dirfd, path, flags, mode);
  track(fd, dirfd == AT_FDCWD || path[0] == '/' ? path : NULL);
  return fd;
}

int openat64(int dirfd, const char* path, int flags, ...)
{
  REAL(openat64);
  va_list args;
  va_start(args, flags);
  const mode_t mode = mode_of(flags, args);
  va_end(args);
  const int fd = real_openat64(dirfd, path, flags, mode);
  track(fd, dirfd == AT_FDCWD || path[0] == '/' ? path : NULL);
  return fd;
}

int creat(const char* path, mode_t mode)
{
  REAL(creat);
  const int fd = real_creat(path, mode);
  track(fd, path);
  return fd;
}

int creat64(const char* path, mode_t mode)
{
  REAL(creat64);
  const int fd = real_creat64(path, mode);
  track(fd, path);
  return fd;
}

FILE* fopen(const char* path, const char* mode)
{
  REAL(fopen);
  FILE* file = real_fopen(path, mode);
  if (file)
    track(fileno(file), path);
  return file;
}

FILE* fopen64(const char* path, const char* mode)
{
  REAL(fopen64);
  FILE* file = real_fopen64(path, mode);
  if (file)
    track(fileno(file), path);
  return file;
}

int close(int fd)
{
  REAL(close);
  if (fd >= 0 && fd < MAX_TRACKED_FD)
    tracked[fd] = 0;
  return real_close(fd);
}

int fclose(FILE* file)
{
  REAL(fclose);
  const int fd = file ? fileno(file) : -1;
  if (fd >= 0 && fd < MAX_TRACKED_FD)
    tracked[fd] = 0;
  return real_fclose(file);
}

/* ---- writing ---- */

ssize_t write(int fd, const void* data, size_t count)
{
  REAL(write);
  int refused;
  const size_t granted = allowed(fd, count, tracked_fd(fd) ? position_of(fd) : -1, &refused);
  if (refused)
  {
    errno = refused;
    return -1;
  }
  return real_write(fd, data, granted);
}

ssize_t pwrite(int fd, const void* data, size_t count, off_t offset)
{
  REAL(pwrite);
  int refused;
  const size_t granted = allowed(fd, count, offset, &refused);
  if (refused)
  {
    errno = refused;
    return -1;
  }
  return real_pwrite(fd, data, granted, offset);
}

ssize_t pwrite64(int fd, const void* data, size_t count, off64_t offset)
{
  REAL(pwrite64);
  int refused;
  const size_t granted = allowed(fd, count, (off_t)offset, &refused);
  if (refused)
  {
    errno = refused;
    return -1;
  }
  return real_pwrite64(fd, data, granted, offset);
}

/* Vectored writes: all or nothing, which callers handle as any failed write. */
static int vector_refused(int fd, const struct iovec* vector, int count, off_t offset)
{
  size_t total = 0;
  for (int i = 0; i < count; ++i)
    total += vector[i].iov_len;
  int refused;
  const size_t granted = allowed(fd, total, offset, &refused);
  if (!refused && granted < total)
    refused = fault.error;
  return refused;
}

ssize_t writev(int fd, const struct iovec* vector, int count)
{
  REAL(writev);
  const int refused = vector_refused(fd, vector, count, tracked_fd(fd) ? position_of(fd) : -1);
  if (refused)
  {
    errno = refused;
    return -1;
  }
  return real_writev(fd, vector, count);
}

ssize_t pwritev(int fd, const struct iovec* vector, int count, off_t offset)
{
  REAL(pwritev);
  const int refused = vector_refused(fd, vector, count, offset);
  if (refused)
  {
    errno = refused;
    return -1;
  }
  return real_pwritev(fd, vector, count, offset);
}

size_t fwrite(const void* data, size_t size, size_t items, FILE* file)
{
  REAL(fwrite);
  if (size == 0 || items == 0)
    return real_fwrite(data, size, items, file);
  int refused;
  const int fd = fileno(file);
  const size_t granted =
      allowed(fd, size * items, tracked_fd(fd) ? (off_t)ftello(file) : -1, &refused);
  if (refused || granted < size * items)
  {
    /* Whole items only, then the stream's error: what a full disk gives. */
    const size_t whole = refused ? 0 : granted / size;
    const size_t done = whole ? real_fwrite(data, size, whole, file) : 0;
    errno = refused ? refused : fault.error;
    return done;
  }
  return real_fwrite(data, size, items, file);
}

static int sync_refused(int fd)
{
  if (fd < 0 || fd >= MAX_TRACKED_FD || !tracked[fd])
    return 0;
  pthread_mutex_lock(&lock);
  refresh();
  if (!file_aimed_at(fd))
  {
    pthread_mutex_unlock(&lock);
    return 0;
  }
  /* An aimed fault makes fsync fail only once it has tripped (or when fsync is its aim). */
  const int aimed =
      fault.only[0] || fault.min > 0 || fault.overwrite || fault.at >= 0 || fault.skip > 0;
  const int refused =
      fault.active && (fault.sync_only || fault.tripped || (!aimed && fault.left <= 0))
          ? fault.error
          : 0;
  pthread_mutex_unlock(&lock);
  return refused;
}

int fsync(int fd)
{
  REAL(fsync);
  const int refused = sync_refused(fd);
  if (refused)
  {
    errno = refused;
    return -1;
  }
  return real_fsync(fd);
}

int fdatasync(int fd)
{
  REAL(fdatasync);
  const int refused = sync_refused(fd);
  if (refused)
  {
    errno = refused;
    return -1;
  }
  return real_fdatasync(fd);
}

/* ---- free space ---- */

/* The free bytes to report for `path`, or -1 to report the truth. */
static long long reported_free(const char* path)
{
  if (!under_folder(path))
    return -1;
  pthread_mutex_lock(&lock);
  refresh();
  const long long left = fault.active && fault.statvfs ? (fault.left > 0 ? fault.left : 0) : -1;
  pthread_mutex_unlock(&lock);
  return left;
}

int statvfs(const char* path, struct statvfs* out)
{
  REAL(statvfs);
  const int result = real_statvfs(path, out);
  const long long left = result == 0 ? reported_free(path) : -1;
  if (left >= 0 && out->f_frsize > 0)
    out->f_bavail = out->f_bfree = (fsblkcnt_t)(left / (long long)out->f_frsize);
  return result;
}

int statvfs64(const char* path, struct statvfs64* out)
{
  REAL(statvfs64);
  const int result = real_statvfs64(path, out);
  const long long left = result == 0 ? reported_free(path) : -1;
  if (left >= 0 && out->f_frsize > 0)
    out->f_bavail = out->f_bfree = (fsblkcnt64_t)(left / (long long)out->f_frsize);
  return result;
}

int statfs(const char* path, struct statfs* out)
{
  REAL(statfs);
  const int result = real_statfs(path, out);
  const long long left = result == 0 ? reported_free(path) : -1;
  if (left >= 0 && out->f_bsize > 0)
    out->f_bavail = out->f_bfree = (fsblkcnt_t)(left / (long long)out->f_bsize);
  return result;
}

int statfs64(const char* path, struct statfs64* out)
{
  REAL(statfs64);
  const int result = real_statfs64(path, out);
  const long long left = result == 0 ? reported_free(path) : -1;
  if (left >= 0 && out->f_bsize > 0)
    out->f_bavail = out->f_bfree = (fsblkcnt64_t)(left / (long long)out->f_bsize);
  return result;
}
