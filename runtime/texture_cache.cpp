#include "runtime/texture_cache.hpp"

#include <fmt/format.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <vector>

namespace snell::rt {

namespace fs = std::filesystem;

fs::path texture_cache_dir(std::string& error) {
  fs::path dir;
  if (const char* set = std::getenv("SNELL_TEXTURE_CACHE"); set && *set) {
    dir = set;
  } else {
    const char* tmp = std::getenv("TMPDIR");
    dir = fs::path(tmp && *tmp ? tmp : "/tmp") / fmt::format("snell-textures-{}", ::getuid());
  }
  // mkdir, not create_directories: its mode is set as it is made (no window in
  // which another user could open it), and an existing one is checked below.
  std::error_code ec;
  fs::create_directories(dir.parent_path(), ec);
  if (::mkdir(dir.c_str(), 0700) != 0 && errno != EEXIST) {
    error = fmt::format("cannot make the texture cache folder {}: {}", dir.string(),
                        std::strerror(errno));
    return {};
  }
  struct stat st {};
  if (::lstat(dir.c_str(), &st) != 0) {
    error = fmt::format("cannot read the texture cache folder {}: {}", dir.string(),
                        std::strerror(errno));
    return {};
  }
  const char* why = !S_ISDIR(st.st_mode)      ? "it is not a folder (a link or a file)"
                    : st.st_uid != ::getuid() ? "another user owns it"
                    : (st.st_mode & 022) != 0 ? "other users can write to it"
                                              : nullptr;
  if (why) {
    error = fmt::format(
        "the texture cache folder {} is not safe to use: {} (remove it, or set "
        "SNELL_TEXTURE_CACHE to a folder of your own)",
        dir.string(), why);
    return {};
  }
  return dir;
}

std::uint64_t texture_cache_max_bytes() {
  std::uint64_t mb = 2048;
  if (const char* set = std::getenv("SNELL_TEXTURE_CACHE_MB"); set && *set) {
    char* end = nullptr;
    const unsigned long long v = std::strtoull(set, &end, 10);
    if (end && *end == '\0') mb = v;
  }
  return mb * 1024 * 1024;
}

void texture_cache_touch(const fs::path& file) {
  std::error_code ec;
  fs::last_write_time(file, fs::file_time_type::clock::now(), ec);
}

namespace {
// Whether the process named in a partial file's name ".KEY-PID..." (KEY 16 hex
// digits) is gone; false when the name is not of that form.
bool writer_gone(const std::string& name) {
  if (name.size() < 19 || name[0] != '.' || name[17] != '-') return false;
  long pid = 0;
  std::size_t i = 18;
  for (; i < name.size() && std::isdigit(static_cast<unsigned char>(name[i])); ++i)
    pid = pid * 10 + (name[i] - '0');
  if (i == 18 || pid <= 0 || pid > 4194304) return false;
  return ::kill(pid_t(pid), 0) != 0 && errno == ESRCH;
}
}  // namespace

void texture_cache_prune(const fs::path& dir, std::uint64_t max_bytes, std::chrono::seconds grace,
                         const fs::path& keep) {
  struct Entry {
    fs::path path;
    fs::file_time_type used;
    std::uint64_t size;
  };
  std::vector<Entry> files;
  std::uint64_t total = 0;
  const auto now = fs::file_time_type::clock::now();
  std::error_code ec;
  for (fs::directory_iterator it(dir, ec), end; !ec && it != end; it.increment(ec)) {
    const fs::path& p = it->path();
    if (p.extension() != ".tx" || !it->is_regular_file(ec)) continue;
    const auto used = it->last_write_time(ec);
    if (ec) continue;
    const std::uint64_t size = it->file_size(ec);
    if (ec) continue;
    if (p.filename().string().front() == '.') {  // a partial file (texture_io.cpp)
      // Removed once a day old, or at once when the process writing it is gone (a
      // ^C while a big image decoded left hundreds of MB, uncounted, for a day):
      // its name is ".KEY-PID..." (OIIO's own temporary adds to it), and a file
      // untouched for a minute whose PID is no process is no one's.
      std::error_code rm;
      if (now - used > std::chrono::hours(24) ||
          (now - used > std::chrono::minutes(1) && writer_gone(p.filename().string())))
        fs::remove(p, rm);
      continue;
    }
    total += size;
    files.push_back({p, used, size});
  }
  if (total <= max_bytes) return;
  std::sort(files.begin(), files.end(),
            [](const Entry& a, const Entry& b) { return a.used < b.used; });
  for (const Entry& f : files) {
    if (total <= max_bytes) break;
    if (f.path == keep || now - f.used < grace) continue;
    std::error_code rm;
    if (fs::remove(f.path, rm)) total -= f.size;
  }
}

}  // namespace snell::rt
