// Positions in a document as LSP counts them and as the compiler does. The
// compiler's spans are byte offsets; LSP positions are a 0-based line and a
// column in UTF-16 code units, or in bytes when the client accepts "utf-8"
// (LSP 3.17 positionEncodings). Bad UTF-8 counts one unit per byte, and
// positions past a line's end clamp to it, so any position maps somewhere.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

namespace snell::lsp {

enum class Encoding { Utf16, Utf8 };

struct Position {
  std::uint32_t line = 0, character = 0;
};

class LineIndex {
 public:
  LineIndex() = default;
  explicit LineIndex(std::string_view text);
  Position position(std::uint32_t offset, Encoding enc) const;
  std::uint32_t offset(Position p, Encoding enc) const;
  nlohmann::json range(std::uint32_t begin, std::uint32_t end, Encoding enc) const;

 private:
  std::string_view text_;
  std::vector<std::uint32_t> starts_;
  // The last UTF-16 position found: the next one on the same line further right
  // counts on from it (an outline of one long line was quadratic in its length).
  mutable std::uint32_t last_line_ = ~0u, last_offset_ = 0, last_units_ = 0;
};

// file:///a%20b/c.scn <-> /a b/c.scn. A URI of another scheme (an unsaved
// "untitled:" buffer) maps to a path that names no file; path_to_uri inverts it.
std::string uri_to_path(std::string_view uri);
std::string path_to_uri(std::string_view path);

}  // namespace snell::lsp
