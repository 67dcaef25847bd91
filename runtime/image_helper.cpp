// The image helper process (image_helper.hpp), on a socket pair or a connection
// to the resident image server (image_server.hpp); the protocol is image_wire.hpp's.
// The child ends at end of file.
#include "runtime/image_helper.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <poll.h>
#include <signal.h>
#include <sys/prctl.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <mutex>

#include "runtime/image_server.hpp"
#include "runtime/image_wire.hpp"
#include "runtime/render.hpp"

namespace snell::rt {

namespace {

using image_wire::Wire;

// The child: load, say how that went, then encode until end of file; at its
// run's goodbye, stay as the resident server (image_server.hpp).
[[noreturn]] void serve(int sock, pid_t parent, const std::optional<DisplayView>& check_display) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(0);  // the parent died before the prctl
  // Off the terminal: a test reading the parent's stderr to its end must not
  // wait for the child, and nothing the encoder prints could reach the user.
  if (int null = ::open("/dev/null", O_RDWR); null >= 0) {
    for (int fd = 0; fd <= 2; ++fd) ::dup2(null, fd);
    if (null > 2) ::close(null);
  }
  // Whatever else the run had open is not the helper's to hold (a server would
  // hold it for minutes); the libraries the load opens come after.
  if (sock > 3) ::close_range(3, unsigned(sock) - 1, 0);
  ::close_range(unsigned(sock) + 1, ~0u, 0);
  std::uint32_t kind = image_wire::kReady;
  std::string message = preload_image_writer();
  if (!message.empty()) {
    kind = image_wire::kLoadError;
  } else if (check_display) {
    message = check_display_transform(*check_display);
    if (!message.empty()) kind = image_wire::kDisplayError;
  }
  if (!image_wire::send_status(sock, kind, message) || kind == image_wire::kLoadError) ::_exit(0);
  if (!image_wire::serve_requests(sock)) ::_exit(0);
  // The goodbye: no longer the run's to die with, said before the run may end.
  ::prctl(PR_SET_PDEATHSIG, 0);
  bool said = image_wire::send_message(sock, Wire{});
  ::close(sock);
  if (!said) ::_exit(0);
  become_image_server();
}

struct Helper {
  std::mutex mutex;
  bool engaged = false;   // started and not stopped: writes go through it, even once it died
  bool resident = false;  // connected to the resident server (no child of ours)
  pid_t pid = -1;
  int sock = -1;
  std::optional<ImageHelperStatus> status;

  // How the child ended, reaped (for a message): "it exited with status 1", ...
  std::string reap() {
    if (pid < 0) return "it was not running";
    int ws = 0;
    pid_t r;
    do r = ::waitpid(pid, &ws, 0);
    while (r < 0 && errno == EINTR);
    pid = -1;
    if (r < 0) return "it could not be waited for";
    if (WIFSIGNALED(ws)) return fmt::format("it was ended by signal {}", WTERMSIG(ws));
    return fmt::format("it exited with status {}", WEXITSTATUS(ws));
  }
  void close_socket() {
    if (sock >= 0) ::close(sock);
    sock = -1;
  }
  // The child ended or broke the protocol. Later writes report this too rather
  // than load the module here: that would cost the load again, and an encoder
  // that crashed there could crash this process the same way.
  void failed(const char* what) {
    close_socket();
    if (resident) {
      status = ImageHelperStatus{
          fmt::format("the resident image server {} (it closed the connection)", what), {}};
      return;
    }
    std::string how = reap();
    status = ImageHelperStatus{fmt::format("the image helper {} ({})", what, how), {}};
  }
  // Takes a status message (false: a broken one).
  bool take_status(Wire& w) {
    auto kind = w.get<std::uint32_t>();
    std::string message = w.get_string();
    if (w.bad) return false;
    ImageHelperStatus s;
    (kind == image_wire::kDisplayError ? s.display_error : s.load_error) = std::move(message);
    status = std::move(s);
    return true;
  }
  // Reads the status message; with `wait` false only when one is there.
  void read_status(bool wait) {
    if (status || sock < 0) return;
    if (!wait) {
      pollfd p{sock, POLLIN, 0};
      if (::poll(&p, 1, 0) <= 0) return;
    }
    Wire w;
    if (!image_wire::recv_message(sock, w)) return failed("ended while loading");
    if (!take_status(w)) failed("sent a broken status");
  }
};

Helper& helper() {
  static Helper h;
  return h;
}

}  // namespace

