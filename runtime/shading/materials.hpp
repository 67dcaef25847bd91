// ir::Material -> BSDF lobes (bsdf.hpp), and what each material does at a hit as
// the ray tree walks it: a lobe lit by the lights (a diffuse surface, the glazed
// base) and up to two branches to trace (mirror, glossy, dielectric reflection and
// refraction, the glazed coat). One overload per material kind of kinds.def; the
// integrator keeps only the walk (depth, weight, pruning, stack), the light sum
// and where each branch starts.
#pragma once

#include <cstdint>
#include <cstring>
#include <optional>
#include <string>
#include <type_traits>
#include <variant>

#include "runtime/ir/ir.hpp"
#include "runtime/sampler.hpp"
#include "runtime/shading/bsdf.hpp"
#include "runtime/shading/fresnel.hpp"
#include "runtime/shading/textures.hpp"

namespace snell::rt {

enum class RayKind : std::uint8_t { Camera, Reflection, Refraction, Glossy };
std::string to_string(RayKind k);

// A branch of the tree: a ray along `wi` carrying node weight × `weight`.
struct Branch {
  // Where it starts: off the surface on the ray's side, off it on the other
  // side, or the same ray continued past the hit (an index-matched interface).
  enum class From : std::uint8_t { Outside, Inside, SameRay };
  RayKind kind = RayKind::Reflection;
  Vec3f wi;
  Color weight;
  std::uint64_t slot = 1;  // names the child's sampler dimensions (1 reflection, 2 refraction)
  From from = From::Outside;
};

// Every node of the ray tree builds one, so the branches past `count` are left
// unset (a union): zeroing both for a diffuse hit that has none was 7 % of the ray
// tree's own time.
struct Scatter {
  std::optional<DiffuseLobe> lit;  // reflects the direct light (DiffuseLobe::reflect)
  Highlight highlight;             // §16: with lit, evaluated per light sample (off: S = 0)
  union {
    Branch branches[2];  // the first `count` are set
  };
  int count = 0;
  bool tir = false;  // a total internal reflection happened (--stats)
  Scatter() {}
  // Field by field in place: a Branch made on the frame and copied whole stalled on
  // store forwarding (3 % of the glass bench). The vectors' x and y go as one 8-byte
  // store, as the ray tree reads them (GCC pairs x and y of a Vec3f in one
  // register); three 4-byte stores stalled that read (4 %).
  void add(RayKind kind, Vec3f wi, Color weight, std::uint64_t slot, Branch::From from) {
    Branch& b = branches[count++];
    b.kind = kind, b.slot = slot, b.from = from;
    store_pair(b.wi, wi);
    store_pair(b.weight, weight);
  }
  static void store_pair(Vec3f& to, Vec3f v) {
    using F2 = float __attribute__((vector_size(8)));
    const F2 xy = {v.x, v.y};
    std::memcpy(&to.x, &xy, sizeof xy);
    to.z = v.z;
  }
};
static_assert(std::is_trivially_copyable_v<Branch> && std::is_trivially_destructible_v<Branch>);

// What the scatter functions see at a hit. `draw1(what)` and `draw2(what)` draw
// the node's sampler dimensions 9 (stochastic branch) and 7 (glossy square): only
// where the material needs them, so no kernel draws a number another does not.
template <class Draw1, class Draw2>
struct ScatterContext {
  Vec3f wo, nf;  // towards the viewer; the normal on the ray's side
  bool entering;
  const TexturePoint& tex;  // not a copy: one per node
  ir::FresnelMode fresnel;
  bool stochastic;  // settings.branching "stochastic"
  Draw1 draw1;
  Draw2 draw2;
};

template <class C>
Scatter scatter(const ir::Diffuse& m, const C& c) {
  Scatter s;
  s.lit = DiffuseLobe{texture_color(m.color, c.tex)};
  s.highlight = {float(m.specular), float(m.shininess)};
  return s;
}

template <class C>
Scatter scatter(const ir::Mirror& m, const C& c) {
  Scatter s;
  BsdfSample b = DeltaReflection{texture_color(m.color, c.tex)}.sample(c.wo, c.nf);
  s.add(RayKind::Reflection, b.wi, b.weight, 1, Branch::From::Outside);
  return s;
}

// Always traced, with the colour as its weight: at grazing incidence the mirror
// direction itself may lie below the surface, where the lobe has no density, and
// the §8 policy folds it back (glossy.hpp).
template <class C>
Scatter scatter(const ir::Glossy& m, const C& c) {
  Scatter s;
  GlossySquare g{texture_color(m.color, c.tex), float(m.blur)};
  BsdfU u{};
  if (m.blur > 0) {  // blur 0: the mirror, and no sample drawn
    Sample2 d = c.draw2();
    u.u = d.u, u.v = d.v;
  }
  s.add(RayKind::Glossy, g.direction(c.wo, c.nf, u), g.color, 1, Branch::From::Outside);
  return s;
}

// Split: both children, weighted R and 1 - R (the lecture's tree). Stochastic: one
// child, reflection with probability R, at full weight; the same expectation, one
// path instead of a tree. Under total internal reflection R is 1, so both agree
// exactly. Beer absorption is the medium's, applied by the walk (medium_absorb).
// `eta` = n_transmitted / n_incident of the interface as the ray meets it.
// Always inlined: as one function with scatter(Dielectric) it was inlined into the
// ray tree; split in two, GCC made it a call (callgrind, examples/glass.scn: 0.2 %
// more instructions in the render loop of a kernel without interiors).
template <class C>
[[gnu::always_inline]] inline Scatter scatter_interface(double eta, const C& c) {
  Scatter s;
  FresnelDielectric fd{eta, c.fresnel};
  FresnelDielectric::Split sp = fd.split(c.wo, c.nf);
  s.tir = sp.f.tir;
  // Index-matched (robustness #14): R = 0 and the very same ray goes on unbent, so
  // a clear ior-1 object renders bit for bit like its absence.
  Branch::From through = sp.index_matched() ? Branch::From::SameRay : Branch::From::Inside;
  if (c.stochastic && !sp.f.tir) {
    BsdfSample b = FresnelDielectric::choose(sp, c.draw1());
    if (b.transmitted)
      s.add(RayKind::Refraction, b.wi, b.weight, 2, through);
    else
      s.add(RayKind::Reflection, b.wi, b.weight, 1, Branch::From::Outside);
    return s;
  }
  s.add(RayKind::Reflection, sp.refl.wi, sp.refl.weight, 1, Branch::From::Outside);
  if (sp.transmits()) s.add(RayKind::Refraction, sp.refr.wi, sp.refr.weight, 2, through);
  return s;
}

// §8: the interface from air to its ior, wherever it is. (A prioritised solid's
// surface is an interface between the media on its two sides instead: the walk
// calls scatter_interface with their ratio, interior.hpp.)
template <class C>
Scatter scatter(const ir::Dielectric& m, const C& c) {
  return scatter_interface(c.entering ? m.ior : 1.0 / m.ior, c);
}

// A clear coat of index ior over a diffuse base, seen from the ray's side.
template <class C>
Scatter scatter(const ir::Glazed& m, const C& c) {
  Scatter s;
  GlazedCoat::Split g =
      GlazedCoat{texture_color(m.color, c.tex), m.ior, c.fresnel}.split(c.wo, c.nf);
  s.lit = g.base;
  // §16: on the coat's surface, unscaled by its Fresnel factors (the spec's f has
  // none): the highlight stands for the light the coat itself reflects.
  s.highlight = {float(m.specular), float(m.shininess)};
  s.add(RayKind::Reflection, g.coat.wi, g.coat.weight, 1, Branch::From::Outside);
  return s;
}

template <class C>
Scatter scatter(const ir::Material& m, const C& c) {
  return std::visit([&](const auto& kind) { return scatter(kind, c); }, m.model);
}

// The Beer coefficient of the medium inside the material (§8), or none.
inline const ir::Vec3* medium_absorb(const ir::Material& m) {
  const ir::Dielectric* d = m.as<ir::Dielectric>();
  return d ? &d->absorb : nullptr;
}

}  // namespace snell::rt
