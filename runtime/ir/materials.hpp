// Materials and patterns: one plain struct per kind (kinds.def), each naming its
// fields once (fields.hpp). A struct's member initialisers are the kind's
// defaults, the only place they are written: compiler/properties.def takes its
// defaults from them.
#pragma once

#include <cstdint>
#include <tuple>
#include <variant>
#include <vector>

#include "runtime/ir/enums.hpp"
#include "runtime/ir/fields.hpp"
#include "runtime/ir/math.hpp"
#include "runtime/ir/program.hpp"
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

// §15's value patterns (runtime/pattern/patterns.hpp has their formulas; the
// colour comes from the Texture's colour map). Kinds without parameters of their
// own take only the common ones (Texture).
struct Gradient {
  Vec3 direction{0, 1, 0};
  bool operator==(const Gradient&) const = default;
  static constexpr auto fields() { return std::tuple{field("direction", &Gradient::direction)}; }
};
struct Brick {
  Vec3 size{0.5, 0.25, 0.25};
  double mortar = 0.02;
  bool operator==(const Brick&) const = default;
  static constexpr auto fields() {
    return std::tuple{field("size", &Brick::size), field("mortar", &Brick::mortar)};
  }
};
struct Fbm {
  double lacunarity = 2;
  double gain = 0.5;
  bool operator==(const Fbm&) const = default;
  static constexpr auto fields() {
    return std::tuple{field("lacunarity", &Fbm::lacunarity), field("gain", &Fbm::gain)};
  }
};
#define SNELL_PLAIN_PATTERN(Type)                           \
  struct Type {                                             \
    bool operator==(const Type&) const = default;           \
    static constexpr auto fields() { return std::tuple{}; } \
  };
SNELL_PLAIN_PATTERN(Onion)
SNELL_PLAIN_PATTERN(Radial)
SNELL_PLAIN_PATTERN(Noise)
SNELL_PLAIN_PATTERN(Marble)
SNELL_PLAIN_PATTERN(Wood)
SNELL_PLAIN_PATTERN(Granite)
SNELL_PLAIN_PATTERN(Agate)
SNELL_PLAIN_PATTERN(Leopard)
SNELL_PLAIN_PATTERN(Ripples)
SNELL_PLAIN_PATTERN(Waves)
SNELL_PLAIN_PATTERN(Cells)
#undef SNELL_PLAIN_PATTERN

// §15 `pattern { function f }`: f compiled (compiler/shading_function.hpp); its
// value clamped to [0, 1], 0 where it is not finite.
struct FunctionPattern {
  Program program;
  bool operator==(const FunctionPattern&) const = default;
  static constexpr auto fields() { return std::tuple{}; }
};

// §17 `image`: Scene::images[image] looked up at (u, v) of the mapping; with
// repeat the image tiles the plane, without it is black outside [0, 1]².
struct ImageTexture {
  std::uint32_t image = 0;
  ImageMapping mapping = ImageMapping::Planar;
  bool repeat = true;
  bool operator==(const ImageTexture&) const = default;
  static constexpr auto fields() {
    return std::tuple{field("image", &ImageTexture::image),
                      field("mapping", &ImageTexture::mapping),
                      field("repeat", &ImageTexture::repeat)};
  }
};

// A stop of a colour map (§15): the colour at value `at`.
struct ColorStop {
  double at = 0;
  Vec3 color;
  bool operator==(const ColorStop&) const = default;
};

#define SNELL_PATTERN(name, Type) Type,
using PatternVariant = variant_of<
#include "runtime/ir/kinds.def"
    ListEnd>;

// A colour parameter: a constant or a pattern evaluated at the hit point (§8).
struct Texture {
  PatternVariant pattern{Constant{}};
  // §15's properties common to every pattern (a constant has none of them):
  // - color_map: the value patterns' colours, stops in non-decreasing order;
  //   empty is the default map, black at 0 to white at 1. A checker with a map
  //   takes its colours from it at 0 (even cells) and 1 (odd cells).
  // - turbulence, octaves: the point is displaced by turbulence × a vector fbm of
  //   `octaves` octaves first; `octaves` is also fbm's and the noise families'.
  // - world_from_pattern: the pattern's transforms in the order written; it is
  //   evaluated at the point taken back through them.
  // - space: world (the hit point), or object (the point in the space of the
  //   object the hit belongs to, moving with its transforms and motion).
  std::vector<ColorStop> color_map;
  double turbulence = 0;
  std::uint32_t octaves = 6;
  Transform world_from_pattern;
  PatternSpace space = PatternSpace::World;
  Texture() = default;
  Texture(Vec3 color) : pattern(Constant{color}) {}  // a colour is a texture
  Texture(const Checker& c) : pattern(c) {}
  PatternKind kind() const { return PatternKind(pattern.index()); }
  bool is_constant() const { return std::holds_alternative<Constant>(pattern); }
  bool operator==(const Texture& o) const {
    return pattern == o.pattern && color_map == o.color_map && turbulence == o.turbulence &&
           octaves == o.octaves && world_from_pattern.m == o.world_from_pattern.m &&
           space == o.space;
  }
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

// §16 `bump <P, A>` (every material): the shading normal tilted by A times the
// tangential gradient of P's value, as if the surface were pushed outward by A·P.
// amount 0 is no bump (the pattern is then a constant and never evaluated).
struct Bump {
  Texture pattern;
  double amount = 0;
  bool on() const { return amount != 0 && !pattern.is_constant(); }
  bool operator==(const Bump&) const = default;
};

struct Material {
  MaterialModel model{Diffuse{}};
  Bump bump;
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
  bool same_as(const Material& o) const { return model == o.model && bump == o.bump; }
};

#define SNELL_MATERIAL SNELL_KIND_NAME
#define SNELL_PATTERN SNELL_KIND_NAME
#include "runtime/ir/kinds.def"

}  // namespace snell::ir
