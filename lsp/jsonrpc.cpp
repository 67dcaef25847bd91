#include "lsp/jsonrpc.hpp"

#include <cctype>
#include <charconv>

namespace snell::lsp {

namespace {
bool iequals_prefix(std::string_view line, std::string_view prefix) {
  if (line.size() < prefix.size()) return false;
  for (std::size_t i = 0; i < prefix.size(); ++i)
    if (std::tolower(static_cast<unsigned char>(line[i])) !=
        std::tolower(static_cast<unsigned char>(prefix[i])))
      return false;
  return true;
}
// Where "Content-Length:" (in any case) first stands in text[0, n), or npos.
std::size_t find_header(std::string_view text, std::size_t n) {
  constexpr std::string_view kName = "content-length:";
  for (std::size_t i = 0; i + kName.size() <= n; ++i)
    if (iequals_prefix(text.substr(i), kName)) return i;
  return std::string_view::npos;
}
}  // namespace

std::optional<std::string> MessageReader::next(std::string* error) {
  // Every problem met on the way, in order (a call may skip several).
  auto say = [&](const std::string& what) {
    if (!error) return;
    if (!error->empty()) *error += "; ";
    *error += what;
  };
  for (;;) {
    if (skip_ > 0) {
      // A header inside what is skipped ends the skip: a Content-Length of 10^14
      // swallowed every later message while it waited for its bytes.
      std::size_t n = std::min(skip_, buffer_.size());
      if (const std::size_t at = find_header(buffer_, n); at != std::string::npos) {
        buffer_.erase(0, at);
        skip_ = 0;
        continue;
      }
      buffer_.erase(0, n);
      skip_ -= n;
      if (skip_ > 0) return std::nullopt;
    }
    // Out of step (a client's Content-Length a byte off left part of a body, or
    // took part of the next header): skip to the next Content-Length header, so
    // a message or two are lost and not every later one.
    if (!buffer_.empty() && !iequals_prefix(buffer_, "content-")) {
      const std::size_t keep = std::min(buffer_.size(), std::size_t(14));
      if (iequals_prefix(std::string_view(buffer_).substr(0, keep),
                         std::string_view("content-length:").substr(0, keep)))
        return std::nullopt;  // the start of one, still arriving
      std::size_t at = find_header(buffer_, buffer_.size());
      say("bytes outside any message, skipped to the next header");
      if (at == std::string::npos) {
        buffer_.erase(0, buffer_.size() > 14 ? buffer_.size() - 14 : 0);
        return std::nullopt;
      }
      buffer_.erase(0, at);
    }
    std::size_t end = buffer_.find("\r\n\r\n");
    if (end == std::string::npos) {
      // A client that sends endless header bytes without a blank line: keep only
      // a tail that could still hold the start of a separator.
      if (buffer_.size() > 1 << 16) {
        buffer_.erase(0, buffer_.size() - 3);
        say("a header block longer than 64 KiB");
      }
      return std::nullopt;
    }
    std::string_view headers(buffer_.data(), end);
    std::optional<std::size_t> length;
    std::size_t pos = 0;
    while (pos <= headers.size()) {
      std::size_t eol = headers.find("\r\n", pos);
      if (eol == std::string_view::npos) eol = headers.size();
      std::string_view line = headers.substr(pos, eol - pos);
      constexpr std::string_view kName = "content-length:";
      if (iequals_prefix(line, kName)) {
        std::string_view v = line.substr(kName.size());
        while (!v.empty() && (v.front() == ' ' || v.front() == '\t')) v.remove_prefix(1);
        while (!v.empty() && (v.back() == ' ' || v.back() == '\t')) v.remove_suffix(1);
        std::size_t n = 0;
        auto [p, ec] = std::from_chars(v.data(), v.data() + v.size(), n);
        if (ec == std::errc() && p == v.data() + v.size() && !v.empty()) length = n;
      }
      pos = eol + 2;
    }
    std::size_t body = end + 4;
    if (!length) {
      say("a header block without a valid Content-Length");
      buffer_.erase(0, body);
      continue;
    }
    if (*length > kMaxMessageBytes) {
      say("a message of " + std::to_string(*length) + " bytes (too large)");
      buffer_.erase(0, body);
      skip_ = *length;
      continue;
    }
    if (buffer_.size() - body < *length) return std::nullopt;
    std::string out = buffer_.substr(body, *length);
    buffer_.erase(0, body + *length);
    return out;
  }
}

std::string frame(const json& message) {
  // Invalid UTF-8 (from a scene's bytes in a message) is replaced, never thrown.
  std::string body = message.dump(-1, ' ', false, json::error_handler_t::replace);
  return "Content-Length: " + std::to_string(body.size()) + "\r\n\r\n" + body;
}

json make_response(const json& id, json result) {
  return {{"jsonrpc", "2.0"}, {"id", id}, {"result", std::move(result)}};
}

json make_error(const json& id, int code, const std::string& message) {
  return {{"jsonrpc", "2.0"}, {"id", id}, {"error", {{"code", code}, {"message", message}}}};
}

json make_notification(const std::string& method, json params) {
  return {{"jsonrpc", "2.0"}, {"method", method}, {"params", std::move(params)}};
}

}  // namespace snell::lsp
