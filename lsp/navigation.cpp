// Go to definition (names to their let / fn / parameter / loop variable, imports
// to their file) and the document's outline (lets, fns, scene items).
#include "compiler/properties.hpp"
#include "lsp/features.hpp"

namespace snell::lsp {

json definition(const Locator& at, std::uint32_t offset) {
  const Analysis& a = at.analysis;
  if (const Reference* r = a.reference_at(offset)) {
    if (r->def < 0) return nullptr;
    return at.location(a.defs[r->def].span);
  }
  if (int d = a.definition_at(offset); d >= 0) return at.location(a.defs[d].span);
  if (const ImportSite* i = a.import_at(offset)) {
    if (i->file == UINT32_MAX) return nullptr;
    return at.location({i->file, 0, 0});
  }
  return nullptr;
}

namespace {

// LSP SymbolKind values.
enum SymbolKind { kFunction = 12, kVariable = 13, kObject = 19, kStruct = 23, kFile = 1 };

class Outline {
 public:
  explicit Outline(const Locator& at) : at_(at) {}

  void add(const std::vector<lang::StmtPtr>& stmts, json& out) {
    for (const lang::StmtPtr& sp : stmts) {
      if (!sp) continue;
      const lang::Stmt& s = *sp;
      switch (s.kind) {
        case lang::StmtKind::Let:
          out.push_back(symbol(s.name, kVariable, s.span, s.name_span, let_detail(s)));
          break;
        case lang::StmtKind::Fn: {
          std::string params;
          for (const std::string& p : s.params) params += (params.empty() ? "" : ", ") + p;
          json f = symbol(s.name, kFunction, s.span, s.name_span, "(" + params + ")");
          json children = json::array();
          add(s.body, children);
          // `fn mk(n) = sphere { radius n };`: what an expression body makes too.
          if (!s.exprs.empty() && s.exprs[0] && s.exprs[0]->kind == lang::ExprKind::Object) {
            const lang::Expr& e = *s.exprs[0];
            const lang::Span kw{e.span.file, e.span.begin,
                                e.span.begin + static_cast<std::uint32_t>(e.text.size())};
            json item = symbol(e.text, kObject, e.span, kw, "");
            if (e.block && !e.block->statements.empty()) {
              json inner = json::array();
              add(e.block->statements, inner);
              if (!inner.empty()) item["children"] = std::move(inner);
            }
            children.push_back(std::move(item));
          }
          if (!children.empty()) f["children"] = std::move(children);
          out.push_back(std::move(f));
          break;
        }
        case lang::StmtKind::For:
          add(s.body, out);
          break;
        case lang::StmtKind::If:
          for (const auto& b : s.branches) add(b, out);
          add(s.else_body, out);
          break;
        case lang::StmtKind::Import:
          out.push_back(symbol("import \"" + s.name + "\"", kFile, s.span, s.span, ""));
          break;
        case lang::StmtKind::Item: {
          const compile::BlockInfo* b = compile::find_block(s.name);
          bool object = (b && b->is_object) || s.name == "object";
          json item = symbol(s.name, object ? kObject : kStruct, s.span, s.name_span, "");
          if (s.block && !s.block->statements.empty()) {
            json children = json::array();
            add(s.block->statements, children);
            if (!children.empty()) item["children"] = std::move(children);
          }
          out.push_back(std::move(item));
          break;
        }
        default:
          break;
      }
    }
  }

 private:
  std::string let_detail(const lang::Stmt& s) const {
    if (s.exprs.empty() || !s.exprs[0]) return "";
    const lang::Expr& e = *s.exprs[0];
    if (e.kind == lang::ExprKind::Constructor || e.kind == lang::ExprKind::Object) return e.text;
    return "";
  }

  json symbol(const std::string& name, int kind, lang::Span range, lang::Span selection,
              const std::string& detail) const {
    // selectionRange must lie inside range.
    if (selection.begin < range.begin || selection.end > range.end) selection = range;
    json j = {{"name", name.empty() ? std::string("?") : name},
              {"kind", kind},
              {"range", at_.range(range)},
              {"selectionRange", at_.range(selection)}};
    if (!detail.empty()) j["detail"] = detail;
    return j;
  }

  const Locator& at_;
};

}  // namespace

json document_symbols(const Locator& at) {
  json out = json::array();
  if (const lang::Program* p = at.analysis.main_program()) Outline(at).add(p->statements, out);
  return out;
}

}  // namespace snell::lsp
