// The registries agree with each other and with the tests: language/constructors.def
// (what the parser reads as a constructor) with compiler/properties.def (what the
// compiler builds), every property's default with its own check, and every kind of
// language/diagnostics.def with a test that produces it. Every list here is
// computed from the .def files through their X-macros and from the test folders,
// so a row added to one table and forgotten in another fails here.
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "compiler/builtins.hpp"
#include "compiler/lower.hpp"
#include "compiler/povray_forms.hpp"
#include "compiler/properties.hpp"
#include "language/ast.hpp"
#include "language/diagnostics.hpp"
#include "language/token.hpp"

using namespace snell;
using namespace snell::compile;
namespace fs = std::filesystem;

namespace {

struct ConstructorRow {
  std::string name, result;  // result: "material" or "pattern"
};
const std::vector<ConstructorRow> kConstructors = {
#define SNELL_CONSTRUCTOR(name, result) {#name, #result},
#define SNELL_BLOCK_CONSTRUCTOR(name, result) {#name, #result},
#include "language/constructors.def"
};

struct BlockRow {
  std::string name;
  BlockKind kind;
};
const std::vector<BlockRow> kBlocks = {
#define SNELL_BLOCK(name, kind) {#name, BlockKind::kind},
#define SNELL_PROP(block, name, type, check, flags, def)
#define SNELL_SETTING(name, type, check, def)
#include "compiler/properties.def"
};

struct PropRow {
  std::string block, name;
};
const std::vector<PropRow> kProps = {
#define SNELL_BLOCK(name, kind)
#define SNELL_PROP(block, name, type, check, flags, def) {#block, #name},
#define SNELL_SETTING(name, type, check, def) {"settings", #name},
#include "compiler/properties.def"
};

using test::slurp;

// A value the property accepts, to build a constructor with: its default, else
// a plain value of its type (none when the type has no plain value).
Value sample_value(const PropInfo& p) {
  if (p.default_value.type != Type::None) return p.default_value;
  switch (p.type) {
    case PropType::Number:
    case PropType::Integer:
      return Value::number(1);
    case PropType::Vec2:
    case PropType::IntVec2:
      return Value::vec2(1, 1);
    case PropType::Vec3:
    case PropType::Color:
    case PropType::ColorOrPattern:
      return Value::vec3({1, 1, 1});
    case PropType::Bool:
      return Value::boolean(false);
    case PropType::String:  // a file's name (make_constructor_value does not read it)
      return Value::string("file");
    case PropType::Function: {
      auto f = std::make_shared<snell::compile::Closure>();
      f->builtin = 0;
      return Value::of_function(f);
    }
    default:
      return Value::none();
  }
}

std::string result_of(const Value& v) {
  if (v.type == Type::Material) return "material";
  if (v.type == Type::Pattern) return "pattern";
  return "neither";
}

// Whether `text` holds `word` as a whole identifier (not inside a longer one).
bool names_word(const std::string& text, const std::string& word) {
  auto ident = [](char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; };
  for (std::size_t at = text.find(word); at != std::string::npos; at = text.find(word, at + 1)) {
    bool left = at == 0 || !ident(text[at - 1]);
    bool right = at + word.size() == text.size() || !ident(text[at + word.size()]);
    if (left && right) return true;
  }
  return false;
}

// Kinds expected by a tests/lang case that some runner runs (a `// test:` first
// line): the last word of each `// expect:` comment. File names per kind.
std::map<std::string, std::set<std::string>> lang_cases() {
  std::map<std::string, std::set<std::string>> out;
  for (const auto& e : fs::recursive_directory_iterator(SNELL_LANG_TEST_DIR)) {
    if (!e.is_regular_file() || e.path().extension() != ".scn") continue;
    std::string text = slurp(e.path());
    if (text.rfind("// test:", 0) != 0) continue;
    std::istringstream in(text);
    std::string line;
    while (std::getline(in, line)) {
      std::size_t at = line.find("// expect:");
      if (at == std::string::npos) continue;
      std::istringstream words(line.substr(at + 10));
      std::string w, last;
      while (words >> w) last = w;
      out[last].insert(fs::relative(e.path(), SNELL_LANG_TEST_DIR).string());
    }
  }
  return out;
}

// C++ test files, other than the ones that only check coverage (they name every
// kind without producing any).
std::vector<fs::path> test_sources() {
  const std::set<std::string> coverage_only = {"test_lang_files.cpp", "test_compile_files.cpp",
                                               "test_registry.cpp"};
  std::vector<fs::path> out;
  for (const auto& e : fs::recursive_directory_iterator(fs::path(SNELL_SOURCE_DIR) / "tests")) {
    std::string ext = e.path().extension().string();
    if (e.is_regular_file() && (ext == ".cpp" || ext == ".hpp") &&
        !coverage_only.count(e.path().filename().string()))
      out.push_back(e.path());
  }
  return out;
}

}  // namespace

