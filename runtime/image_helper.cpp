// The image helper process (image_helper.hpp). The protocol, on a socket pair,
// all integers in this machine's order (both ends are the same binary):
//   child -> parent, once loaded:  u32 kind (0 ready, 1 load error, 2 display
//                                  error), string message
//   parent -> child, per image:    string path, Image, OutputInfo, DisplayView
//   child -> parent, per image:    string error, bytes encoded
// where a string or byte run is a u64 length and its bytes. The child ends at
// end of file; the parent's sends never raise SIGPIPE (MSG_NOSIGNAL), so a child
// that died is an error message, not the end of the render.
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

#include "runtime/render.hpp"

namespace snell::rt {

namespace {

// A message being built or read back.
struct Wire {
  std::vector<unsigned char> bytes;
  std::size_t at = 0;
  bool bad = false;  // a read ran past the end

  void put(const void* p, std::size_t n) {
    const auto* b = static_cast<const unsigned char*>(p);
    bytes.insert(bytes.end(), b, b + n);
  }
  template <class T>
  void put(const T& v) {
    put(&v, sizeof v);
  }
  void put_string(const std::string& s) {
    put(std::uint64_t(s.size()));
    put(s.data(), s.size());
  }
  bool get(void* p, std::size_t n) {
    if (bad || bytes.size() - at < n) return !(bad = true);
    if (n) std::memcpy(p, bytes.data() + at, n);
    at += n;
    return true;
  }
  template <class T>
  T get() {
    T v{};
    get(&v, sizeof v);
    return v;
  }
  std::string get_string() {
    auto n = get<std::uint64_t>();
    if (bad || bytes.size() - at < n) return bad = true, std::string();
    std::string s(reinterpret_cast<const char*>(bytes.data() + at), n);
    at += n;
    return s;
  }
};

bool send_all(int fd, const void* p, std::size_t n) {
  const auto* b = static_cast<const unsigned char*>(p);
  while (n > 0) {
    ssize_t k = ::send(fd, b, n, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    b += k;
    n -= std::size_t(k);
  }
  return true;
}

bool recv_all(int fd, void* p, std::size_t n) {
  auto* b = static_cast<unsigned char*>(p);
  while (n > 0) {
    ssize_t k = ::recv(fd, b, n, 0);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    b += k;
    n -= std::size_t(k);
  }
  return true;
}

// One message: its length, then its bytes.
bool send_message(int fd, const Wire& w) {
  std::uint64_t n = w.bytes.size();
  return send_all(fd, &n, sizeof n) && send_all(fd, w.bytes.data(), w.bytes.size());
}
bool recv_message(int fd, Wire& w) {
  std::uint64_t n = 0;
  if (!recv_all(fd, &n, sizeof n)) return false;
  // A length no image of this process could have is a broken stream, not an
  // allocation to attempt.
  if (n > (std::uint64_t(1) << 40)) return false;
  w.bytes.resize(n);
  w.at = 0;
  return recv_all(fd, w.bytes.data(), n);
}

void put_request(Wire& w, const std::string& path, const Image& image, const OutputInfo& info,
                 const DisplayView& display) {
  w.put_string(path);
  for (std::uint32_t v :
       {image.width, image.height, image.x0, image.y0, image.full_width, image.full_height})
    w.put(v);
  w.put(std::uint64_t(image.rgb.size()));
  w.put(image.rgb.data(), image.rgb.size() * sizeof(float));
  w.put_string(info.scene_path);
  w.put(info.samples);
  w.put(info.seed);
  w.put(info.render_seconds);
  w.put(std::uint64_t(info.attributes.size()));
  for (const auto& [k, v] : info.attributes) {
    w.put_string(k);
    w.put_string(v);
  }
  w.put_string(display.config);
  w.put_string(display.display);
  w.put_string(display.view);
}

bool get_request(Wire& w, std::string& path, Image& image, OutputInfo& info, DisplayView& display) {
  path = w.get_string();
  for (std::uint32_t* v :
       {&image.width, &image.height, &image.x0, &image.y0, &image.full_width, &image.full_height})
    *v = w.get<std::uint32_t>();
  auto n = w.get<std::uint64_t>();
  if (w.bad || n > (w.bytes.size() - w.at) / sizeof(float)) return false;
  image.rgb.resize(n);
  w.get(image.rgb.data(), n * sizeof(float));
  info.scene_path = w.get_string();
  info.samples = w.get<std::uint32_t>();
  info.seed = w.get<std::uint64_t>();
  info.render_seconds = w.get<double>();
  auto attributes = w.get<std::uint64_t>();
  for (std::uint64_t i = 0; i < attributes && !w.bad; ++i) {
    std::string k = w.get_string();
    info.attributes.emplace_back(std::move(k), w.get_string());
  }
  display.config = w.get_string();
  display.display = w.get_string();
  display.view = w.get_string();
  return !w.bad;
}

// The child: load, say how that went, then encode until end of file.
[[noreturn]] void serve(int sock, pid_t parent, const std::optional<DisplayView>& check_display) {
  ::prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (::getppid() != parent) ::_exit(0);  // the parent died before the prctl
  // Off the terminal: a test reading the parent's stderr to its end must not
  // wait for the child, and nothing the encoder prints could reach the user.
  if (int null = ::open("/dev/null", O_RDWR); null >= 0) {
    for (int fd = 0; fd <= 2; ++fd) ::dup2(null, fd);
    if (null > 2) ::close(null);
  }
  Wire status;
  std::uint32_t kind = 0;
  std::string message = preload_image_writer();
  if (!message.empty()) {
    kind = 1;
  } else if (check_display) {
    message = check_display_transform(*check_display);
    if (!message.empty()) kind = 2;
  }
  status.put(kind);
  status.put_string(message);
  if (!send_message(sock, status) || kind != 0) ::_exit(0);
  for (Wire in; recv_message(sock, in);) {
    std::string path;
    Image image;
    OutputInfo info;
    DisplayView display;
    std::vector<unsigned char> bytes;
    std::string error = get_request(in, path, image, info, display)
                            ? encode_image_here(path, image, info, display, bytes)
                            : "a request to the image helper was cut short";
    Wire out;
    out.put_string(error);
    out.put(std::uint64_t(bytes.size()));
    out.put(bytes.data(), bytes.size());
    if (!send_message(sock, out)) break;
    in = Wire{};
  }
  ::_exit(0);
}

struct Helper {
  std::mutex mutex;
  bool engaged = false;  // started and not stopped: writes go through it, even once it died
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
    std::string how = reap();
    status = ImageHelperStatus{fmt::format("the image helper {} ({})", what, how), {}};
  }
  // Reads the status message; with `wait` false only when one is there.
  void read_status(bool wait) {
    if (status || sock < 0) return;
    if (!wait) {
      pollfd p{sock, POLLIN, 0};
      if (::poll(&p, 1, 0) <= 0) return;
    }
    Wire w;
    if (!recv_message(sock, w)) return failed("ended while loading");
    auto kind = w.get<std::uint32_t>();
    std::string message = w.get_string();
    if (w.bad) return failed("sent a broken status");
    ImageHelperStatus s;
    (kind == 2 ? s.display_error : s.load_error) = std::move(message);
    status = std::move(s);
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
  int fds[2];
  if (::socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, fds) != 0) return;
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
  h.pid = pid;
  h.sock = fds[0];
  h.status.reset();
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

void stop_image_helper() {
  Helper& h = helper();
  std::lock_guard lock(h.mutex);
  h.engaged = false;
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
  put_request(out, path, image, info, display);
  Wire in;
  if (!send_message(h.sock, out) || !recv_message(h.sock, in)) {
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
