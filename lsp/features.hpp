// The answers to an editor's questions about one analysed document. Each takes
// the analysis of the document's current text and a byte offset in it, and
// returns the LSP result object (null when there is nothing to say). The words
// about blocks, properties and builtins come from the compiler's own tables
// (compiler/properties.def, builtins.def, language/constructors.def).
#pragma once

#include <string_view>
#include <unordered_map>

#include "lsp/analysis.hpp"
#include "lsp/jsonrpc.hpp"
#include "lsp/text.hpp"

namespace snell::lsp {

// Positions of files other than the main one (definitions in imports).
struct Locator {
  Locator(const Analysis& a, Encoding e, std::string uri)
      : analysis(a), encoding(e), main_uri(std::move(uri)) {}
  const Analysis& analysis;
  Encoding encoding;
  std::string main_uri;
  json location(lang::Span span) const;
  json range(lang::Span span) const;
  std::string uri(lang::FileId file) const;
  const LineIndex& index(lang::FileId file) const;

 private:
  mutable std::unordered_map<lang::FileId, LineIndex> indexes_;
};

json diagnostics(const Locator& at);                       // publishDiagnostics
json hover(const Locator& at, std::uint32_t offset);       // textDocument/hover
json definition(const Locator& at, std::uint32_t offset);  // textDocument/definition
json document_symbols(const Locator& at);                  // textDocument/documentSymbol
json completion(const Locator& at, std::string_view text, std::uint32_t offset,
                const AnalysisOptions& options);  // textDocument/completion

// Words for hovers, shared with completion's details.
std::string describe_block(std::string_view block);
std::string describe_property(std::string_view block, std::string_view property);
std::string describe_definition(const Analysis& a, const Definition& d);

}  // namespace snell::lsp
