// Hovers: a block keyword shows what the block is and every property it takes;
// a property shows what it accepts, its default and whether it is required (all
// from the compiler's property registry); a name shows its kind, the types its
// value had when the program ran, and where it is defined.
#include <filesystem>

#include "compiler/builtins.hpp"
#include "compiler/compile.hpp"
#include "compiler/properties.hpp"
#include "lsp/features.hpp"

namespace snell::lsp {

namespace {

// A value as a Markdown code span whatever it holds (a string value may hold
// backticks and line breaks, which ended the span and let the rest render as
// Markdown): fenced by more backticks than its longest run, line breaks shown as
// \n.
std::string code_span(const std::string& value) {
  std::string v;
  std::size_t run = 0, longest = 0;
  for (char c : value) {
    run = c == '`' ? run + 1 : 0;
    longest = std::max(longest, run);
    if (c == '\n')
      v += "\\n";
    else if (c == '\r')
      v += "\\r";
    else
      v += c;
  }
  const std::string fence(longest + 1, '`');
  return fence + " " + v + " " + fence;
}

std::string kind_words(const compile::BlockInfo& b) {
  if (b.csg_op >= 0) return "a CSG block (§12): its body holds object statements";
  if (b.is_object) return "an object (a shape)";
  switch (b.kind) {
    case compile::BlockKind::Item:
      return "a scene item";
    case compile::BlockKind::Constructor:
      return b.pattern_kind >= 0 || b.material_kind < 0 ? "a pattern constructor"
                                                        : "a material constructor";
    case compile::BlockKind::Nested:
      return "a nested block";
  }
  return "a block";
}

std::string prop_line(const compile::PropInfo& p) {
  std::string s = "- `" + std::string(p.name) + "`: " + compile::describe(p);
  if (p.required()) s += " (required)";
  if (p.repeats()) s += " (may repeat)";
  if (p.default_value.type != compile::Type::None)
    s += "; default `" + compile::to_string(p.default_value) + "`";
  return s + "\n";
}

std::string types_words(std::uint32_t mask) {
  std::string out;
  for (unsigned t = 0; t < 32; ++t) {
    if (!(mask & (1u << t))) continue;
    auto type = static_cast<compile::Type>(t);
    if (type == compile::Type::Error || type == compile::Type::None) continue;
    out += (out.empty() ? "" : " or ") + std::string(compile::type_name(type));
  }
  return out;
}

std::string relative(const std::string& path) {
  std::error_code ec;
  std::filesystem::path p = std::filesystem::relative(path, ec);
  return ec || p.empty() ? path : p.string();
}

json markdown(const std::string& text, const json& range) {
  json h = {{"contents", {{"kind", "markdown"}, {"value", text}}}};
  if (!range.is_null()) h["range"] = range;
  return h;
}

}  // namespace

std::string describe_block(std::string_view name) {
  if (name == "object")
    return "**object** — an instance (§13): `object { EXPR ... }` places the object value "
           "EXPR with the object properties:\n\n" +
           [] {
             std::string s;
             for (const compile::PropInfo* p : compile::find_block("object")->props)
               s += prop_line(*p);
             return s;
           }();
  if (name == "background")
    return "**background** — `background EXPR`: what a ray that meets nothing sees, a colour "
           "or any pattern (§6, §17: a gradient sky, `sky_gradient`, an image with mapping "
           "\"latlong\"); at most one per scene";
  const compile::BlockInfo* b = compile::find_block(name);
  if (!b) return {};
  std::string s = "**" + std::string(name) + "** — " + kind_words(*b) + "\n\n";
  if (b->props.empty() && b->named.empty() && !b->is_object) return s;
  if (!b->props.empty() || !b->named.empty()) s += "Properties:\n\n";
  for (const compile::PropInfo* p : b->props) s += prop_line(*p);
  for (const compile::PropInfo* p : b->named) s += prop_line(*p);
  if (b->is_object) {
    s += b->props.empty() && b->named.empty() ? "The object properties:\n\n"
                                              : "\nand the object properties:\n\n";
    for (const compile::PropInfo* p : compile::find_block("object")->props) s += prop_line(*p);
  }
  return s;
}

std::string describe_property(std::string_view block, std::string_view property) {
  const compile::BlockInfo* b = compile::find_block(block);
  const compile::PropInfo* p = b ? compile::find_prop(*b, property) : nullptr;
  if (!p && (block == "object" || (b && b->csg_op >= 0)))
    p = compile::find_prop(*compile::find_block("object"), property);
  if (!p) return {};
  std::string s = "**" + std::string(property) + "** — property of `" + std::string(p->block) +
                  "`\n\naccepts " + compile::describe(*p);
  if (p->required()) s += "\n\nrequired";
  if (p->repeats()) s += "\n\nmay repeat (applies in the order written)";
  // Defaults computed from other properties, which the registry cannot hold.
  static const std::pair<std::string_view, std::string_view> kComputed[] = {
      {"camera.focal_distance", "|look_at - location| (look_at is in focus)"}};
  std::string computed;
  for (const auto& [name, text] : kComputed)
    if (name == std::string(p->block) + "." + std::string(p->name)) computed = text;
  if (p->default_value.type != compile::Type::None)
    s += "\n\ndefault: `" + compile::to_string(p->default_value) + "`";
  else if (!computed.empty())
    s += "\n\ndefault: " + computed;
  else if (!p->required())
    s += "\n\nno default (optional)";
  return s;
}

std::string describe_definition(const Analysis& a, const Definition& d) {
  std::string head;
  switch (d.kind) {
    case Definition::Let:
      head = "let " + d.name;
      break;
    case Definition::Fn: {
      head = "fn " + d.name + "(";
      if (d.stmt)
        for (std::size_t i = 0; i < d.stmt->params.size(); ++i)
          head += (i ? ", " : "") + d.stmt->params[i];
      head += ")";
      break;
    }
    case Definition::Param:
      head = d.name + " (parameter of " + (d.stmt ? d.stmt->name : std::string("?")) + ")";
      break;
    case Definition::LoopVar:
      head = d.name + " (loop variable)";
      break;
  }
  std::string s = "```snell\n" + head + "\n```\n";
  if (d.kind == Definition::Fn) {
    s += "\nfunction";
  } else if (d.kind == Definition::LoopVar) {
    s += "\nnumber";
  } else if (auto it = a.types.find(Analysis::type_key(d.span)); it != a.types.end()) {
    s += "\n" + types_words(it->second.mask);
    if (it->second.count == 1 && !it->second.first.empty())
      s += " = " + code_span(it->second.first);
    if (it->second.count > 1) s += " (bound " + std::to_string(it->second.count) + " times)";
  } else {
    s += "\n(not evaluated)";
  }
  if (d.span.file < a.comp->sources.size()) {
    const lang::SourceFile& f = a.comp->sources.file(d.span.file);
    lang::LineCol lc = f.line_col(d.span.begin);
    s += "\n\ndefined at " + (d.span.file == a.main
                                  ? std::string("line ") + std::to_string(lc.line)
                                  : relative(f.path()) + ":" + std::to_string(lc.line));
  }
  return s;
}

json hover(const Locator& at, std::uint32_t offset) {
  const Analysis& a = at.analysis;
  if (const Reference* r = a.reference_at(offset)) {
    if (r->def >= 0) return markdown(describe_definition(a, a.defs[r->def]), at.range(r->span));
    const lang::SourceFile& f = a.main_file();
    std::string name(f.text().substr(r->span.begin, r->span.end - r->span.begin));
    for (const compile::PredeclaredName& p : compile::kPredeclared)
      if (name == p.name)
        return markdown("```snell\n" + name + "\n```\n" + p.doc, at.range(r->span));
    int b = compile::find_builtin(name);
    if (b >= 0)
      return markdown("```snell\n" + std::string(compile::builtin_info(b).signature) +
                          "\n```\nbuilt-in function",
                      at.range(r->span));
    return nullptr;
  }
  if (int d = a.definition_at(offset); d >= 0)
    return markdown(describe_definition(a, a.defs[d]), at.range(a.defs[d].span));
  if (const Site* s = a.site_at(offset)) {
    std::string text = s->kind == Site::Block ? describe_block(s->block)
                                              : describe_property(s->block, s->property);
    if (text.empty()) return nullptr;
    return markdown(text, at.range(s->span));
  }
  if (const ImportSite* i = a.import_at(offset))
    return markdown(
        i->path.empty() ? "`" + i->name + "`: not found" : "imports `" + relative(i->path) + "`",
        at.range(i->span));
  return nullptr;
}

}  // namespace snell::lsp