TEST_CASE("registry: constructors.def and properties.def name the same constructors",
          "[compiler][registry]") {
  REQUIRE(!kConstructors.empty());
  std::set<std::string> in_parser, in_compiler;
  for (const ConstructorRow& c : kConstructors) in_parser.insert(c.name);
  for (const BlockRow& b : kBlocks)
    if (b.kind == BlockKind::Constructor) in_compiler.insert(b.name);
  CHECK(in_parser == in_compiler);

  for (const ConstructorRow& c : kConstructors) {
    INFO("constructor " << c.name << " (constructors.def: " << c.result << ")");
    CHECK((c.result == "material" || c.result == "pattern"));
    const BlockInfo* block = find_block(c.name);
    REQUIRE(block);
    CHECK(block->kind == BlockKind::Constructor);
    // The kind it makes is what the compiler builds from it, every property at
    // its default.
    std::vector<EvaluatedProp> props;
    for (const PropInfo* p : block->props) {
      EvaluatedProp e;
      e.info = p;
      e.value = sample_value(*p);
      INFO("property " << p->name);
      REQUIRE(e.value.type != Type::None);
      std::string err = check_value(*p, e.value);
      REQUIRE(err.empty());
      props.push_back(std::move(e));
    }
    snell::lang::SourceManager sources;
    snell::lang::DiagnosticEngine diags(sources);
    CHECK(result_of(make_constructor_value(*block, props, diags)) == c.result);
  }
}

TEST_CASE("registry: every property is described and its default passes its own check",
          "[compiler][registry]") {
  REQUIRE(kProps.size() == static_cast<std::size_t>(kPropCount));
  for (const PropRow& row : kProps) {
    INFO(row.block << "." << row.name);
    const BlockInfo* block = find_block(row.block);
    REQUIRE(block);
    const PropInfo* p = find_prop(*block, row.name);
    REQUIRE(p);
    CHECK(p->block == row.block);
    CHECK(!describe(*p).empty());
    bool has_default = p->default_value.type != Type::None;
    // A required property's default would never be used.
    CHECK(!(p->required() && has_default));
    if (!has_default) continue;
    Value v = p->default_value;
    bool integral = false;
    std::string err = check_value(*p, v, &integral);
    INFO("describe: " << describe(*p) << "; check_value: " << err);
    CHECK(err.empty());
    Value w = p->default_value;
    CHECK(value_ok(*p, w));  // the hot path decides as check_value does
  }
}

TEST_CASE("registry: every diagnostic kind has a test that produces it", "[compiler][registry]") {
  std::map<std::string, std::set<std::string>> cases = lang_cases();
  REQUIRE(!cases.empty());
  std::vector<std::pair<fs::path, std::string>> sources;
  for (const fs::path& p : test_sources()) sources.push_back({p, slurp(p)});
  REQUIRE(!sources.empty());

  // Kinds no .scn case can produce (FileTooLarge needs a 100 MB file) are
  // covered by a C++ test that names them; the rest have no test at all.
  std::string missing, elsewhere;
  for (lang::DiagKind k : lang::all_diag_kinds()) {
    std::string name(lang::diag_name(k));
    if (cases.count(name)) continue;
    std::string where;
    for (const auto& [path, text] : sources)
      if (names_word(text, name)) where += " " + path.filename().string();
    if (where.empty())
      missing += " " + name;
    else
      elsewhere += "  " + name + ":" + where + "\n";
  }
  INFO("no tests/lang case, named by a test:\n" << elsewhere);
  INFO("no tests/lang case and no test naming them:" << missing);
  CHECK(missing.empty());
}

namespace {
struct KindRow {
  std::string name, family;  // family: "shape", "material" or "pattern"
};
const std::vector<KindRow> kKinds = {
#define SNELL_SHAPE(name, Type) {#name, "shape"},
#define SNELL_MATERIAL(name, Type) {#name, "material"},
#define SNELL_PATTERN(name, Type) {#name, "pattern"},
#include "runtime/ir/kinds.def"
};

// The field names of every kind struct, by kind name.
std::map<std::string, std::vector<std::string>> kind_fields() {
  std::map<std::string, std::vector<std::string>> out;
  auto add = [&](const auto& kind) {
    using T = std::decay_t<decltype(kind)>;
    ir::for_each_field(
        kind, [&](const char* f, const auto&) { out[ir::KindName<T>::value].push_back(f); });
  };
#define SNELL_SHAPE(name, Type) add(ir::Type{});
#define SNELL_MATERIAL(name, Type) add(ir::Type{});
#define SNELL_PATTERN(name, Type) add(ir::Type{});
#include "runtime/ir/kinds.def"
  return out;
}
}  // namespace

