#include "runtime/image_wire.hpp"

#include <sys/socket.h>

#include <cerrno>

#include "runtime/image_helper.hpp"
#include "runtime/render.hpp"

namespace snell::rt::image_wire {

namespace {

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

}  // namespace

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

bool send_status(int sock, std::uint32_t kind, const std::string& message) {
  Wire status;
  status.put(kind);
  status.put_string(message);
  return send_message(sock, status);
}

bool serve_requests(int sock, std::mutex* encoder) {
  for (Wire in; recv_message(sock, in);) {
    if (in.bytes.empty()) return true;
    std::string path;
    Image image;
    OutputInfo info;
    DisplayView display;
    std::vector<unsigned char> bytes;
    std::string error = "a request to the image helper was cut short";
    if (get_request(in, path, image, info, display)) {
      std::unique_lock<std::mutex> lock;
      if (encoder) lock = std::unique_lock(*encoder);
      error = encode_image_here(path, image, info, display, bytes);
    }
    Wire out;
    out.put_string(error);
    out.put(std::uint64_t(bytes.size()));
    out.put(bytes.data(), bytes.size());
    if (!send_message(sock, out)) break;
    in = Wire{};
  }
  return false;
}

}  // namespace snell::rt::image_wire
