// One document's analysis: the real compilation (the code `snell check` runs,
// with its imports, bounded by a step budget and never rendering) plus what an
// editor asks about that the compiler does not keep: where each name is
// defined, which definition each name in the document refers to, the blocks and
// properties written, and the types values took when the program ran.
//
// Name resolution here is static, over the syntax tree, and follows §4: a name
// is visible from the end of its `let` (from its own name for a `fn`, so it can
// recurse) to the end of the enclosing scope; parameters and loop variables in
// their body; an import's top-level names from the import on. A function body
// also sees the top-level names defined after it (they exist when it is called).
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

#include "compiler/compile.hpp"
#include "language/ast.hpp"

namespace snell::lsp {

struct Definition {
  enum Kind { Let, Fn, Param, LoopVar } kind = Let;
  std::string name;
  lang::Span span;                   // the name where it is defined (any file)
  const lang::Stmt* stmt = nullptr;  // its let / fn / for statement
  // Where the main document sees it (byte offsets in the main file).
  std::uint32_t visible_begin = 0, visible_end = 0;
  bool imported = false;
  bool body_only = false;  // seen only inside function bodies (defined after them)
};

struct Reference {
  lang::Span span;
  int def = -1;  // index into Analysis::defs; -1: a builtin or undefined
};

// A block keyword or a property name written in the main document.
struct Site {
  enum Kind { Block, Property } kind = Block;
  lang::Span span;
  std::string block;     // the block the keyword opens, or the property belongs to
  std::string property;  // Property sites
};

struct ImportSite {
  lang::Span span;                 // the quoted file name (the statement when it has none)
  std::string name;                // as written
  std::string path;                // where it resolves, empty when nowhere
  lang::FileId file = UINT32_MAX;  // its parsed file, when it could be read
};

// The types a binding's values had while the program ran (a bit per
// compile::Type), and the first value in words when it is short.
struct TypesSeen {
  std::uint32_t mask = 0;
  std::string first;
  std::uint64_t count = 0;
};

struct AnalysisOptions {
  std::vector<std::string> include_dirs;
  // Bounds the evaluation per keystroke (the CLI's default is for renders).
  std::uint64_t step_budget = 5'000'000;
  std::size_t max_errors = 200;
  // Open documents by canonical path (they win over the disk for imports).
  std::function<const std::string*(const std::string& canonical_path)> overlay;
  // Their canonical paths (import completion offers the unsaved ones too); null:
  // none.
  std::function<std::vector<std::string>()> open_documents;
  // §17: images the texture system cannot read (compile::CompileOptions'); null:
  // only existence and signature are checked.
  decltype(compile::CompileOptions::unreadable_images) unreadable_images;
  // The warnings `snell check` prints about a scene as a whole (no light, the
  // camera inside an object: rt::scene_warnings, which the runtime owns), each
  // with the object it is about; null: none.
  using SceneWarnings = std::vector<std::pair<std::string, ir::SourceRef>>;
  std::function<SceneWarnings(const ir::Scene&)> scene_warnings;
};

struct Analysis {
  std::unique_ptr<compile::Compilation> comp;
  lang::FileId main = 0;
  std::string path;
  std::vector<Definition> defs;
  std::vector<Reference> refs;  // in the main file, in source order
  std::vector<Site> sites;      // in the main file, in source order
  std::vector<ImportSite> imports;
  std::unordered_map<std::uint64_t, TypesSeen> types;  // by type_key(span)
  AnalysisOptions::SceneWarnings scene_warnings;       // of a scene without errors
  double milliseconds = 0;                             // the whole analysis

  const lang::SourceFile& main_file() const { return comp->sources.file(main); }
  const lang::Program* main_program() const {
    return comp->programs.empty() ? nullptr : comp->programs.front().get();
  }
  static std::uint64_t type_key(lang::Span s) { return (std::uint64_t(s.file) << 32) | s.begin; }

  // What the main document has at byte `offset` (null / -1 when nothing).
  const Reference* reference_at(std::uint32_t offset) const;
  int definition_at(std::uint32_t offset) const;  // a definition's own name in main
  const Site* site_at(std::uint32_t offset) const;
  const ImportSite* import_at(std::uint32_t offset) const;
  // The definitions visible at `offset`, innermost first, one per name.
  std::vector<const Definition*> visible_at(std::uint32_t offset) const;
};

std::unique_ptr<Analysis> analyze(const std::string& path, std::string text,
                                  const AnalysisOptions& options);

// The options the compiler gets for an analysis (imports resolved as the CLI does).
compile::CompileOptions compile_options(const AnalysisOptions& options);

}  // namespace snell::lsp
