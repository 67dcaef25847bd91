#include "runtime/atomic_file.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstring>
#include <filesystem>

namespace snell::rt {

namespace fs = std::filesystem;

namespace {

// The temporaries being written now, for the signal handler. A fixed table of
// fixed buffers: the handler may only read memory that is never reallocated, and
// only call async-signal-safe functions (unlink). More writes at once than slots
// still work; their temporaries are just not removed on a signal.
constexpr int kSlots = 32;
struct Slot {
  std::atomic<bool> taken{false};  // owned by a writer
  std::atomic<bool> live{false};   // `path` is complete and names a temporary
  char path[4096];
};
Slot g_slots[kSlots];

Slot* claim_slot(const std::string& path) {
  if (path.size() >= sizeof(Slot::path)) return nullptr;
  for (Slot& s : g_slots) {
    bool expected = false;
    if (s.taken.compare_exchange_strong(expected, true)) {
      std::memcpy(s.path, path.c_str(), path.size() + 1);
      s.live.store(true);
      return &s;
    }
  }
  return nullptr;
}

void release_slot(Slot* s) {
  if (!s) return;
  s->live.store(false);
  s->taken.store(false);
}

extern "C" void remove_temporaries_and_die(int sig) {
  for (Slot& s : g_slots)
    if (s.live.load()) ::unlink(s.path);
  // SA_RESETHAND restored the default action: the signal raised again ends the
  // process (at once, or when this handler returns if the kernel blocks it here).
  ::raise(sig);
}

std::string temp_name(const fs::path& target) {
  static std::atomic<unsigned> counter{0};
  const std::string file = target.filename().string();
  std::string name = fmt::format(".{}.snell-tmp-{}-{}", file, ::getpid(), counter++);
  // A name of 236..255 bytes is legal, but its temporary one would not be (255
  // bytes a name on Linux file systems): then the temporary takes a prefix of it.
  constexpr std::size_t kNameMax = 255;
  if (name.size() > kNameMax) {
    const std::string tail = name.substr(1 + file.size());  // ".snell-tmp-PID-N"
    std::size_t keep = kNameMax - 1 - tail.size();
    // Cut on a UTF-8 character boundary, not inside a multi-byte sequence.
    while (keep > 0 && (static_cast<unsigned char>(file[keep]) & 0xC0) == 0x80) --keep;
    name = "." + file.substr(0, keep) + tail;
  }
  return (target.parent_path() / name).string();
}

}  // namespace

std::string write_target(const std::string& path) {
  fs::path p = path;
  // 40: the kernel's own limit on links followed in one lookup (ELOOP).
  for (int i = 0; i < 40; ++i) {
    std::error_code ec;
    if (!fs::is_symlink(fs::symlink_status(p, ec))) return p.string();
    fs::path link = fs::read_symlink(p, ec);
    if (ec) return p.string();
    p = link.is_absolute() ? link : p.parent_path() / link;
  }
  return path;
}

std::string write_file_atomically(const std::string& path, const void* data, std::size_t size) {
  const fs::path target = write_target(path);
  auto fail = [&](const std::string& why) { return fmt::format("cannot write {}: {}", path, why); };
  struct stat old {};
  const bool had = ::stat(target.c_str(), &old) == 0;
  if (had && !S_ISREG(old.st_mode)) return fail("it exists and is not a regular file");

  const std::string tmp = temp_name(target);
  Slot* slot = claim_slot(tmp);  // before the file exists: a signal from here on removes it
  int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, had ? 0600 : 0666);
  auto fail_errno = [&](const char* step) {
    std::string why = fmt::format("{} ({})", std::strerror(errno), step);
    if (fd >= 0) ::close(fd);
    ::unlink(tmp.c_str());
    release_slot(slot);
    return fail(why);
  };
  if (fd < 0) return fail_errno("creating a temporary file beside it");
  if (had) {
    if (::fchmod(fd, old.st_mode & 07777) != 0) return fail_errno("keeping its mode");
    // Only root may give a file away; for anyone else the new file is theirs.
    if (::geteuid() == 0) (void)!::fchown(fd, old.st_uid, old.st_gid);
  }
  const char* p = static_cast<const char*>(data);
  std::size_t left = size;
  while (left > 0) {
    // Chunks of at most 1 GiB: Linux writes at most 0x7ffff000 bytes per call.
    ssize_t n = ::write(fd, p, std::min<std::size_t>(left, std::size_t(1) << 30));
    if (n < 0) {
      if (errno == EINTR) continue;
      return fail_errno("writing");
    }
    if (n == 0) {
      errno = ENOSPC;
      return fail_errno("writing");
    }
    p += n;
    left -= std::size_t(n);
  }
  if (::fsync(fd) != 0) return fail_errno("flushing to disk");
  int rc = ::close(fd);
  fd = -1;
  if (rc != 0) return fail_errno("closing");
  if (::rename(tmp.c_str(), target.c_str()) != 0) return fail_errno("renaming into place");
  release_slot(slot);
  // The rename is durable once the folder is synced. The file is whole either way;
  // a folder that cannot be synced (some network file systems) is not an error.
  fs::path dir = target.parent_path();
  int dfd = ::open(dir.empty() ? "." : dir.c_str(), O_RDONLY | O_DIRECTORY | O_CLOEXEC);
  if (dfd >= 0) {
    (void)::fsync(dfd);
    ::close(dfd);
  }
  return {};
}

void remove_temporaries_on_signals() {
  struct sigaction sa {};
  sa.sa_handler = remove_temporaries_and_die;
  sigemptyset(&sa.sa_mask);
  sa.sa_flags = SA_RESETHAND;
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) {
    struct sigaction prev {};
    // A signal the parent set to be ignored (nohup, a shell's background job)
    // stays ignored.
    if (::sigaction(sig, nullptr, &prev) == 0 && prev.sa_handler == SIG_IGN) continue;
    ::sigaction(sig, &sa, nullptr);
  }
  // A file-size limit (ulimit -f) is an I/O error, not a signal: with SIGXFSZ's
  // default the write killed the process (exit 153) and left the temporary; ignored,
  // the write fails with EFBIG, the temporary is removed, the old file kept, exit 3.
  ::signal(SIGXFSZ, SIG_IGN);
}

}  // namespace snell::rt
