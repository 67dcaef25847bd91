#include "lsp/analysis.hpp"

#include <algorithm>
#include <chrono>
#include <unordered_set>

#include "compiler/value.hpp"
#include "language/parser.hpp"

namespace snell::lsp {

using lang::Expr;
using lang::ExprKind;
using lang::Stmt;
using lang::StmtKind;

compile::CompileOptions compile_options(const AnalysisOptions& options) {
  compile::CompileOptions c;
  c.include_dirs = options.include_dirs;
  c.step_budget = options.step_budget;
  c.max_errors = options.max_errors;
  c.overlay = options.overlay;
  c.unreadable_images = options.unreadable_images;
  return c;
}

namespace {

class Walker {
 public:
  Walker(Analysis& a, const AnalysisOptions& o) : a_(a), opts_(o) {}

  void run() {
    const lang::Program* p = a_.main_program();
    if (!p) return;
    for (std::size_t i = 0; i < a_.comp->sources.size(); ++i)
      by_path_[compile::canonical_path(a_.comp->sources.file(lang::FileId(i)).path())] =
          lang::FileId(i);
    std::uint32_t end = static_cast<std::uint32_t>(a_.main_file().text().size());
    walk(p->statements, end, true);
    resolve();
    // The walk visits an if's conditions before its branches: put the names back
    // in source order for reference_at's binary search.
    std::stable_sort(a_.refs.begin(), a_.refs.end(), [](const Reference& x, const Reference& y) {
      return x.span.begin < y.span.begin;
    });
  }

 private:
  struct PendingRef {
    std::string_view name;
    bool in_body;
  };

  int add_def(Definition d) {
    a_.defs.push_back(std::move(d));
    int id = static_cast<int>(a_.defs.size()) - 1;
    by_name_[a_.defs.back().name].push_back(id);
    return id;
  }

  void walk(const std::vector<lang::StmtPtr>& stmts, std::uint32_t scope_end, bool top) {
    for (const lang::StmtPtr& sp : stmts) {
      if (!sp) continue;
      const Stmt& s = *sp;
      switch (s.kind) {
        case StmtKind::Let:
          for (const lang::ExprPtr& e : s.exprs) walk_expr(e.get());
          add_def({Definition::Let, s.name, s.name_span, &s, s.span.end, scope_end, false, false});
          if (top) top_level_.push_back(static_cast<int>(a_.defs.size()) - 1);
          break;
        case StmtKind::Fn: {
          add_def({Definition::Fn, s.name, s.name_span, &s, s.name_span.begin, scope_end, false,
                   false});
          if (top) top_level_.push_back(static_cast<int>(a_.defs.size()) - 1);
          for (std::size_t i = 0; i < s.params.size() && i < s.param_spans.size(); ++i)
            add_def({Definition::Param, s.params[i], s.param_spans[i], &s, s.param_spans[i].begin,
                     s.span.end, false, false});
          ++fn_depth_;
          for (const lang::ExprPtr& e : s.exprs) walk_expr(e.get());
          walk(s.body, s.span.end, false);
          --fn_depth_;
          break;
        }
        case StmtKind::For:
          for (const lang::ExprPtr& e : s.exprs) walk_expr(e.get());
          add_def({Definition::LoopVar, s.name, s.name_span, &s, s.name_span.begin, s.span.end,
                   false, false});
          walk(s.body, s.span.end, false);
          break;
        case StmtKind::If:
          for (const lang::ExprPtr& e : s.exprs) walk_expr(e.get());
          for (const auto& branch : s.branches) walk(branch, s.span.end, false);
          walk(s.else_body, s.span.end, false);
          break;
        case StmtKind::Import:
          import(s, scope_end);
          break;
        case StmtKind::Item:
          a_.sites.push_back({Site::Block, s.name_span, s.name, ""});
          walk_block(s.block.get(), s.name);
          break;
        case StmtKind::Background:
          a_.sites.push_back({Site::Block, s.name_span, "background", ""});
          for (const lang::ExprPtr& e : s.exprs) walk_expr(e.get());
          break;
        case StmtKind::Return:
        case StmtKind::ExprStmt:
          for (const lang::ExprPtr& e : s.exprs) walk_expr(e.get());
          break;
        case StmtKind::Error:
          break;
      }
    }
  }

