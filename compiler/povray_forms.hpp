// The POV-Ray habit diagnostic: a block written with POV-Ray's positional values
// (`cylinder { <0,0,0>, <0,1,0>, 0.5 }`, kept by the parser in Block::positional)
// gets one error that shows the named form, with the user's own values filled in
// when their count fits POV-Ray's order (povray_forms.def).
#pragma once

#include <cstddef>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "compiler/properties.hpp"

namespace snell::compile {

struct PovrayForm {
  std::string_view block;
  std::string_view order;  // as povray_forms.def writes it
  // The property names in order, and how many of them POV-Ray requires (the
  // rest, written in [ ], are trailing optional values).
  std::vector<std::string_view> props() const;
  std::size_t required() const;
};

// Every row of povray_forms.def, in its order.
std::span<const PovrayForm> povray_forms();
const PovrayForm* find_povray_form(std::string_view block);

struct PositionalHint {
  std::string message;  // "'cylinder' takes named properties, not POV-Ray's positional values"
  std::string note;     // "write: cylinder { base <0,0,0> cap <0,1,0> radius 0.5 }"
};
// `values`: the source text of each positional value, in order.
PositionalHint positional_hint(const BlockInfo& block, const std::vector<std::string>& values);

// POV-Ray's words that Snell writes another way (povray_words.def): the note for an
// unknown block, property or name that is one of them, or null.
enum class PovrayWordKind { Block, Property, Name };
struct PovrayWord {
  PovrayWordKind kind;
  std::string_view word, scope, note;  // scope: a block's name, or "any"
};
std::span<const PovrayWord> povray_words();
// `block`: where a property word was written (its scope must match).
const char* povray_note(PovrayWordKind kind, std::string_view word, std::string_view block = {});

}  // namespace snell::compile
