// The image helper's wire format (image_helper.hpp, image_server.hpp), on a stream
// socket, all integers in this machine's order (both ends are the same binary):
//   helper -> client, once loaded: u32 kind (0 ready, 1 load error, 2 display
//                                  error), string message
//   client -> helper, per image:   string path, Image, OutputInfo, DisplayView
//   helper -> client, per image:   string error, bytes encoded
//   client -> helper, at the end:  an empty message (goodbye: stay as the resident
//                                  server, image_server.hpp)
//   helper -> client, to that:     an empty message (it will not die with the run)
// where a string or byte run is a u64 length and its bytes, and each of these is
// one message (a u64 length, then its bytes). Sends never raise SIGPIPE
// (MSG_NOSIGNAL): a helper that died is an error message, not the end of a render.
#pragma once

#include <cstdint>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "runtime/image_format.hpp"

namespace snell::rt {

struct Image;
struct OutputInfo;

namespace image_wire {

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

// One message: its length, then its bytes. False when the stream ended or broke.
bool send_message(int fd, const Wire& w);
bool recv_message(int fd, Wire& w);

// A request to encode `image` for `path`, and reading one back (false: cut short).
void put_request(Wire& w, const std::string& path, const Image& image, const OutputInfo& info,
                 const DisplayView& display);
bool get_request(Wire& w, std::string& path, Image& image, OutputInfo& info, DisplayView& display);

// The helper's status message: kind 0 ready, 1 the module did not load, 2 the
// display transform could not be made; and the message.
enum StatusKind : std::uint32_t { kReady = 0, kLoadError = 1, kDisplayError = 2 };

// The helper's end, in the per-run child and in each of the resident server's
// connections: sends the status; encodes requests until end of file or a
// goodbye (true: the goodbye, not yet answered), holding `encoder` (when given)
// over each one.
bool send_status(int sock, std::uint32_t kind, const std::string& message);
bool serve_requests(int sock, std::mutex* encoder = nullptr);

}  // namespace image_wire
}  // namespace snell::rt