  void walk_block(const lang::Block* b, const std::string& name) {
    if (!b) return;
    walk_expr(b->subject.get());
    for (const lang::ExprPtr& e : b->positional) walk_expr(e.get());
    for (const lang::Property& p : b->properties) {
      a_.sites.push_back({Site::Property, p.name_span, name, p.name});
      walk_expr(p.value.get());
      walk_block(p.block.get(), p.name);
    }
    walk(b->statements, b->span.end, false);
  }

  void walk_expr(const Expr* e) {
    if (!e) return;
    switch (e->kind) {
      case ExprKind::Name:
        a_.refs.push_back({e->span, -1});
        pending_.push_back({e->text, fn_depth_ > 0});
        return;
      case ExprKind::Constructor:
      case ExprKind::Object: {
        lang::Span kw{e->span.file, e->span.begin,
                      e->span.begin + static_cast<std::uint32_t>(e->text.size())};
        a_.sites.push_back({Site::Block, kw, e->text, ""});
        for (const lang::ExprPtr& c : e->args) walk_expr(c.get());
        walk_block(e->block.get(), e->text);
        return;
      }
      default:
        for (const lang::ExprPtr& c : e->args) walk_expr(c.get());
        walk_block(e->block.get(), e->text);
        return;
    }
  }

  // The file an import names, parsed into the compilation's sources when the
  // compiler did not get to it (a syntax error elsewhere stops evaluation).
  void import(const Stmt& s, std::uint32_t scope_end) {
    ImportSite site;
    site.span = s.name_span.end > s.name_span.begin ? s.name_span : s.span;
    site.name = s.name;
    compile::CompileOptions copts = compile_options(opts_);
    site.path = compile::find_import(s.name, a_.path, copts);
    if (!site.path.empty()) {
      std::string key = compile::canonical_path(site.path);
      if (auto it = by_path_.find(key); it != by_path_.end()) {
        site.file = it->second;
      } else {
        std::string text, message;
        const std::string* open = opts_.overlay ? opts_.overlay(key) : nullptr;
        if (open || compile::read_file(site.path, text, message)) {
          compile::Compilation& c = *a_.comp;
          lang::FileId id = c.sources.add(site.path, open ? *open : text);
          lang::DiagnosticEngine scratch(c.sources);
          c.programs.push_back(
              std::make_unique<lang::Program>(lang::parse(c.sources, id, scratch)));
          by_path_[key] = site.file = id;
        }
      }
    }
    if (site.file != UINT32_MAX) {
      for (const auto& prog : a_.comp->programs) {
        if (!prog || prog->file != site.file) continue;
        for (const lang::StmtPtr& st : prog->statements) {
          if (!st || (st->kind != StmtKind::Let && st->kind != StmtKind::Fn)) continue;
          add_def({st->kind == StmtKind::Let ? Definition::Let : Definition::Fn, st->name,
                   st->name_span, st.get(), s.span.end, scope_end, true, false});
        }
        break;
      }
    }
    a_.imports.push_back(std::move(site));
  }

  void resolve() {
    for (std::size_t i = 0; i < a_.refs.size(); ++i) {
      auto it = by_name_.find(std::string(pending_[i].name));
      if (it == by_name_.end()) continue;
      std::uint32_t at = a_.refs[i].span.begin;
      int best = -1;
      for (int d : it->second) {
        const Definition& def = a_.defs[d];
        if (def.visible_begin <= at && at < def.visible_end &&
            (best < 0 || def.visible_begin > a_.defs[best].visible_begin))
          best = d;
      }
      // A function body runs when called: the top-level names defined after it
      // exist by then.
      if (best < 0 && pending_[i].in_body)
        for (int d : it->second)
          if (std::find(top_level_.begin(), top_level_.end(), d) != top_level_.end()) best = d;
      a_.refs[i].def = best;
    }
  }