void start_image_helper(const std::optional<DisplayView>& check_display) {
  Helper& h = helper();
  std::lock_guard lock(h.mutex);
  if (h.engaged) return;
  if (const char* env = std::getenv("SNELL_IMAGE_HELPER"); env && std::strcmp(env, "0") == 0)
    return;
  // A resident server that answers saves this run the module's load.
  Wire status;
  if (int fd = connect_image_server(check_display, status); fd >= 0) {
    h.resident = true;
    h.sock = fd;
    h.status.reset();
    if (h.take_status(status)) {
      h.engaged = true;
      return;
    }
    h.close_socket();
    h.resident = false;
    h.status.reset();
  }
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) return;
  // Above 2: a run started with a standard stream closed would get the socket as
  // one, and the child points 0-2 at /dev/null.
  for (int& fd : fds)
    if (fd <= 2) {
      int high = ::fcntl(fd, F_DUPFD_CLOEXEC, 3);
      ::close(fd);
      fd = high;
    }
  if (fds[0] < 0 || fds[1] < 0) {
    for (int fd : fds)
      if (fd >= 0) ::close(fd);
    return;
  }
  pid_t parent = ::getpid();
  pid_t pid = ::fork();
  if (pid < 0) {
    ::close(fds[0]);
    ::close(fds[1]);
    return;
  }
  if (pid == 0) {
    ::close(fds[0]);
    serve(fds[1], parent, check_display);
  }
  ::close(fds[1]);
  h.engaged = true;
  h.resident = false;
  h.pid = pid;
  h.sock = fds[0];
  h.status.reset();
}

std::string image_writer_kind() {
  Helper& h = helper();
  std::lock_guard lock(h.mutex);
  if (!h.engaged) return "this process";
  return h.resident ? "the resident image server" : "a helper process";
}

bool image_helper_running() {
  Helper& h = helper();
  std::lock_guard lock(h.mutex);
  return h.engaged;
}

std::optional<ImageHelperStatus> image_helper_status(bool wait) {
  Helper& h = helper();
  std::lock_guard lock(h.mutex);
  if (!h.engaged) return ImageHelperStatus{"the image helper is not running", {}};
  h.read_status(wait);
  return h.status;
}

void stop_image_helper(bool leave_resident) {
  Helper& h = helper();
  std::lock_guard lock(h.mutex);
  h.engaged = false;
  // A child that loaded stays as the resident server when it answers the goodbye
  // at once; one still loading is killed (a run that wrote nothing must not wait
  // for it). Not reaped: it is no longer ours to wait for.
  if (leave_resident && h.pid >= 0 && h.sock >= 0 && !image_server_socket().empty()) {
    h.read_status(false);
    if (!h.status || h.status->load_error.empty()) {
      Wire in;
      pollfd p{h.sock, POLLIN, 0};
      if (image_wire::send_message(h.sock, Wire{}) && ::poll(&p, 1, 50) > 0 &&
          image_wire::recv_message(h.sock, in) && in.bytes.empty()) {
        h.close_socket();
        h.pid = -1;
      }
    }
  }
  h.status.reset();
  h.close_socket();
  if (h.pid < 0) return;
  ::kill(h.pid, SIGKILL);
  h.reap();
}

std::string image_helper_encode(const std::string& path, const Image& image, const OutputInfo& info,
                                const DisplayView& display, std::vector<unsigned char>& bytes) {
  Helper& h = helper();
  std::lock_guard lock(h.mutex);
  h.read_status(true);
  if (!h.status) return fmt::format("cannot write {}: the image helper is not running", path);
  if (!h.status->load_error.empty())
    return fmt::format("cannot write {}: {}", path, h.status->load_error);
  if (h.sock < 0) return fmt::format("cannot write {}: the image helper is not running", path);
  Wire out;
  image_wire::put_request(out, path, image, info, display);
  Wire in;
  if (!image_wire::send_message(h.sock, out) || !image_wire::recv_message(h.sock, in)) {
    h.failed("ended while encoding");
    return fmt::format("cannot write {}: {}", path, h.status->load_error);
  }
  std::string error = in.get_string();
  auto n = in.get<std::uint64_t>();
  if (in.bad || n != in.bytes.size() - in.at) {
    h.failed("sent a broken reply");
    return fmt::format("cannot write {}: {}", path, h.status->load_error);
  }
  if (!error.empty()) return error;
  bytes.assign(in.bytes.begin() + std::ptrdiff_t(in.at), in.bytes.end());
  return {};
}

}  // namespace snell::rt
