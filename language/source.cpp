#include "language/source.hpp"

#include <algorithm>

namespace snell::lang {

SourceFile::SourceFile(std::string path, std::string text)
    : path_(std::move(path)), text_(std::move(text)) {
  line_starts_.push_back(0);
  for (std::uint32_t i = 0; i < text_.size(); ++i)
    if (text_[i] == '\n') line_starts_.push_back(i + 1);
}

LineCol SourceFile::line_col(std::uint32_t offset) const {
  auto it = std::upper_bound(line_starts_.begin(), line_starts_.end(), offset);
  auto line = static_cast<std::uint32_t>(it - line_starts_.begin());  // 1-based
  return {line, offset - line_starts_[line - 1] + 1};
}

std::uint32_t SourceFile::offset_of(LineCol lc) const {
  if (lc.line == 0 || lc.line > line_starts_.size())
    return static_cast<std::uint32_t>(text_.size());
  std::uint64_t o = std::uint64_t(line_starts_[lc.line - 1]) + (lc.col > 0 ? lc.col - 1 : 0);
  return static_cast<std::uint32_t>(std::min<std::uint64_t>(o, text_.size()));
}

std::string_view SourceFile::line_text(std::uint32_t line) const {
  if (line == 0 || line > line_starts_.size()) return {};
  std::uint32_t b = line_starts_[line - 1];
  std::uint32_t e = line < line_starts_.size() ? line_starts_[line] - 1
                                               : static_cast<std::uint32_t>(text_.size());
  if (e > b && text_[e - 1] == '\r') --e;
  return std::string_view(text_).substr(b, e - b);
}

FileId SourceManager::add(std::string path, std::string text) {
  // A UTF-8 byte-order mark (what Windows editors write first) is not part of the
  // scene: dropped here, so tokens, columns and printed source lines all ignore it.
  if (text.compare(0, 3, "\xEF\xBB\xBF") == 0) text.erase(0, 3);
  files_.push_back(std::make_unique<SourceFile>(std::move(path), std::move(text)));
  return static_cast<FileId>(files_.size() - 1);
}

std::string SourceManager::location(Span span) const {
  const SourceFile& f = file(span.file);
  LineCol lc = f.line_col(span.begin);
  return f.path() + ":" + std::to_string(lc.line) + ":" + std::to_string(lc.col);
}

}  // namespace snell::lang