const std::set<std::string> kCommonPatternProps = {
    "color_map", "turbulence", "octaves", "translate", "rotate", "scale", "space"};

TEST_CASE("registry: every IR kind of kinds.def is a block of properties.def, bound field by field",
          "[registry]") {
  auto fields = kind_fields();
  for (const KindRow& k : kKinds) {
    INFO(k.family << " " << k.name);
    if (k.name == "constant") continue;  // a plain colour: no block in the language
    const BlockInfo* b = find_block(k.name);
    REQUIRE(b);
    if (k.family == "pattern")
      for (const std::string& common : kCommonPatternProps) {
        INFO("common property " << common);
        CHECK(find_prop(*b, common));
      }
    if (k.family == "shape") {
      CHECK(b->kind == BlockKind::Item);
      CHECK(b->shape_kind >= 0);
      CHECK(b->is_object);
    } else {
      CHECK(b->kind == BlockKind::Constructor);
      CHECK((k.family == "material" ? b->material_kind : b->pattern_kind) >= 0);
    }
    // Every property of the block is a field of the kind's struct, except those a
    // kind's lowering hook reads itself (lower_kinds.cpp): the mesh's file.
    std::vector<const PropInfo*> all = b->props;
    all.insert(all.end(), b->named.begin(), b->named.end());
    for (const PropInfo* p : all) {
      INFO("property " << p->name);
      // A Named property is never positional, so it cannot be required or defaulted,
      // but for the IR's default it shows (hovers): never added to a block.
      if (p->named_only())
        CHECK((!p->required() && (p->default_from_ir || p->default_value.type == Type::None)));
      // §15's properties common to every pattern are the Texture's, not the kind's
      // (lower_kinds.cpp common_pattern_props).
      bool hooked = (k.name == "mesh" && p->name == "file") ||
                    (k.family == "material" && p->name == "bump") ||   // ir::Material::bump
                    (k.name == "pattern" && p->name == "function") ||  // compiled: ::program
                    (k.name == "image" && p->name == "file") ||        // numbered: ::image
                    (k.family == "pattern" && kCommonPatternProps.count(std::string(p->name)));
      bool field = std::count(fields[k.name].begin(), fields[k.name].end(), p->name) > 0;
      CHECK((field || hooked));
    }
  }
  // No block is a kind the IR lacks: every Constructor block is a material or a
  // pattern kind, every object block a shape kind.
  for (const BlockRow& b : kBlocks) {
    const BlockInfo* info = find_block(b.name);
    REQUIRE(info);
    if (b.kind == BlockKind::Constructor)
      CHECK((info->material_kind >= 0 || info->pattern_kind >= 0));
  }
}

TEST_CASE("registry: every IR-bound default was filled from the IR", "[registry]") {
  for (const PropRow& r : kProps) {
    const BlockInfo* b = find_block(r.block);
    REQUIRE(b);
    const PropInfo* p = find_prop(*b, r.name);
    REQUIRE(p);
    INFO(r.block << "." << r.name);
    if (p->default_from_ir) CHECK(p->default_value.type != Type::None);
  }
  // The IR's defaults are what the language promises (spec §5-§8): a sample.
  CHECK(find_prop(*find_block("settings"), "sampler")->default_value.str() == "stratified");
  CHECK(find_prop(*find_block("diffuse"), "color")->default_value.v == ir::Vec3(0.8));
  CHECK(find_prop(*find_block("settings"), "resolution")->default_value.v == ir::Vec3(640, 480, 0));
}

TEST_CASE("registry: enum spellings parse back to their enumerators", "[registry]") {
  auto round_trip = [](auto tag) {
    using E = decltype(tag);
    auto all = ir::spellings<E>();
    for (std::size_t i = 0; i < all.size(); ++i) {
      E e{};
      REQUIRE(ir::parse_enum(all[i], e));
      CHECK(std::size_t(e) == i);
      CHECK(ir::spelling(e) == all[i]);
    }
    E e{};
    CHECK_FALSE(ir::parse_enum("no-such-value", e));
  };
#define SNELL_ENUM(Type, VALUES) round_trip(ir::Type{});
#include "runtime/ir/kinds.def"
  round_trip(ir::ShapeKind{});
  round_trip(ir::MaterialKind{});
  round_trip(ir::PatternKind{});
}

