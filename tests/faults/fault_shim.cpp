// An LD_PRELOAD shim that makes the file system fail on cue, for the fault tests
// (tests/faults/faults.sh). It acts only on Snell's output temporaries (names
// holding ".snell-tmp-"), so reading the scene, loading libraries and writing to
// the terminal behave as usual. SNELL_FAULT chooses the fault:
//   write-eio     every write fails with EIO
//   short-writes  writes take at most 7 bytes at a time (and EINTR every other
//                 call): a correct writer still produces the whole file
//   fsync-eio     fsync fails with EIO (delayed write-back errors surface here)
//   close-eio     close fails with EIO after closing (NFS reports quota here)
//   rename-eio    rename of a temporary fails with EIO
//   sigterm       the first write raises SIGTERM (a signal in the write phase);
//   sigint        likewise SIGINT
// Limits: only the libc entry points Snell's writer uses (open, write, fsync,
// close, rename) are wrapped; calls libc makes internally are not seen.
#include <dlfcn.h>
#include <fcntl.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdarg>
#include <cstdlib>
#include <cstring>

namespace {

constexpr int kMaxFd = 4096;
std::atomic<bool> g_tracked[kMaxFd];
std::atomic<unsigned> g_calls{0};

bool is_temp(const char* path) {
  return path && std::strstr(path, ".snell-tmp-") != nullptr;
}
bool tracked(int fd) {
  return fd >= 0 && fd < kMaxFd && g_tracked[fd].load();
}
bool fault(const char* name) {
  const char* f = std::getenv("SNELL_FAULT");
  return f && std::strcmp(f, name) == 0;
}
template <class Fn>
Fn next(const char* name) {
  return reinterpret_cast<Fn>(dlsym(RTLD_NEXT, name));
}

int open_impl(const char* symbol, const char* path, int flags, mode_t mode) {
  using Open = int (*)(const char*, int, ...);
  static Open real_open = next<Open>("open");
  static Open real_open64 = next<Open>("open64");
  Open real = std::strcmp(symbol, "open64") == 0 ? real_open64 : real_open;
  int fd = real(path, flags, mode);
  if (fd >= 0 && fd < kMaxFd) g_tracked[fd].store(is_temp(path));
  return fd;
}

}  // namespace

extern "C" {

int open(const char* path, int flags, ...) {
  mode_t mode = 0;
  if (flags & (O_CREAT | O_TMPFILE)) {
    va_list ap;
    va_start(ap, flags);
    mode = mode_t(va_arg(ap, int));
    va_end(ap);
  }
  return open_impl("open", path, flags, mode);
}

int open64(const char* path, int flags, ...) {
  mode_t mode = 0;
  if (flags & (O_CREAT | O_TMPFILE)) {
    va_list ap;
    va_start(ap, flags);
    mode = mode_t(va_arg(ap, int));
    va_end(ap);
  }
  return open_impl("open64", path, flags, mode);
}

ssize_t write(int fd, const void* buf, size_t n) {
  using Write = ssize_t (*)(int, const void*, size_t);
  static Write real = next<Write>("write");
  if (tracked(fd)) {
    if (fault("write-eio")) {
      errno = EIO;
      return -1;
    }
    if (fault("sigterm")) raise(SIGTERM);
    if (fault("sigint")) raise(SIGINT);
    if (fault("short-writes")) {
      if (g_calls++ % 2 == 0) {
        errno = EINTR;
        return -1;
      }
      return real(fd, buf, n < 7 ? n : 7);
    }
  }
  return real(fd, buf, n);
}

int fsync(int fd) {
  using Fsync = int (*)(int);
  static Fsync real = next<Fsync>("fsync");
  if (tracked(fd) && fault("fsync-eio")) {
    errno = EIO;
    return -1;
  }
  return real(fd);
}

int close(int fd) {
  using Close = int (*)(int);
  static Close real = next<Close>("close");
  bool fail = tracked(fd) && fault("close-eio");
  if (fd >= 0 && fd < kMaxFd) g_tracked[fd].store(false);
  int rc = real(fd);
  if (fail) {
    errno = EIO;
    return -1;
  }
  return rc;
}

int rename(const char* from, const char* to) {
  using Rename = int (*)(const char*, const char*);
  static Rename real = next<Rename>("rename");
  if (is_temp(from) && fault("rename-eio")) {
    errno = EIO;
    return -1;
  }
  return real(from, to);
}

}  // extern "C"
