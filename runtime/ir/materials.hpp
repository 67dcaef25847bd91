// Materials and patterns: one plain struct per kind (kinds.def), each naming its
// fields once (fields.hpp). A struct's member initialisers are the kind's
// defaults, the only place they are written: compiler/properties.def takes its
// defaults from them.
#pragma once

#include <cstdint>
#include <tuple>
#include <variant>

#include "runtime/ir/enums.hpp"
#include "runtime/ir/fields.hpp"
#include "runtime/ir/math.hpp"
#include "runtime/ir/source_ref.hpp"

namespace snell::ir {

// A plain colour (§8: a colour wherever a pattern may stand).
struct Constant {
  Vec3 color{0.8, 0.8, 0.8};
  bool operator==(const Constant&) const = default;
  static constexpr auto fields() { return std::tuple{field("color", &Constant::color)}; }
};

// §8 checker: cells of side `size`, color1 where floor(p/size) sums even.
struct Checker {
  Vec3 color1{1, 1, 1};
  Vec3 color2{0, 0, 0};
  double size = 1;
  bool operator==(const Checker&) const = default;
  static constexpr auto fields() {
    return std::tuple{field("color1", &Checker::color1), field("color2", &Checker::color2),
                      field("size", &Checker::size)};
  }
};

#define SNELL_PATTERN(name, Type) Type,
using PatternVariant = variant_of<
#include "runtime/ir/kinds.def"
    ListEnd>;

// A colour parameter: a constant or a pattern evaluated at the hit point (§8).
struct Texture {
  PatternVariant pattern{Constant{}};
  Texture() = default;
  Texture(Vec3 color) : pattern(Constant{color}) {}  // a colour is a texture
  Texture(const Checker& c) : pattern(c) {}
  PatternKind kind() const { return PatternKind(pattern.index()); }
  bool is_constant() const { return std::holds_alternative<Constant>(pattern); }
  bool operator==(const Texture&) const = default;
};

// §16: `specular` S >= 0 and `shininess` E > 0 of diffuse and glazed: a
// Blinn–Phong highlight S·(E + 8)/(8π)·max(0, n·h)^E in the direct light only
// (runtime/shading/bsdf.hpp Highlight). S = 0 is none.
struct Diffuse {
  Texture color{Vec3(0.8)};
  double specular = 0;
  double shininess = 50;
  bool operator==(const Diffuse&) const = default;
  static constexpr auto fields() {
    return std::tuple{field("color", &Diffuse::color), field("specular", &Diffuse::specular),
                      field("shininess", &Diffuse::shininess)};
  }
};
struct Mirror {
  Texture color{Vec3(1)};
  bool operator==(const Mirror&) const = default;
  static constexpr auto fields() { return std::tuple{field("color", &Mirror::color)}; }
};
// §8 glossy: the mirror direction perturbed in a square of side `blur`.
struct Glossy {
  Texture color{Vec3(1)};
  double blur = 0;
  bool operator==(const Glossy&) const = default;
  static constexpr auto fields() {
    return std::tuple{field("color", &Glossy::color), field("blur", &Glossy::blur)};
  }
};
struct Dielectric {
  double ior = 1.5;
  Vec3 absorb{0, 0, 0};  // Beer coefficient per channel, per scene unit
  // §14: 0 is "none" (the core's interface from air, wherever it is); >= 1 makes
  // the object's solid a medium that rays track (runtime/shading/interior.hpp).
  std::uint64_t priority = 0;
  bool operator==(const Dielectric&) const = default;
  static constexpr auto fields() {
    return std::tuple{field("ior", &Dielectric::ior), field("absorb", &Dielectric::absorb),
                      field("priority", &Dielectric::priority)};
  }
};
// The black glazed coating: a clear coat of index `ior` over a diffuse base.
// §16: its highlight is on the coated surface, not under the coat (no Fresnel).
struct Glazed {
  Texture color{Vec3(0)};
  double ior = 1.5;
  double specular = 0;
  double shininess = 50;
  bool operator==(const Glazed&) const = default;
  static constexpr auto fields() {
    return std::tuple{field("color", &Glazed::color), field("ior", &Glazed::ior),
                      field("specular", &Glazed::specular), field("shininess", &Glazed::shininess)};
  }
};

#define SNELL_MATERIAL(name, Type) Type,
using MaterialModel = variant_of<
#include "runtime/ir/kinds.def"
    ListEnd>;

struct Material {
  MaterialModel model{Diffuse{}};
  SourceRef src;
  Material() = default;
  template <class T>
  Material(const T& m) : model(m) {}  // any kind struct is a material
  MaterialKind kind() const { return MaterialKind(model.index()); }
  template <class T>
  const T* as() const {
    return std::get_if<T>(&model);
  }
  // Equality ignores src: the materials table is deduplicated by value.
  bool same_as(const Material& o) const { return model == o.model; }
};

#define SNELL_MATERIAL SNELL_KIND_NAME
#define SNELL_PATTERN SNELL_KIND_NAME
#include "runtime/ir/kinds.def"

}  // namespace snell::ir
