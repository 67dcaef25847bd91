#include "runtime/image_server.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/un.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <thread>

#include "runtime/image_helper.hpp"
#include "runtime/render.hpp"

extern char** environ;

namespace snell::rt {

namespace {

using image_wire::Wire;

bool server_off() {
  for (const char* name : {"SNELL_IMAGE_SERVER", "SNELL_IMAGE_HELPER"})
    if (const char* env = std::getenv(name); env && std::strcmp(env, "0") == 0) return true;
  return false;
}

// The socket's directory, made if missing; empty unless it is this user's own
// directory that no one else may enter.
std::string server_dir() {
  std::string dir;
  if (const char* env = std::getenv("SNELL_IMAGE_SERVER_DIR"); env && *env)
    dir = env;
  else if (const char* run = std::getenv("XDG_RUNTIME_DIR"); run && *run)
    dir = std::string(run) + "/snell";
  else
    dir = fmt::format("/tmp/snell-{}", ::getuid());
  ::mkdir(dir.c_str(), 0700);
  struct stat st {};
  if (::lstat(dir.c_str(), &st) != 0 || !S_ISDIR(st.st_mode) || st.st_uid != ::getuid() ||
      (st.st_mode & 077) != 0)
    return {};
  return dir;
}

// FNV-1a, 64 bits: a name, not a secret (the directory is private).
struct Fnv {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void add(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ b[i]) * 0x100000001b3ull;
  }
  void add(const std::string& s) { add(s.data(), s.size() + 1); }
};

bool shapes_encoding(const char* var) {
  for (const char* prefix : {"OCIO", "OPENIMAGEIO", "OIIO", "OPENEXR", "LD_", "SNELL_"})
    if (std::strncmp(var, prefix, std::strlen(prefix)) == 0)
      return std::strncmp(var, "SNELL_IMAGE_", 12) != 0;
  return false;
}

double idle_seconds() {
  if (const char* env = std::getenv("SNELL_IMAGE_SERVER_IDLE"); env && *env) {
    char* end = nullptr;
    double s = std::strtod(env, &end);
    if (end && *end == 0 && s > 0 && s < 1e7) return s;
  }
  return 300;
}

bool fill_address(const std::string& path, sockaddr_un& a) {
  a = {};
  a.sun_family = AF_UNIX;
  if (path.size() >= sizeof a.sun_path) return false;
  std::memcpy(a.sun_path, path.c_str(), path.size() + 1);
  return true;
}

// The server: a connection's thread per client, one encoding at a time.
struct Server {
  std::string path;
  ino_t ino = 0;
  int listener = -1;
  std::mutex encode;
  std::atomic<int> active{0};
  std::atomic<std::int64_t> last_ns{0};

