// Locator: spans of any file of an analysis as LSP locations.
#include <filesystem>

#include "lsp/features.hpp"

namespace snell::lsp {

std::string Locator::uri(lang::FileId file) const {
  if (file == analysis.main) return main_uri;
  std::error_code ec;
  std::filesystem::path p = std::filesystem::absolute(analysis.comp->sources.file(file).path(), ec);
  return path_to_uri(ec ? analysis.comp->sources.file(file).path() : p.lexically_normal().string());
}

json Locator::range(lang::Span span) const {
  if (span.file >= analysis.comp->sources.size()) span = {analysis.main, 0, 0};
  return index(span.file).range(span.begin, span.end, encoding);
}

const LineIndex& Locator::index(lang::FileId file) const {
  auto it = indexes_.find(file);
  if (it == indexes_.end())
    it = indexes_.emplace(file, LineIndex(analysis.comp->sources.file(file).text())).first;
  return it->second;
}

json Locator::location(lang::Span span) const {
  if (span.file >= analysis.comp->sources.size()) span = {analysis.main, 0, 0};
  return {{"uri", uri(span.file)}, {"range", range(span)}};
}

}  // namespace snell::lsp
