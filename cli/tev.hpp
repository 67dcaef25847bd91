// snell watch --display-server HOST:PORT: each finished pass streamed to the tev
// image viewer over its IPC protocol (as pbrt-v4 speaks it): a CreateImage packet
// naming the image and its R, G, B channels, then UpdateImage packets of linear
// float tiles, one channel each. The sending runs on its own thread and keeps only
// the newest image, so a slow or absent viewer never holds up the renders.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <mutex>
#include <optional>
#include <string>
#include <thread>
#include <vector>

#include "runtime/render.hpp"

namespace snell::cli {

// tev's packet types (its Ipc.h); snell sends the last two.
enum class TevPacket : std::uint8_t {
  OpenImage = 0,
  ReloadImage = 1,
  CloseImage = 2,
  UpdateImage = 3,
  CreateImage = 4
};

// The bytes of one packet: its total length (4 bytes, little-endian, counting
// itself), its type, then the payload. Exposed for the tests.
std::vector<std::uint8_t> tev_create_image(const std::string& name, std::uint32_t width,
                                           std::uint32_t height);
// One channel (0 R, 1 G, 2 B) of the window x0 <= x < x0 + w, y0 <= y < y0 + h.
std::vector<std::uint8_t> tev_update_image(const std::string& name, const rt::Image& image,
                                           int channel, std::uint32_t x0, std::uint32_t y0,
                                           std::uint32_t w, std::uint32_t h);

class TevStream {
 public:
  // `address` is HOST:PORT; false with `error` set when it is not of that form.
  static bool parse_address(const std::string& address, std::string& host, std::string& port,
                            std::string& error);
  TevStream(std::string host, std::string port, bool quiet);
  ~TevStream();
  TevStream(const TevStream&) = delete;
  TevStream& operator=(const TevStream&) = delete;

  // Queues `image` under `name`, replacing any image not yet sent.
  void show(const std::string& name, const rt::Image& image);

 private:
  void run();
  bool connect_socket();
  bool send_all(const std::vector<std::uint8_t>& packet);
  void disconnect();

  std::string host_, port_;
  bool quiet_;
  int fd_ = -1;
  std::string created_name_;  // the image tev has, and its size
  std::uint32_t created_w_ = 0, created_h_ = 0;
  bool warned_ = false;

  std::mutex mutex_;
  std::condition_variable wake_;
  bool stop_ = false;
  std::optional<std::pair<std::string, rt::Image>> pending_;
  std::thread thread_;
};

}  // namespace snell::cli