TEST_CASE("registry: groups.def's CSG blocks, instance block and object properties agree",
          "[registry]") {
  // Every CSG block is a CsgOp spelling and a block of properties.def that takes
  // the object properties; and the reverse.
  std::set<std::string> groups;
#define SNELL_GROUP(name) groups.insert(#name);
#include "language/groups.def"
  std::set<std::string> ops;
  for (std::string_view s : ir::spellings<ir::CsgOp>()) ops.insert(std::string(s));
  CHECK(groups == ops);
  for (const std::string& g : groups) {
    INFO(g);
    const BlockInfo* b = find_block(g);
    REQUIRE(b);
    CHECK(b->kind == BlockKind::Item);
    CHECK(b->is_object);
    CHECK(b->csg_op >= 0);
    CHECK(lang::is_group_name(g));
  }
  // The instance keyword is the `object` block, whose properties are the Obj rows.
  std::set<std::string> instance;
#define SNELL_INSTANCE(name) instance.insert(#name);
#include "language/groups.def"
  CHECK(instance == std::set<std::string>{"object"});
  std::set<std::string> listed, obj_rows;
#define SNELL_OBJECT_PROP(name) listed.insert(#name);
#include "language/groups.def"
  for (const PropInfo* p : find_block("object")->props) obj_rows.insert(std::string(p->name));
  CHECK(listed == obj_rows);
  for (const std::string& p : listed) CHECK(lang::is_object_property(p));
  CHECK_FALSE(lang::is_object_property("radius"));
  // The statement blocks are properties.def's Item rows and the instance keyword,
  // and no block has a property of their names (the parser's missing-'}' hint).
  std::set<std::string> items, item_rows = {"object"};
#define SNELL_ITEM(name) items.insert(#name);
#include "language/groups.def"
#include "tests/compiler/compile_util.hpp"
  for (std::string_view b : block_names(BlockKind::Item)) item_rows.insert(std::string(b));
  CHECK(items == item_rows);
  for (const std::string& i : items) CHECK(lang::is_item_name(i));
  CHECK_FALSE(lang::is_item_name("material"));
  for (BlockKind k : {BlockKind::Item, BlockKind::Constructor, BlockKind::Nested})
    for (std::string_view b : block_names(k))
      if (const BlockInfo* info = find_block(b))
        for (std::string_view p : prop_names(*info)) {
          INFO(b << "." << p);
          CHECK(items.count(std::string(p)) == 0);
          CHECK(p != "background");  // a statement's word, also a missing '}'s sign
        }
}

// povray_words.def's notes stand in for "did you mean" only where the word is none
// of Snell's own: no block, property, builtin or keyword of that name, so a note
// never hides a real name.
TEST_CASE("registry: POV-Ray's words are none of Snell's names", "[compiler][registry]") {
  std::set<std::string_view> snell_names;
  for (BlockKind k : {BlockKind::Item, BlockKind::Constructor, BlockKind::Nested})
    for (std::string_view b : block_names(k)) {
      snell_names.insert(b);
      if (const BlockInfo* info = find_block(b))
        for (std::string_view p : prop_names(*info)) snell_names.insert(p);
    }
  for (int i = 0; i < builtin_count(); ++i) snell_names.insert(builtin_info(i).name);
  REQUIRE(!povray_words().empty());
  for (const PovrayWord& w : povray_words()) {
    INFO("word " << w.word);
    if (w.scope == "any") {
      CHECK(!snell_names.count(w.word));
    } else {  // a property word of one block: none of that block's, which exists
      const BlockInfo* b = find_block(w.scope);
      REQUIRE(b);
      for (std::string_view p : prop_names(*b)) CHECK(p != w.word);
    }
    CHECK(lang::keyword_kind(w.word) == lang::TokenKind::Identifier);
    CHECK(!w.note.empty());
    CHECK(povray_note(w.kind, w.word, w.scope) == w.note.data());
  }
  // A camera word's note is the camera's only.
  CHECK(povray_note(PovrayWordKind::Property, "angle", "camera") != nullptr);
  CHECK(povray_note(PovrayWordKind::Property, "angle", "sphere") == nullptr);
  CHECK(povray_note(PovrayWordKind::Name, "radius") == nullptr);
}
