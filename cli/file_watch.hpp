// snell watch's view of the files a scene reads: inotify on their folders, not on
// the files, because editors save by writing a new file and renaming it over the
// old one (vim, VS Code, sed -i), which ends a watch on the old file's inode.
#pragma once

#include <chrono>
#include <map>
#include <set>
#include <string>
#include <vector>

namespace snell::cli {

class FileWatch {
 public:
  FileWatch();
  ~FileWatch();
  FileWatch(const FileWatch&) = delete;
  FileWatch& operator=(const FileWatch&) = delete;

  // Empty when inotify works; else why not (the watcher then polls the files'
  // times, as it does when none of their folders exists).
  const std::string& error() const { return error_; }

  // The files to watch from now on (any path; made absolute here). With
  // `any_in_folders`, every change in their folders counts: after a failed
  // compile, the import or mesh that was missing may be the file that appears.
  void set_files(const std::vector<std::string>& files, bool any_in_folders);

  // Waits up to `timeout` for a change to a watched file; true when one came.
  // Changes are debounced: after the first, events are gathered until `quiet` has
  // passed without one (an editor's save is several events: write, rename, chmod).
  bool wait(std::chrono::milliseconds timeout,
            std::chrono::milliseconds quiet = std::chrono::milliseconds(60));

 private:
  bool read_events(int timeout_ms);  // true when a relevant event arrived
  bool poll_mtimes();

  int fd_ = -1;
  std::string error_;
  std::map<int, std::string> folders_;       // watch descriptor -> folder
  std::set<std::string> files_;              // absolute paths
  std::map<std::string, long long> mtimes_;  // the polling fallback
  bool any_ = false;
};

}  // namespace snell::cli
