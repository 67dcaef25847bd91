// JSON-RPC 2.0 messages with the Language Server Protocol's base framing:
//   Content-Length: N\r\n[other headers]\r\n\r\n<N bytes of JSON>
// The reader is fed bytes as they arrive and hands back whole bodies; it never
// throws and recovers from a malformed header by skipping to the next one, so
// no input can wedge the server.
#pragma once

#include <cstddef>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace snell::lsp {

using json = nlohmann::json;

// A message body larger than this is refused (the header is skipped and the
// body dropped as it arrives): a scene is at most 100 MB (lang::kMaxSourceBytes),
// JSON escaping can grow it, and nothing else a client sends is large.
inline constexpr std::size_t kMaxMessageBytes = std::size_t(256) << 20;

class MessageReader {
 public:
  void feed(std::string_view bytes) { buffer_.append(bytes); }
  // The next complete body, or nullopt when more bytes are needed. What was
  // skipped on the way (junk, a header block with no usable Content-Length, a body
  // too large) is appended to `error`, problems joined by "; ".
  std::optional<std::string> next(std::string* error = nullptr);
  std::size_t buffered() const { return buffer_.size(); }

 private:
  std::string buffer_;
  std::size_t skip_ = 0;  // bytes of a refused body still to drop
};

// The framed bytes of one message.
std::string frame(const json& message);

// JSON-RPC error codes the server uses.
enum ErrorCode : int {
  kParseError = -32700,
  kInvalidRequest = -32600,
  kMethodNotFound = -32601,
  kInvalidParams = -32602,
  kInternalError = -32603,
  kServerNotInitialized = -32002,
  kRequestFailed = -32803,
};

json make_response(const json& id, json result);
json make_error(const json& id, int code, const std::string& message);
json make_notification(const std::string& method, json params);

}  // namespace snell::lsp
