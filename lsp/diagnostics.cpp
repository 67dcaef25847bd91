// The compiler's diagnostics as LSP Diagnostics: the exact span, the severity,
// the [Kind] as the code, and each note as related information. A diagnostic in
// an imported file is shown at the import that leads to it (the editor shows
// only the open document's), its real place kept as related information.
#include "language/diagnostics.hpp"

#include <cctype>

#include "lsp/features.hpp"

namespace snell::lsp {

json diagnostics(const Locator& at) {
  const Analysis& a = at.analysis;
  json out = json::array();
  const lang::SourceManager& sources = a.comp->sources;
  for (const lang::Diagnostic& d : a.comp->diags.diagnostics()) {
    lang::Span span = d.span.file < sources.size() ? d.span : lang::Span{a.main, 0, 0};
    std::string message = d.text();
    json related = json::array();
    if (span.file != a.main) {
      related.push_back({{"location", at.location(span)}, {"message", d.text()}});
      message = "in " + sources.location(span) + ": " + d.text();
      lang::Span via{a.main, 0, 0};
      for (const ImportSite& s : a.imports)
        if (s.file == span.file || via.end == 0) via = s.span;
      span = via;
    }
    for (const lang::DiagNote& n : d.notes) {
      lang::Span ns = n.span && n.span->file < sources.size() ? *n.span : d.span;
      if (ns.file >= sources.size()) ns = {a.main, 0, 0};
      related.push_back({{"location", at.location(ns)}, {"message", n.message}});
    }
    json j = {{"range", at.range(span)},
              {"severity", d.severity == lang::Severity::Error ? 1 : 2},
              {"code", std::string(lang::diag_name(d.kind))},
              {"source", "snell"},
              {"message", message}};
    if (!related.empty()) j["relatedInformation"] = std::move(related);
    out.push_back(std::move(j));
  }
  // The scene's own warnings (`snell check`'s): at the object they name, the
  // import that brings it when it is another file's, else the file's start.
  for (const auto& [message, where] : a.scene_warnings) {
    lang::Span span{a.main, 0, 0};
    const ir::Scene& scene = a.comp->scene;
    if (where.line > 0 && where.file < scene.files.size()) {
      for (lang::FileId f = 0; f < sources.size(); ++f) {
        if (sources.file(f).path() != scene.files[where.file]) continue;
        const lang::SourceFile& file = sources.file(f);
        std::uint32_t b = file.offset_of({where.line, where.col}), e = b;
        const std::string_view text = file.text();
        while (e < text.size() &&
               (std::isalnum(static_cast<unsigned char>(text[e])) || text[e] == '_'))
          ++e;  // the block's keyword
        span = {f, b, e};
        break;
      }
      if (span.file != a.main)
        for (const ImportSite& s : a.imports)
          if (s.file == span.file) span = s.span;
      if (span.file != a.main) span = {a.main, 0, 0};
    }
    out.push_back({{"range", at.range(span)},
                   {"severity", 2},
                   {"code", "SceneWarning"},
                   {"source", "snell"},
                   {"message", message}});
  }
  // Errors past --max-errors are counted but not kept: say so once.
  std::size_t kept = 0;
  for (const lang::Diagnostic& d : a.comp->diags.diagnostics())
    kept += d.severity == lang::Severity::Error;
  if (a.comp->diags.error_count() > kept)
    out.push_back({{"range", at.range({a.main, 0, 0})},
                   {"severity", 3},
                   {"source", "snell"},
                   {"message", std::to_string(a.comp->diags.error_count() - kept) +
                                   " more errors not shown"}});
  return out;
}

}  // namespace snell::lsp
