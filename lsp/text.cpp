#include "lsp/text.hpp"

#include <algorithm>
#include <cctype>
#include <cstdio>

namespace snell::lsp {

namespace {
// Bytes of the UTF-8 sequence led by `c`, or 1 for a byte that leads none.
std::uint32_t seq_len(unsigned char c) {
  if (c < 0x80) return 1;
  if ((c & 0xE0) == 0xC0) return 2;
  if ((c & 0xF0) == 0xE0) return 3;
  if ((c & 0xF8) == 0xF0) return 4;
  return 1;
}
}  // namespace

LineIndex::LineIndex(std::string_view text) : text_(text) {
  starts_.push_back(0);
  // LSP's line ends are \n, \r\n and a lone \r (an old Mac file, or one an
  // editor mixed): the client counts lines by all three.
  for (std::uint32_t i = 0; i < text.size(); ++i)
    if (text[i] == '\n' || (text[i] == '\r' && (i + 1 == text.size() || text[i + 1] != '\n')))
      starts_.push_back(i + 1);
}

Position LineIndex::position(std::uint32_t offset, Encoding enc) const {
  if (starts_.empty()) return {};
  offset = std::min<std::uint32_t>(offset, static_cast<std::uint32_t>(text_.size()));
  auto it = std::upper_bound(starts_.begin(), starts_.end(), offset);
  std::uint32_t line = static_cast<std::uint32_t>(it - starts_.begin()) - 1;
  std::uint32_t start = starts_[line];
  if (enc == Encoding::Utf8) return {line, offset - start};
  std::uint32_t units = 0, i = start;
  if (line == last_line_ && offset >= last_offset_) i = last_offset_, units = last_units_;
  bool split = false;
  while (i < offset) {
    std::uint32_t n = seq_len(static_cast<unsigned char>(text_[i]));
    if (i + n > offset) n = offset - i, split = true;  // an offset inside a sequence
    units += n == 4 ? 2 : 1;
    i += n;
  }
  // Remembered only at a sequence boundary: counting on from inside one differs.
  if (!split) last_line_ = line, last_offset_ = offset, last_units_ = units;
  return {line, units};
}

std::uint32_t LineIndex::offset(Position p, Encoding enc) const {
  if (starts_.empty()) return 0;
  if (p.line >= starts_.size()) return static_cast<std::uint32_t>(text_.size());
  std::uint32_t i = starts_[p.line];
  std::uint32_t end = p.line + 1 < starts_.size() ? starts_[p.line + 1] - 1
                                                  : static_cast<std::uint32_t>(text_.size());
  if (enc == Encoding::Utf8) return std::min(i + p.character, end);
  for (std::uint32_t units = 0; i < end && units < p.character;) {
    std::uint32_t n = seq_len(static_cast<unsigned char>(text_[i]));
    if (i + n > end) n = end - i;
    units += n == 4 ? 2 : 1;
    i += n;
  }
  return i;
}

nlohmann::json LineIndex::range(std::uint32_t begin, std::uint32_t end, Encoding enc) const {
  Position a = position(begin, enc), b = position(std::max(begin, end), enc);
  return {{"start", {{"line", a.line}, {"character", a.character}}},
          {"end", {{"line", b.line}, {"character", b.character}}}};
}

std::string uri_to_path(std::string_view uri) {
  constexpr std::string_view kFile = "file://";
  if (uri.substr(0, kFile.size()) != kFile) {
    // untitled:Untitled-1 and the like: a name in the current folder, so relative
    // imports resolve from where the server runs.
    std::string name;
    for (char c : uri) name += (c == '/' || c == ':') ? '_' : c;
    return name;
  }
  uri.remove_prefix(kFile.size());
  std::size_t slash = uri.find('/');  // skip an authority (file://host/path)
  if (slash == std::string_view::npos) return "/";
  uri.remove_prefix(slash);
  std::string out;
  for (std::size_t i = 0; i < uri.size(); ++i) {
    auto hex = [](char c) -> int {
      if (c >= '0' && c <= '9') return c - '0';
      if (c >= 'a' && c <= 'f') return c - 'a' + 10;
      if (c >= 'A' && c <= 'F') return c - 'A' + 10;
      return -1;
    };
    if (uri[i] == '%' && i + 2 < uri.size() && hex(uri[i + 1]) >= 0 && hex(uri[i + 2]) >= 0) {
      out += static_cast<char>(hex(uri[i + 1]) * 16 + hex(uri[i + 2]));
      i += 2;
    } else {
      out += uri[i];
    }
  }
  return out;
}

std::string path_to_uri(std::string_view path) {
  std::string out = "file://";
  for (unsigned char c : path) {
    if (std::isalnum(c) || c == '/' || c == '-' || c == '_' || c == '.' || c == '~') {
      out += static_cast<char>(c);
    } else {
      char buf[4];
      std::snprintf(buf, sizeof buf, "%%%02X", c);
      out += buf;
    }
  }
  return out;
}

}  // namespace snell::lsp
