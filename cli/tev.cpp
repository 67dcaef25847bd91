#include "cli/tev.hpp"

#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>
#include <sys/time.h>
#include <unistd.h>

#include <cstring>
#include <iostream>

namespace snell::cli {

namespace {

// tev reads its packets in the host's byte order; both ends are little-endian x86
// or ARM in practice, and so is this writer, whatever the host.
void put_u32(std::vector<std::uint8_t>& b, std::uint32_t v) {
  for (int i = 0; i < 4; ++i) b.push_back(std::uint8_t(v >> (8 * i)));
}
void put_f32(std::vector<std::uint8_t>& b, float f) {
  std::uint32_t v;
  std::memcpy(&v, &f, 4);
  put_u32(b, v);
}
void put_string(std::vector<std::uint8_t>& b, const std::string& s) {
  b.insert(b.end(), s.begin(), s.end());
  b.push_back(0);
}
std::vector<std::uint8_t> begin_packet(TevPacket type) {
  std::vector<std::uint8_t> b;
  put_u32(b, 0);  // the length, filled in by end_packet
  b.push_back(std::uint8_t(type));
  return b;
}
void end_packet(std::vector<std::uint8_t>& b) {
  std::uint32_t n = std::uint32_t(b.size());
  for (int i = 0; i < 4; ++i) b[i] = std::uint8_t(n >> (8 * i));
}

// Tiles of at most this many pixels a side: a packet stays ~64 KiB, so tev shows
// a large image's progress tile by tile and a send never needs a huge buffer.
constexpr std::uint32_t kTile = 128;

}  // namespace

std::vector<std::uint8_t> tev_create_image(const std::string& name, std::uint32_t width,
                                           std::uint32_t height) {
  std::vector<std::uint8_t> b = begin_packet(TevPacket::CreateImage);
  b.push_back(1);  // grab focus: the newest scene is the one to look at
  put_string(b, name);
  put_u32(b, width);
  put_u32(b, height);
  put_u32(b, 3);
  for (const char* c : {"R", "G", "B"}) put_string(b, c);
  end_packet(b);
  return b;
}

std::vector<std::uint8_t> tev_update_image(const std::string& name, const rt::Image& image,
                                           int channel, std::uint32_t x0, std::uint32_t y0,
                                           std::uint32_t w, std::uint32_t h) {
  static const char* kNames[] = {"R", "G", "B"};
  std::vector<std::uint8_t> b = begin_packet(TevPacket::UpdateImage);
  b.reserve(b.size() + name.size() + 24 + std::size_t(w) * h * 4);
  b.push_back(0);  // no focus grab per tile
  put_string(b, name);
  put_string(b, kNames[channel]);
  for (std::uint32_t v : {x0, y0, w, h}) put_u32(b, v);
  for (std::uint32_t y = y0; y < y0 + h; ++y)
    for (std::uint32_t x = x0; x < x0 + w; ++x) put_f32(b, image.at(x, y)[channel]);
  end_packet(b);
  return b;
}

bool TevStream::parse_address(const std::string& address, std::string& host, std::string& port,
                              std::string& error) {
  std::size_t k = address.rfind(':');
  if (k == std::string::npos || k == 0 || k + 1 == address.size() ||
      address.find_first_not_of("0123456789", k + 1) != std::string::npos) {
    error = "--display-server takes HOST:PORT (e.g. 127.0.0.1:14158), got '" + address + "'";
    return false;
  }
  host = address.substr(0, k);
  if (host.size() > 2 && host.front() == '[' && host.back() == ']')  // [::1]:14158
    host = host.substr(1, host.size() - 2);
  port = address.substr(k + 1);
  const unsigned long number = port.size() > 5 ? 0 : std::stoul(port);  // digits only
  if (number < 1 || number > 65535) {
    error = "--display-server's port must be in 1..65535, got '" + port + "'";
    return false;
  }
  return true;
}

TevStream::TevStream(std::string host, std::string port, bool quiet)
    : host_(std::move(host)), port_(std::move(port)), quiet_(quiet) {
  thread_ = std::thread([this] { run(); });
}

TevStream::~TevStream() {
  {
    std::lock_guard lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  thread_.join();
  disconnect();
}

void TevStream::show(const std::string& name, const rt::Image& image) {
  {
    std::lock_guard lock(mutex_);
    pending_.emplace(name, image);
  }
  wake_.notify_all();
}

bool TevStream::connect_socket() {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  if (int err = getaddrinfo(host_.c_str(), port_.c_str(), &hints, &found); err != 0) {
    if (!warned_ && !quiet_)
      std::cerr << "snell watch: display server " << host_ << ":" << port_ << ": "
                << gai_strerror(err) << "\n";
    warned_ = true;
    return false;
  }
  for (addrinfo* a = found; a && fd_ < 0; a = a->ai_next) {
    int fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    // A viewer that stops reading must not stall this thread for ever.
    timeval tv{3, 0};
    setsockopt(fd, SOL_SOCKET, SO_SNDTIMEO, &tv, sizeof tv);
    if (::connect(fd, a->ai_addr, a->ai_addrlen) == 0)
      fd_ = fd;
    else
      ::close(fd);
  }
  freeaddrinfo(found);
  if (fd_ < 0) {
    if (!warned_ && !quiet_)
      std::cerr << "snell watch: cannot reach the display server at " << host_ << ":" << port_
                << " (is tev running?); trying again with the next pass\n";
    warned_ = true;
    return false;
  }
  warned_ = false;
  created_name_.clear();
  return true;
}

bool TevStream::send_all(const std::vector<std::uint8_t>& packet) {
  std::size_t sent = 0;
  while (sent < packet.size()) {
    ssize_t n = ::send(fd_, packet.data() + sent, packet.size() - sent, MSG_NOSIGNAL);
    if (n <= 0) {
      if (n < 0 && errno == EINTR) continue;
      if (!quiet_) std::cerr << "snell watch: the display server went away; reconnecting\n";
      disconnect();
      return false;
    }
    sent += std::size_t(n);
  }
  return true;
}

void TevStream::disconnect() {
  if (fd_ >= 0) ::close(fd_);
  fd_ = -1;
}

void TevStream::run() {
  for (;;) {
    std::pair<std::string, rt::Image> job;
    {
      std::unique_lock lock(mutex_);
      wake_.wait(lock, [&] { return stop_ || pending_; });
      // Stopping: the last pass was sent when it finished; a viewer that is not
      // answering must not hold up the exit.
      if (stop_) return;
      job = std::move(*pending_);
      pending_.reset();
    }
    const auto& [name, image] = job;
    if (fd_ < 0 && !connect_socket()) continue;
    // A new name or size is a new image in tev; the same one is updated in place.
    if (name != created_name_ || image.width != created_w_ || image.height != created_h_) {
      if (!send_all(tev_create_image(name, image.width, image.height))) continue;
      created_name_ = name;
      created_w_ = image.width;
      created_h_ = image.height;
    }
    bool ok = true;
    for (std::uint32_t y = 0; ok && y < image.height; y += kTile)
      for (std::uint32_t x = 0; ok && x < image.width; x += kTile)
        for (int c = 0; ok && c < 3; ++c)
          ok = send_all(tev_update_image(name, image, c, x, y, std::min(kTile, image.width - x),
                                         std::min(kTile, image.height - y)));
    if (!ok) created_name_.clear();
  }
}

}  // namespace snell::cli
