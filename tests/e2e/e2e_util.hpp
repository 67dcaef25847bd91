// What the end-to-end tests share: the snell program under test, a scratch folder
// per test, and running snell as a user does.
#pragma once

#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

namespace snell::e2e {

namespace fs = std::filesystem;

inline const std::string kSnell = SNELL_EXE;
inline const std::string kSrc = SNELL_SOURCE_DIR;
inline const std::string kShowcase = kSrc + "/examples/showcase.scn";

// A folder of its own (by process: one Scratch of a prefix at a time), removed
// with everything in it at the end of the test.
struct Scratch {
  fs::path dir;
  explicit Scratch(const std::string& prefix = "snell_e2e_") {
    dir = fs::temp_directory_path() / (prefix + std::to_string(::getpid()));
    fs::create_directories(dir);
  }
  ~Scratch() { fs::remove_all(dir); }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  std::string operator/(const std::string& name) const { return (dir / name).string(); }
};

// Runs snell with `args` (a shell command line's words), its stdout and stderr to
// `log`, and returns its exit code (-1 if it did not exit).
inline int run(const std::string& args, const std::string& log = "/dev/null") {
  int status = std::system((kSnell + " " + args + " > " + log + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

inline std::string slurp(const std::string& path) {
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), {});
}

// Runs snell (under timeout: none of these may block) and returns its exit code,
// with what it printed on stderr in `err`.
inline int run_capture(const std::string& args, std::string& err, const Scratch& tmp) {
  const std::string log = tmp / "stderr.txt";
  int status =
      std::system(("timeout 20 " + kSnell + " " + args + " > /dev/null 2> " + log).c_str());
  err = slurp(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

}  // namespace snell::e2e
