#include "compiler/povray_forms.hpp"

namespace snell::compile {

namespace {

const PovrayForm kForms[] = {
#define SNELL_POVRAY(block, props) {#block, props},
#include "compiler/povray_forms.def"
};

// Runs of whitespace (a value written over several lines) become one space.
std::string one_line(std::string_view text) {
  std::string out;
  bool space = false;
  for (char c : text) {
    bool ws = c == ' ' || c == '\t' || c == '\n' || c == '\r';
    if (ws) {
      space = !out.empty();
      continue;
    }
    if (space) out += ' ';
    space = false;
    out += c;
  }
  return out;
}

}  // namespace

std::vector<std::string_view> PovrayForm::props() const {
  std::vector<std::string_view> out;
  std::size_t i = 0;
  while (i < order.size()) {
    while (i < order.size() && (order[i] == ' ' || order[i] == '[' || order[i] == ']')) ++i;
    std::size_t j = i;
    while (j < order.size() && order[j] != ' ' && order[j] != '[' && order[j] != ']') ++j;
    if (j > i) out.push_back(order.substr(i, j - i));
    i = j;
  }
  return out;
}

std::size_t PovrayForm::required() const {
  std::size_t bracket = order.find('[');
  if (bracket == std::string_view::npos) return props().size();
  return PovrayForm{block, order.substr(0, bracket)}.props().size();
}

std::span<const PovrayForm> povray_forms() {
  return kForms;
}

const PovrayForm* find_povray_form(std::string_view block) {
  for (const PovrayForm& f : kForms)
    if (f.block == block) return &f;
  return nullptr;
}

PositionalHint positional_hint(const BlockInfo& block, const std::vector<std::string>& values) {
  PositionalHint h;
  std::string name(block.name);
  const PovrayForm* form = find_povray_form(block.name);
  std::vector<std::string_view> props = form ? form->props() : std::vector<std::string_view>{};
  if (props.empty()) {
    // Not a shape POV-Ray writes positionally (a camera, a light, a material, a mesh).
    h.message = "'" + name + "' takes named properties, not positional values";
    h.note = "write each value after its property name; '" + name + "' takes:";
    const char* sep = " ";
    for (std::string_view p : prop_names(block)) h.note += sep + std::string(p), sep = ", ";
    if (block.props.empty()) h.note = "'" + name + "' takes no values of its own";
    return h;
  }
  h.message = "'" + name + "' takes named properties, not POV-Ray's positional values";
  bool fits = values.size() >= form->required() && values.size() <= props.size();
  h.note = "write: " + name + " {";
  for (std::size_t i = 0; i < props.size(); ++i) {
    if (fits && i >= values.size()) break;  // an optional value not given
    h.note += " " + std::string(props[i]) + " " + (fits ? one_line(values[i]) : "…");
  }
  h.note += " }";
  if (!fits) {
    h.note += " (POV-Ray's order is ";
    for (std::size_t i = 0; i < props.size(); ++i)
      h.note += (i ? ", " : "") + std::string(props[i]);
    h.note += "; " + std::to_string(values.size()) + " value" + (values.size() == 1 ? "" : "s") +
              " given)";
  }
  return h;
}

namespace {
constexpr PovrayWord kWords[] = {
#define SNELL_POVRAY_WORD(kind, word, scope, note) {PovrayWordKind::kind, #word, #scope, note},
#include "compiler/povray_words.def"
};
}  // namespace

std::span<const PovrayWord> povray_words() {
  return kWords;
}

const char* povray_note(PovrayWordKind kind, std::string_view word, std::string_view block) {
  for (const PovrayWord& w : kWords)
    if (w.kind == kind && w.word == word && (w.scope == "any" || w.scope == block))
      return w.note.data();
  return nullptr;
}

}  // namespace snell::compile
