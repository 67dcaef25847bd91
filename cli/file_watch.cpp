#include "cli/file_watch.hpp"

#include <poll.h>
#include <sys/inotify.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <thread>

namespace snell::cli {

namespace fs = std::filesystem;

namespace {
// Events that mean a file's content may differ: written and closed, moved in or
// out (a rename-save), created, deleted, its attributes changed (touch).
constexpr std::uint32_t kMask = IN_CLOSE_WRITE | IN_MOVED_TO | IN_MOVED_FROM | IN_CREATE |
                                IN_DELETE | IN_ATTRIB | IN_DELETE_SELF | IN_MOVE_SELF;

std::string absolute(const std::string& path) {
  std::error_code ec;
  fs::path p = fs::absolute(path, ec);
  if (ec) return path;
  return p.lexically_normal().string();
}

long long mtime_of(const std::string& path) {
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0) return -1;
  return (long long)st.st_mtim.tv_sec * 1000000000LL + st.st_mtim.tv_nsec + st.st_size;
}
}  // namespace

FileWatch::FileWatch() {
  fd_ = inotify_init1(IN_NONBLOCK | IN_CLOEXEC);
  if (fd_ < 0)
    error_ = std::string("inotify: ") + std::strerror(errno) + "; checking the files every 0.5 s";
}

FileWatch::~FileWatch() {
  if (fd_ >= 0) ::close(fd_);
}

void FileWatch::set_files(const std::vector<std::string>& files, bool any_in_folders) {
  files_.clear();
  mtimes_.clear();
  any_ = any_in_folders;
  std::set<std::string> folders;
  for (const std::string& f : files) {
    std::string a = absolute(f);
    files_.insert(a);
    mtimes_[a] = mtime_of(a);
    folders.insert(fs::path(a).parent_path().string());
  }
  if (fd_ < 0) return;
  // Watches on folders no longer needed are dropped; inotify_add_watch on a
  // folder already watched returns its descriptor again.
  std::map<int, std::string> kept;
  for (const std::string& d : folders) {
    int wd = inotify_add_watch(fd_, d.c_str(), kMask);
    if (wd >= 0) kept[wd] = d;
  }
  for (const auto& [wd, d] : folders_)
    if (!kept.count(wd)) inotify_rm_watch(fd_, wd);
  folders_ = std::move(kept);
}

bool FileWatch::read_events(int timeout_ms) {
  pollfd p{fd_, POLLIN, 0};
  int n = ::poll(&p, 1, timeout_ms);
  if (n <= 0) return false;
  bool relevant = false;
  alignas(inotify_event) char buf[16384];
  for (;;) {
    ssize_t len = ::read(fd_, buf, sizeof buf);
    if (len <= 0) break;
    for (char* at = buf; at < buf + len;) {
      const auto* ev = reinterpret_cast<const inotify_event*>(at);
      at += sizeof(inotify_event) + ev->len;
      if (ev->mask & IN_Q_OVERFLOW) {  // events were lost: assume the worst
        relevant = true;
        continue;
      }
      auto it = folders_.find(ev->wd);
      if (it == folders_.end() || ev->len == 0) continue;
      std::string path = (fs::path(it->second) / ev->name).string();
      if (any_ || files_.count(path)) relevant = true;
    }
  }
  return relevant;
}

bool FileWatch::poll_mtimes() {
  bool changed = false;
  for (auto& [path, t] : mtimes_) {
    long long now = mtime_of(path);
    if (now != t) {
      t = now;
      changed = true;
    }
  }
  return changed;
}

bool FileWatch::wait(std::chrono::milliseconds timeout, std::chrono::milliseconds quiet) {
  using Clock = std::chrono::steady_clock;
  // Polling, coarse but never blind: without inotify, or when no folder could be
  // watched (the scene's folder does not exist yet).
  if (fd_ < 0 || folders_.empty()) {
    auto end = Clock::now() + timeout;
    do {
      if (poll_mtimes()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(std::min<long>(500, timeout.count())));
    } while (Clock::now() < end);
    return false;
  }
  if (!read_events(int(timeout.count()))) return false;
  // Debounce, but never for more than a second: a file written continuously
  // still gets rendered.
  auto give_up = Clock::now() + std::chrono::seconds(1);
  while (Clock::now() < give_up && read_events(int(quiet.count()))) {
  }
  return true;
}

}  // namespace snell::cli