  static std::int64_t now_ns() {
    return std::chrono::duration_cast<std::chrono::nanoseconds>(
               std::chrono::steady_clock::now().time_since_epoch())
        .count();
  }
  // Whether the socket name is still this server's (a newer one renames over it).
  bool owns_name() const {
    struct stat st {};
    return ::stat(path.c_str(), &st) == 0 && st.st_ino == ino;
  }
  // hello: u32 whether to check a display, then its config, display and view.
  void connection(int fd) {
    Wire hello;
    if (image_wire::recv_message(fd, hello)) {
      auto check = hello.get<std::uint32_t>();
      DisplayView dv;
      dv.config = hello.get_string();
      dv.display = hello.get_string();
      dv.view = hello.get_string();
      if (!hello.bad) {
        std::string message;
        if (check) {
          std::lock_guard lock(encode);
          message = check_display_transform(dv);
        }
        if (image_wire::send_status(
                fd, message.empty() ? image_wire::kReady : image_wire::kDisplayError, message) &&
            image_wire::serve_requests(fd, &encode))
          image_wire::send_message(fd, Wire{});  // a goodbye: the server stays anyway
      }
    }
    ::close(fd);
    last_ns = now_ns();
    --active;
  }
  [[noreturn]] void run() {
    const auto idle_ns = std::int64_t(idle_seconds() * 1e9);
    last_ns = now_ns();
    for (;;) {
      pollfd p{listener, POLLIN, 0};
      int r = ::poll(&p, 1, 500);
      if (r > 0) {
        int fd = ::accept4(listener, nullptr, nullptr, SOCK_CLOEXEC);
        if (fd >= 0) {
          ucred cred{};
          socklen_t len = sizeof cred;
          if (::getsockopt(fd, SOL_SOCKET, SO_PEERCRED, &cred, &len) != 0 ||
              cred.uid != ::getuid()) {
            ::close(fd);
            continue;
          }
          ++active;
          last_ns = now_ns();
          try {
            std::thread([this, fd] { connection(fd); }).detach();
          } catch (const std::exception&) {  // no thread to be had: this client starts its own
            ::close(fd);
            --active;
          }
        }
        continue;
      }
      if (active.load() > 0) continue;
      bool ours = owns_name();
      if (ours && now_ns() - last_ns.load() < idle_ns) continue;
      // Closed before the name goes: a client that connected meanwhile is reset,
      // not left waiting, and starts a helper of its own.
      ::close(listener);
      if (ours) ::unlink(path.c_str());
      ::_exit(0);
    }
  }
};

// Binds under a name of its own, then renames it to `path`: a server that two
// runs start at once ends up as one name, and the other's server, no longer
// reachable, ends (Server::owns_name).
[[noreturn]] void become_server(const std::string& path) {
  Server s;
  s.path = path;
  std::string temp = fmt::format("{}.{}", path, ::getpid());
  sockaddr_un a{};
  s.listener = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (s.listener < 0 || !fill_address(temp, a)) ::_exit(0);
  ::unlink(temp.c_str());
  if (::bind(s.listener, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
      ::listen(s.listener, 64) != 0) {
    ::unlink(temp.c_str());
    ::_exit(0);
  }
  struct stat st {};
  if (::stat(temp.c_str(), &st) != 0 || ::rename(temp.c_str(), path.c_str()) != 0) {
    ::unlink(temp.c_str());
    ::_exit(0);
  }
  s.ino = st.st_ino;
  s.run();
}

}  // namespace

std::string image_server_socket() {
  if (server_off()) return {};
  std::string dir = server_dir();
  if (dir.empty()) return {};
  Fnv f;
  std::error_code ec;
  std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
  if (ec) return {};
  struct stat st {};
  if (::stat("/proc/self/exe", &st) != 0) return {};
  f.add(exe.string());
  auto add_file = [&](const struct stat& s) {
    for (auto v : {std::uint64_t(s.st_dev), std::uint64_t(s.st_ino), std::uint64_t(s.st_size),
                   std::uint64_t(s.st_mtim.tv_sec), std::uint64_t(s.st_mtim.tv_nsec)})
      f.add(&v, sizeof v);
  };
  add_file(st);
  // The image module is built apart from the binary (image_module.cpp's paths).
  for (const char* module : {SNELL_IMAGE_IO_BUILD_MODULE, SNELL_IMAGE_IO_INSTALL_MODULE}) {
    struct stat ms {};
    f.add(std::string(module));
    if (::stat(module, &ms) == 0) add_file(ms);
  }
  for (char** e = environ; e && *e; ++e)
    if (shapes_encoding(*e)) f.add(std::string(*e));
  std::string path = fmt::format("{}/image-{:016x}.sock", dir, f.h);
  sockaddr_un a{};
  return fill_address(path, a) ? path : std::string();
}

int connect_image_server(const std::optional<DisplayView>& check_display, Wire& status) {
  // Its working directory is not ours: a relative config would name another file.
  if (check_display && !check_display->config.empty() && check_display->config[0] != '/') return -1;
  std::string path = image_server_socket();
  sockaddr_un a{};
  if (path.empty() || !fill_address(path, a)) return -1;
  int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0);
  if (fd < 0) return -1;
  auto fail = [&] {
    ::close(fd);
    return -1;
  };
  if (::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0) return fail();
  Wire hello;
  DisplayView dv = check_display.value_or(DisplayView{});
  hello.put(std::uint32_t(check_display ? 1 : 0));
  hello.put_string(dv.config);
  hello.put_string(dv.display);
  hello.put_string(dv.view);
  if (!image_wire::send_message(fd, hello)) return fail();
  // A server that is ending resets the connection; one that hangs is not waited
  // for longer than the load it would save.
  pollfd p{fd, POLLIN, 0};
  int r;
  do r = ::poll(&p, 1, 1000);
  while (r < 0 && errno == EINTR);
  if (r <= 0 || !image_wire::recv_message(fd, status)) return fail();
  return fd;
}

void become_image_server() {
  std::string path = image_server_socket();
  if (path.empty()) ::_exit(0);
  // One answers already (started by a run beside this one): it serves.
  sockaddr_un a{};
  if (int fd = ::socket(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0); fd >= 0) {
    bool there =
        fill_address(path, a) && ::connect(fd, reinterpret_cast<sockaddr*>(&a), sizeof a) == 0;
    ::close(fd);
    if (there) ::_exit(0);
  }
  // A session of its own: no terminal's signals reach it. The handlers the run
  // had when it forked the helper are the run's, not the server's.
  ::setsid();
  ::prctl(PR_SET_NAME, "snell-images");  // what ps -o comm and top show
  for (int sig : {SIGINT, SIGTERM, SIGHUP, SIGQUIT, SIGUSR1, SIGUSR2}) ::signal(sig, SIG_DFL);
  ::signal(SIGPIPE, SIG_IGN);
  if (::chdir("/") != 0) ::_exit(0);
  become_server(path);
}

}  // namespace snell::rt
