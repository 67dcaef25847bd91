// Source files and spans. A Span is a byte range in one file of a SourceManager;
// line and column are computed on demand (1-based; columns count bytes).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

namespace snell::lang {

using FileId = std::uint32_t;

struct Span {
  FileId file = 0;
  std::uint32_t begin = 0;  // byte offset of the first character
  std::uint32_t end = 0;    // byte offset one past the last character

  static Span join(Span a, Span b) { return {a.file, a.begin, b.end > a.end ? b.end : a.end}; }
};

struct LineCol {
  std::uint32_t line = 1;
  std::uint32_t col = 1;
};

class SourceFile {
 public:
  SourceFile(std::string path, std::string text);
  const std::string& path() const { return path_; }
  std::string_view text() const { return text_; }
  LineCol line_col(std::uint32_t offset) const;
  // The offset of a 1-based line and byte column, the inverse of line_col
  // (clamped to the file's end).
  std::uint32_t offset_of(LineCol lc) const;
  // The text of a 1-based line, without its newline.
  std::string_view line_text(std::uint32_t line) const;
  std::uint32_t line_count() const { return static_cast<std::uint32_t>(line_starts_.size()); }

 private:
  std::string path_;
  std::string text_;
  std::vector<std::uint32_t> line_starts_;
};

// Owns every file read for one compilation. FileIds are indices and stay valid.
class SourceManager {
 public:
  FileId add(std::string path, std::string text);
  const SourceFile& file(FileId id) const { return *files_.at(id); }
  std::size_t size() const { return files_.size(); }
  // "path:line:col" of the start of a span.
  std::string location(Span span) const;

 private:
  std::vector<std::unique_ptr<SourceFile>> files_;
};

}  // namespace snell::lang
