// Completion. What fits at the cursor is read from the tokens before it (the
// text being typed rarely parses): the braces say which block the cursor is
// in, and the token just before it whether a statement, a property name or a
// value comes next. Then:
//   statement start  statement keywords, scene item blocks, names in scope
//   property name    the block's properties not yet given (repeatable ones always)
//   value            names in scope, builtins, constructors, object blocks
//   import "…"       .scn files where imports are searched (§9)
//   NAME "…"         the spellings of an enum property (settings { sampler "…" })
// Every block, property, builtin and constructor name comes from the compiler's tables.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <set>

#include "compiler/builtins.hpp"
#include "compiler/compile.hpp"
#include "compiler/properties.hpp"
#include "language/lexer.hpp"
#include "lsp/features.hpp"

namespace snell::lsp {

namespace fs = std::filesystem;
using lang::TokenKind;

namespace {

// LSP CompletionItemKind values.
enum ItemKind {
  kFunction = 3,
  kConstructor = 4,
  kVariable = 6,
  kClass = 7,
  kProperty = 10,
  kValue = 12,
  kKeyword = 14,
  kFile = 17,
  kFolder = 19
};

constexpr std::string_view kConstructors[] = {
#define SNELL_CONSTRUCTOR(name, type) #name,
#include "language/constructors.def"
};

json item(std::string label, int kind, std::string detail = "", std::string doc = "") {
  json j = {{"label", std::move(label)}, {"kind", kind}};
  if (!detail.empty()) j["detail"] = std::move(detail);
  if (!doc.empty()) j["documentation"] = {{"kind", "markdown"}, {"value", std::move(doc)}};
  return j;
}

struct Frame {
  enum Kind { Statements, Block, Group, Instance } kind = Statements;
  std::string block;
  std::set<std::string> given;
};

const compile::PropInfo* prop_of(const Frame& f, std::string_view name) {
  if (f.kind == Frame::Statements || name.empty()) return nullptr;
  const compile::BlockInfo* b = compile::find_block(f.kind == Frame::Instance ? "object" : f.block);
  return b ? compile::find_prop(*b, name) : nullptr;
}

bool is_prop_of(const Frame& f, std::string_view name) {
  return prop_of(f, name) != nullptr;
}

// The spellings a settings enum property takes (runtime/ir/kinds.def).
std::vector<std::string_view> enum_spellings(compile::PropType t) {
  switch (t) {
#define SNELL_ENUM(Type, VALUES)              \
  case compile::PropType::Type: {             \
    const auto s = ir::spellings<ir::Type>(); \
    return {std::begin(s), std::end(s)};      \
  }
#include "runtime/ir/kinds.def"
    default:
      return {};
  }
}

// True when a value may end with this token (so a property name or a new
// statement may follow).
bool ends_value(const lang::Token& t, const Frame& f) {
  switch (t.kind) {
    case TokenKind::Number:
    case TokenKind::String:
    case TokenKind::KwTrue:
    case TokenKind::KwFalse:
    case TokenKind::RParen:
    case TokenKind::Greater:
    case TokenKind::RBrace:
      return true;
    case TokenKind::Identifier:
      return !is_prop_of(f, t.text) && !lang::is_constructor_name(t.text);
    default:
      return false;
  }
}

void add_names(const Analysis& a, std::uint32_t offset, json& out) {
  for (const Definition* d : a.visible_at(offset))
    out.push_back(item(d->name, d->kind == Definition::Fn ? kFunction : kVariable,
                       d->imported ? "imported" : "", describe_definition(a, *d)));
}

void add_values(const Analysis& a, std::uint32_t offset, json& out) {
  add_names(a, offset, out);
  // noise, fbm and cells are builtins and pattern constructors both: one item each,
  // which says so (editors showed every such name twice).
  for (int i = 0; i < compile::builtin_count(); ++i) {
    const compile::BuiltinInfo& b = compile::builtin_info(i);
    const bool also = std::find(std::begin(kConstructors), std::end(kConstructors), b.name) !=
                      std::end(kConstructors);
    out.push_back(item(std::string(b.name), kFunction,
                       std::string(b.signature) + (also ? "; or a pattern constructor" : ""),
                       also ? describe_block(b.name) : ""));
  }
  for (std::string_view c : kConstructors)
    if (compile::find_builtin(c) < 0)
      out.push_back(item(std::string(c), kConstructor, "constructor", describe_block(c)));
  for (std::string_view b : compile::block_names(compile::BlockKind::Item)) {
    const compile::BlockInfo* info = compile::find_block(b);
    if (info && info->is_object)
      out.push_back(item(std::string(b), kClass, "object value", describe_block(b)));
  }
  out.push_back(item("true", kValue));
  out.push_back(item("false", kValue));
  for (const compile::PredeclaredName& p : compile::kPredeclared)
    out.push_back(item(p.name, kVariable, "predeclared", p.doc));
}

// `in_csg`: a CSG body's statements, which hold objects only (§12: settings, the
// camera, lights and the background there are NotInsideCsg errors).
void add_statements(const Analysis& a, std::uint32_t offset, json& out, bool in_csg = false) {
  for (TokenKind k : {TokenKind::KwLet, TokenKind::KwFn, TokenKind::KwFor, TokenKind::KwIf,
                      TokenKind::KwImport, TokenKind::KwReturn})
    out.push_back(item(std::string(lang::token_spelling(k)), kKeyword));
  for (std::string_view b : compile::block_names(compile::BlockKind::Item)) {
    if (const compile::BlockInfo* info = compile::find_block(b); in_csg && info && !info->is_object)
      continue;
    out.push_back(item(std::string(b), kClass, "scene item", describe_block(b)));
  }
  out.push_back(item("object", kClass, "instance", describe_block("object")));
  if (!in_csg) out.push_back(item("background", kKeyword, "background COLOUR_OR_PATTERN"));
  add_names(a, offset, out);
}

void add_properties(const Frame& f, json& out) {
  std::string name = f.kind == Frame::Instance ? "object" : f.block;
  const compile::BlockInfo* b = compile::find_block(name);
  if (!b) return;
  std::vector<const compile::PropInfo*> props(b->props.begin(), b->props.end());
  props.insert(props.end(), b->named.begin(), b->named.end());
  if (b->is_object)
    for (const compile::PropInfo* p : compile::find_block("object")->props) props.push_back(p);
  for (const compile::PropInfo* p : props) {
    if (!p->repeats() && f.given.count(std::string(p->name))) continue;
    out.push_back(item(std::string(p->name), kProperty, compile::describe(*p),
                       describe_property(p->block, p->name)));
  }
}

void add_imports(const Analysis& a, std::string_view typed, const AnalysisOptions& options,
                 json& out) {
  std::vector<std::string> dirs;
  compile::find_import("", a.path, compile_options(options), &dirs);
  std::string sub(
      typed.substr(0, typed.rfind('/') == std::string_view::npos ? 0 : typed.rfind('/') + 1));
  std::set<std::string> seen;
  std::string self = fs::path(a.path).filename().string();
  for (const std::string& d : dirs) {
    std::error_code ec;
    fs::path dir = fs::path(d.empty() ? "." : d) / sub;
    int n = 0;
    for (auto it = fs::directory_iterator(dir, ec); !ec && it != fs::directory_iterator();
         it.increment(ec)) {
      if (++n > 2000) break;  // a huge folder: enough
      std::string name = it->path().filename().string();
      if (name.empty() || name[0] == '.') continue;
      bool folder = it->is_directory(ec);
      if (!folder &&
          (it->path().extension() != ".scn" || (sub.empty() && d == dirs.front() && name == self)))
        continue;
      std::string label = name + (folder ? "/" : "");
      if (!seen.insert(label).second) continue;
      out.push_back(item(label, folder ? kFolder : kFile, (fs::path(d) / sub / name).string()));
    }
    // Open documents not saved there yet count for imports, so they are offered.
    if (!options.open_documents) continue;
    const fs::path here = fs::weakly_canonical(dir, ec);
    for (const std::string& open : options.open_documents()) {
      const fs::path p(open);
      const std::string name = p.filename().string();
      if (p.parent_path() != here || p.extension() != ".scn" || name.empty() || name[0] == '.' ||
          (sub.empty() && d == dirs.front() && name == self) || !seen.insert(name).second)
        continue;
      out.push_back(item(name, kFile, open + " (open, unsaved)"));
    }
  }
}

// Whether `offset` is inside a string on its line, and where that string began.
bool in_string(std::string_view text, std::uint32_t offset, std::uint32_t& open) {
  std::uint32_t line = offset;
  while (line > 0 && text[line - 1] != '\n') --line;
  bool inside = false;
  for (std::uint32_t i = line; i < offset; ++i) {
    char c = text[i];
    if (inside && c == '\\') {
      ++i;
      continue;
    }
    if (!inside && c == '/' && i + 1 < offset && text[i + 1] == '/') return false;  // comment
    if (c == '"') {
      inside = !inside;
      open = i;
    }
  }
  return inside;
}

// Whether `offset` is inside a comment, `//` or `/* */` (one never closed too),
// read from the start of the text as the lexer reads it: strings end at their
// quote or line, and a comment's opener inside a string is none.
bool in_comment(std::string_view text, std::uint32_t offset) {
  enum { Code, String, Line, Block } state = Code;
  for (std::uint32_t i = 0; i < offset; ++i) {
    const char c = text[i], next = i + 1 < text.size() ? text[i + 1] : '\0';
    switch (state) {
      case Code:
        if (c == '"') state = String;
        if (c == '/' && next == '/') state = Line, ++i;
        if (c == '/' && next == '*') state = Block, ++i;
        break;
      case String:
        if (c == '\\') ++i;
        if (c == '"' || c == '\n') state = Code;
        break;
      case Line:
        if (c == '\n') state = Code;
        break;
      case Block:
        if (c == '*' && next == '/' && i + 1 < offset) state = Code, ++i;
        break;
    }
  }
  return state == Line || state == Block;
}

}  // namespace

json completion(const Locator& at, std::string_view text, std::uint32_t offset,
                const AnalysisOptions& options) {
  const Analysis& a = at.analysis;
  json out = json::array();
  offset = std::min<std::uint32_t>(offset, static_cast<std::uint32_t>(text.size()));
  if (in_comment(text, offset)) return out;
  std::uint32_t open = 0;
  bool string = in_string(text, offset, open);
  // The word before an opening quote: `import "…"`, or a property `sampler "…"`.
  std::string_view before_quote;
  if (string) {
    std::uint32_t k = open;
    while (k > 0 && (text[k - 1] == ' ' || text[k - 1] == '\t')) --k;
    std::uint32_t w = k;
    while (w > 0 && (std::isalnum(static_cast<unsigned char>(text[w - 1])) || text[w - 1] == '_'))
      --w;
    before_quote = text.substr(w, k - w);
    if (before_quote == "import") {
      const std::string_view typed = text.substr(open + 1, offset - open - 1);
      add_imports(a, typed, options, out);
      // Each replaces what is typed inside the quotes: a client left to itself
      // replaces the word before the cursor only, and "colors." + "colors.scn"
      // became "colors.colors.scn".
      const std::size_t slash = typed.rfind('/');
      const std::string sub(typed.substr(0, slash == std::string_view::npos ? 0 : slash + 1));
      const json range = LineIndex(text).range(open + 1, offset, at.encoding);
      for (json& it : out) {
        const std::string path = sub + it["label"].get<std::string>();
        it["textEdit"] = {{"range", range}, {"newText", path}};
        it["filterText"] = path;
      }
      return out;
    }
  }

  lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  diags.set_max_errors(1);
  std::uint32_t until = string ? open : offset;
  std::vector<lang::Token> tokens =
      lang::lex(sources, sources.add("completion", std::string(text.substr(0, until))), diags);
  // The word being typed is not context.
  std::size_t n = tokens.size() - 1;  // without EndOfFile
  if (!string && n > 0 && tokens[n - 1].span.end == offset &&
      (tokens[n - 1].kind == TokenKind::Identifier ||
       lang::keyword_kind(tokens[n - 1].text) != TokenKind::Identifier))
    --n;
  std::vector<Frame> frames(1);
  for (std::size_t i = 0; i < n; ++i) {
    const lang::Token& t = tokens[i];
    if (t.kind == TokenKind::LBrace) {
      Frame f;
      if (i > 0 && tokens[i - 1].kind == TokenKind::Identifier) {
        std::string word(tokens[i - 1].text);
        if (lang::is_instance_name(word)) {
          f.kind = Frame::Instance;
        } else if (lang::is_group_name(word)) {
          f.kind = Frame::Group;
          f.block = word;
        } else if (compile::find_block(word)) {
          f.kind = Frame::Block;
          f.block = word;
        }
      }
      frames.push_back(std::move(f));
    } else if (t.kind == TokenKind::RBrace) {
      if (frames.size() > 1) frames.pop_back();
    } else if (t.kind == TokenKind::Identifier && is_prop_of(frames.back(), t.text)) {
      frames.back().given.insert(std::string(t.text));
    }
  }
  if (frames.size() > 1 && !string) {
    // The block's properties after the cursor are given too (`checker { color1 0 |
    // color2 1 }` offers no second color2): its own level, up to its '}'.
    std::vector<lang::Token> rest =
        lang::lex(sources, sources.add("after", std::string(text.substr(offset))), diags);
    int depth = 0;
    for (const lang::Token& t : rest) {
      if (t.kind == TokenKind::LBrace) ++depth;
      if (t.kind == TokenKind::RBrace && --depth < 0) break;
      if (depth == 0 && t.kind == TokenKind::Identifier && t.span.begin > 0 &&
          is_prop_of(frames.back(), t.text))
        frames.back().given.insert(std::string(t.text));
    }
  }
  if (string) {
    // An enum property's spellings (settings { sampler "…" }).
    if (const compile::PropInfo* p = prop_of(frames.back(), before_quote))
      for (std::string_view v : enum_spellings(p->type))
        out.push_back(item(std::string(v), kValue, compile::describe(*p)));
    return out;
  }
  const Frame& f = frames.back();
  const lang::Token* prev = n > 0 ? &tokens[n - 1] : nullptr;
  bool after_open = !prev || prev->kind == TokenKind::LBrace;
  bool statement_start =
      after_open || prev->kind == TokenKind::Semicolon || prev->kind == TokenKind::RBrace;
  // A new name is being written: nothing to offer.
  if (prev && (prev->kind == TokenKind::KwLet || prev->kind == TokenKind::KwFn ||
               prev->kind == TokenKind::KwFor || prev->kind == TokenKind::Dot))
    return out;
  switch (f.kind) {
    case Frame::Statements:
      if (statement_start)
        add_statements(a, offset, out);
      else
        add_values(a, offset, out);
      break;
    case Frame::Group:
      if (statement_start || ends_value(*prev, f)) {
        add_statements(a, offset, out, /*in_csg=*/true);
        add_properties(f, out);
      } else {
        add_values(a, offset, out);
      }
      break;
    case Frame::Instance:
      if (after_open) {
        add_values(a, offset, out);
        break;
      }
      [[fallthrough]];
    case Frame::Block:
      if (after_open || ends_value(*prev, f))
        add_properties(f, out);
      else
        add_values(a, offset, out);
      break;
  }
  return out;
}

}  // namespace snell::lsp