  Analysis& a_;
  const AnalysisOptions& opts_;
  int fn_depth_ = 0;
  std::vector<PendingRef> pending_;
  std::vector<int> top_level_;
  std::unordered_map<std::string, std::vector<int>> by_name_;
  std::unordered_map<std::string, lang::FileId> by_path_;
};

}  // namespace

std::unique_ptr<Analysis> analyze(const std::string& path, std::string text,
                                  const AnalysisOptions& options) {
  auto t0 = std::chrono::steady_clock::now();
  auto a = std::make_unique<Analysis>();
  a->path = path;
  compile::CompileOptions copts = compile_options(options);
  Analysis* raw = a.get();
  copts.on_define = [raw](lang::Span span, const compile::Value& v) {
    TypesSeen& t = raw->types[Analysis::type_key(span)];
    if (t.count++ == 0) {
      switch (v.type) {
        case compile::Type::Number:
        case compile::Type::Bool:
        case compile::Type::Vec2:
        case compile::Type::Vec3:
          t.first = compile::to_string(v);
          break;
        case compile::Type::String:
          if (v.str().size() <= 60) t.first = compile::to_string(v);
          break;
        default:
          break;
      }
    }
    t.mask |= 1u << static_cast<unsigned>(v.type);
  };
  a->comp = compile::compile_source(path, std::move(text), copts);
  compile::run_with_large_stack([&] { Walker(*a, options).run(); });
  if (options.scene_warnings && a->comp->status == compile::CompileStatus::Ok &&
      !a->comp->diags.has_errors())
    a->scene_warnings = options.scene_warnings(a->comp->scene);
  a->milliseconds =
      std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - t0).count();
  return a;
}

namespace {
bool contains(lang::Span s, std::uint32_t offset) {
  // The end counts: a cursor just after a name is on it.
  return s.begin <= offset && offset <= s.end && s.end > s.begin;
}
}  // namespace

const Reference* Analysis::reference_at(std::uint32_t offset) const {
  auto it = std::partition_point(refs.begin(), refs.end(),
                                 [&](const Reference& r) { return r.span.end < offset; });
  for (; it != refs.end() && it->span.begin <= offset; ++it)
    if (it->span.file == main && contains(it->span, offset)) return &*it;
  return nullptr;
}

int Analysis::definition_at(std::uint32_t offset) const {
  for (std::size_t i = 0; i < defs.size(); ++i)
    if (!defs[i].imported && defs[i].span.file == main && contains(defs[i].span, offset))
      return static_cast<int>(i);
  return -1;
}

const Site* Analysis::site_at(std::uint32_t offset) const {
  for (const Site& s : sites)
    if (s.span.file == main && contains(s.span, offset)) return &s;
  return nullptr;
}

const ImportSite* Analysis::import_at(std::uint32_t offset) const {
  for (const ImportSite& s : imports)
    if (contains(s.span, offset)) return &s;
  return nullptr;
}

std::vector<const Definition*> Analysis::visible_at(std::uint32_t offset) const {
  std::vector<const Definition*> out;
  for (const Definition& d : defs)
    if (d.visible_begin <= offset && offset <= d.visible_end) out.push_back(&d);
  std::stable_sort(out.begin(), out.end(), [](const Definition* x, const Definition* y) {
    return x->visible_begin > y->visible_begin;
  });
  std::vector<const Definition*> unique;
  std::unordered_set<std::string_view> seen;
  for (const Definition* d : out)
    if (seen.insert(d->name).second) unique.push_back(d);
  return unique;
}

}  // namespace snell::lsp
