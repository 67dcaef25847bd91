// The shading layer's BSDF: today's five materials as lobes with sample / eval / pdf
// (docs: /work/shared/design/runtime-layout.md, "shading/"). Header-only because every
// call sits in the integrator's hot loop and must inline to today's code.
//
// No ir::Material here: lobes take plain parameters (colours, ior, blur, Fresnel mode)
// that the materials layer (shading/materials.cpp, to come) computes from the IR, with
// texture lookups and Beer absorption done there, not here.
//
// Conventions (pbrt's):
//   wo  unit direction towards the viewer: wo = -ray.dir. Negation is exact, so the
//       lobes recover li's `d` bit for bit as -wo.
//   n   unit normal on wo's side of the surface: li's `nf`. Every lobe is one-sided
//       with respect to it; the dielectric's other side is "transmission".
//   wi  unit direction the new ray leaves along (also for refraction).
//   eval(wo, n, wi) = f, the BSDF value WITHOUT the cosine; pdf(wo, n, wi) a density
//       per unit solid angle. Both are 0 off the support and for delta components
//       (a delta has no density: it is reached only through sample()).
//   sample(wo, n, u) -> {wi, weight = f·cos/pdf, pdf, kind, transmitted}. For a delta
//       component `pdf` is the discrete probability of having chosen it and `weight`
//       its reflectance (or transmittance) divided by that probability. pdf == 0
//       means "no sample" for a path tracer (!ok()); the Whitted tree uses wi and
//       weight regardless, as li does today (see GlossySquare::sample).
//
// Bit-identity contract: the delta, glazed and glossy directions and weights are the
// very float/double operations, in the very order, that Integrator::li performs today
// (integrator.cpp at 1b3454d), so switching li over changes no image by a single bit.
// tests/runtime/test_bsdf.cpp checks this against a frozen copy of li's formulas. It
// holds only while this header and li's caller are compiled with the same
// floating-point flags: no -ffast-math, and no FMA contraction that could differ
// between inlining contexts (the default x86-64 target has no FMA, so GCC's default
// -ffp-contract=fast contracts nothing today; an -march with FMA would need
// -ffp-contract=off to keep any bit-for-bit guarantee, today's included).
#pragma once

#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <variant>

#include "runtime/shading/fresnel.hpp"
#include "runtime/shading/glossy.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

enum class LobeKind : std::uint8_t { Delta, Diffuse, Glossy };

inline std::string to_string(LobeKind k) {
  switch (k) {
    case LobeKind::Delta:
      return "delta";
    case LobeKind::Diffuse:
      return "diffuse";
    case LobeKind::Glossy:
      return "glossy";
  }
  return "?";
}

namespace bsdf_detail {
inline std::string num(double x) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%.9g", x);
  return buf;
}
inline std::string vec(Vec3f v) {
  return "(" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ")";
}
// Densities are evaluated in double: reprojecting a float direction onto the glossy
// square in float would misplace it by ~1e-7 (relative to blur/2, large for small blur).
struct V3 {
  double x, y, z;
};
inline V3 d3(Vec3f v) {
  return {v.x, v.y, v.z};
}
inline double dot3(V3 a, V3 b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
}  // namespace bsdf_detail

// The random numbers one sample() may consume. `c` chooses a component (dielectric:
// reflect or refract; glazed: coat or base); (u, v) picks a direction inside a lobe
// (glossy square, diffuse disk). All in [0, 1). Integrator::li today feeds the glossy
// lobe (u, v) = sample2(node_dim(key, 7)) and the stochastic dielectric
// c = sample1(node_dim(key, 9)); other fields are ignored.
struct BsdfU {
  float c = 0, u = 0, v = 0;
};

inline std::string to_string(BsdfU u) {
  return "bsdf_u { c " + bsdf_detail::num(u.c) + " u " + bsdf_detail::num(u.u) + " v " +
         bsdf_detail::num(u.v) + " }";
}

struct BsdfSample {
  Vec3f wi;
  Color weight;   // f·|cos θi| / pdf; for a delta: component reflectance / choice probability
  float pdf = 0;  // solid-angle density, or a delta's discrete choice probability
  LobeKind kind = LobeKind::Delta;
  bool transmitted = false;  // wi leaves on the far side of n (refraction)
  bool ok() const { return pdf > 0; }
};

inline std::string to_string(const BsdfSample& s) {
  if (!s.ok()) return "bsdf_sample { none }";
  return "bsdf_sample { " + to_string(s.kind) + (s.transmitted ? " transmitted" : "") + " wi " +
         bsdf_detail::vec(s.wi) + " weight " + bsdf_detail::vec(s.weight) + " pdf " +
         bsdf_detail::num(s.pdf) + " }";
}

// What li derives from the ray and the side normal, in li's operations:
//   cos_i = fmin(1, -dot(d, nf)); refl = d + nf * (2 * cos_i); mirror = normalize(refl).
// cos_i is >= 0 (up to the sign of zero) because nf is on the ray's side.
struct Incident {
  Vec3f d;      // the ray's direction, towards the surface (li's `d`)
  Vec3f n;      // li's `nf`
  float cos_i;  // li's `cos_i`
  Vec3f mirror() const { return normalize(d + n * (2 * cos_i)); }
};

inline Incident incident(Vec3f wo, Vec3f n) {
  Vec3f d = -wo;
  return {d, n, std::fmin(1.0f, -dot(d, n))};
}

inline std::string to_string(const Incident& i) {
  return "incident { d " + bsdf_detail::vec(i.d) + " n " + bsdf_detail::vec(i.n) + " cos_i " +
         bsdf_detail::num(i.cos_i) + " }";
}

// One delta child of the Whitted tree: li spawns a ray along `wi` carrying
// node.weight * weight (Vec3f * Vec3f is componentwise, so `w * Color(s)` has the
// bits of li's `w * s`).
struct DeltaBranch {
  Vec3f wi;
  Color weight;
};

inline std::string to_string(const DeltaBranch& b) {
  return "delta_branch { wi " + bsdf_detail::vec(b.wi) + " weight " + bsdf_detail::vec(b.weight) +
         " }";
}

// ---------------------------------------------------------------------------------
// Lambertian: f = albedo · scale with scale = 1/π (a plain diffuse surface) or
// (1/π)·float(1 − R) (the base under a glazed coat, see GlazedCoat). Keeping the
// scale a separate float, not folded into the colour, is what lets reflect() repeat
// li's operation order. One-sided: f is nonzero only when wo and wi are both strictly
// above n (so it is reciprocal exactly, see the tests). Sampling is cosine-weighted
// (Shirley–Chiu concentric disk, then Malley); li does not sample it today (Whitted:
// direct light only), so nothing about sample() is bound by bit-identity.
struct DiffuseLobe {
  static constexpr float kInvPi = 0.318309886183790671538f;  // li's constant, same bits
  static constexpr float kPi = 3.14159265358979323846f;

  Color albedo;
  float scale = kInvPi;

  // The radiance a Whitted node reflects, given li's irradiance-like sum E from
  // Integrator::direct and the node weight w: ((w · albedo) · E) · scale, li's order
  // for both the diffuse material (scale = kInvPi) and the glazed base.
  Color reflect(Color w, Color e) const { return w * albedo * e * scale; }

  Color eval(Vec3f wo, Vec3f n, Vec3f wi) const {
    if (!(dot(wo, n) > 0) || !(dot(wi, n) > 0)) return Color(0);
    return albedo * scale;
  }
  float pdf(Vec3f wo, Vec3f n, Vec3f wi) const {
    float c = dot(wi, n);
    if (!(dot(wo, n) > 0) || !(c > 0)) return 0;
    return c * kInvPi;
  }
  BsdfSample sample(Vec3f wo, Vec3f n, BsdfU u) const {
    BsdfSample s;
    if (!(dot(wo, n) > 0)) return s;
    // Concentric map of [0,1)² to the unit disk: area-preserving up to a constant,
    // so the lifted point is cosine-distributed on the hemisphere.
    float sx = 2 * u.u - 1, sy = 2 * u.v - 1, r = 0, phi = 0;
    if (sx != 0 || sy != 0) {
      if (std::fabs(sx) > std::fabs(sy)) {
        r = sx;
        phi = (kPi / 4) * (sy / sx);
      } else {
        r = sy;
        phi = kPi / 2 - (kPi / 4) * (sx / sy);
      }
    }
    float x = r * std::cos(phi), y = r * std::sin(phi);
    float z = std::sqrt(std::fmax(0.0f, 1 - x * x - y * y));
    Vec3f b1, b2;
    orthonormal_basis(n, b1, b2);
    Vec3f wi = normalize(b1 * x + b2 * y + n * z);
    float p = pdf(wo, n, wi);
    if (!(p > 0)) return s;  // the disk's rim: tangent, no density; measure zero
    s.wi = wi;
    s.pdf = p;
    s.kind = LobeKind::Diffuse;
    s.weight = albedo * (scale * kPi);  // f·cos/pdf = albedo·scale·π exactly in the reals
    return s;
  }
};

inline std::string to_string(const DiffuseLobe& l) {
  return "diffuse_lobe { albedo " + bsdf_detail::vec(l.albedo) + " scale " +
         bsdf_detail::num(l.scale) + " }";
}

// ---------------------------------------------------------------------------------
// §16 Blinn–Phong highlight of diffuse and glazed surfaces:
//   f = S · (E + 8)/(8π) · max(0, n·h)^E,  h = normalize(wo + wi)
// a BRDF value (no cosine) that only the direct-light sum evaluates, per light
// sample, beside the Lambertian lobe: it is no lobe of the ray tree (no sample, no
// pdf), so mirror, glossy and refracted rays never see it and a point light never
// shows up in a mirror through it. (E + 8)/(8π) is the usual approximate
// normalisation: seen along n, the lobe reflects S times 1.00–1.08 of the light for
// every E (1 as E grows; integrated numerically), less at grazing views. Computed
// in float: an absurd S·E (beyond ~1e37) can overflow to inf right at the peak,
// which the film then drops as a non-finite sample.
struct Highlight {
  static constexpr float kInv8Pi = 0.0397887357729738339422f;  // 1/(8π)
  float specular = 0;                                          // S; 0 is no highlight
  float shininess = 50;                                        // E

  bool on() const { return specular > 0; }
  // wo towards the viewer, wi towards the light, both unit; n the shading normal on
  // wo's side. One-sided like DiffuseLobe: 0 unless both are strictly above n.
  float eval(Vec3f wo, Vec3f n, Vec3f wi) const {
    if (!(dot(wo, n) > 0) || !(dot(wi, n) > 0)) return 0;
    Vec3f h = wo + wi;
    float len = length(h);
    if (!(len > 0)) return 0;
    float c = dot(n, h) / len;
    if (!(c > 0)) return 0;
    float p = std::pow(std::fmin(c, 1.0f), shininess);
    if (!(p > 0)) return 0;  // underflow: no 0 · inf for a huge shininess
    return specular * ((shininess + 8) * kInv8Pi) * p;
  }
};

inline std::string to_string(const Highlight& h) {
  return "highlight { specular " + bsdf_detail::num(h.specular) + " shininess " +
         bsdf_detail::num(h.shininess) + " }";
}

// ---------------------------------------------------------------------------------
// Perfect mirror: one delta along li's normalize(d + nf·(2·cos_i)), weight `color`
// (li's mirror: texture(m.color); a Fresnel-weighted reflection is Color(float(R))).
struct DeltaReflection {
  Color color;

  Color eval(Vec3f, Vec3f, Vec3f) const { return Color(0); }
  float pdf(Vec3f, Vec3f, Vec3f) const { return 0; }
  BsdfSample sample(Vec3f wo, Vec3f n, BsdfU = {}) const {
    BsdfSample s;
    s.wi = incident(wo, n).mirror();
    s.weight = color;
    s.pdf = 1;
    s.kind = LobeKind::Delta;
    return s;
  }
};

inline std::string to_string(const DeltaReflection& l) {
  return "delta_reflection { color " + bsdf_detail::vec(l.color) + " }";
}

// ---------------------------------------------------------------------------------
// Glossy (§8): glossy_direction (glossy.hpp) around li's mirror direction, weight
// `color` for every sample. Directions are exactly today's: sample() calls the same
// function on the same mirror vector.
//
// Density. With b = blur, (u, v) uniform on [0,1)² maps to the point q = (x, y) =
// ((u − ½)b, (v − ½)b) of the square S = [−b/2, b/2)² in the plane at distance 1
// along r spanned by the Duff basis (b1, b2) — density 1/b² per unit plane area —
// then to w = p/|p| with p = r + x·b1 + y·b2. Central projection of a plane at unit
// distance onto the sphere has dω = cos α · dA / |p|² with cos α = dot(w, r) = 1/|p|,
// so dω = dA / |p|³ and
//     g(w) = |p|³ / b² = 1 / (b² cos³α),   where x = dot(w, b1)/cos α,
//                                            y = dot(w, b2)/cos α must lie in S.
// Folding: a w below the surface (dot(w, n) < 0) is replaced by its mirror image
// M w = w − 2·dot(w, n)·n, an isometry (|det M| = 1). The density of the folded
// direction at any w above the surface is therefore exactly
//     pdf(w) = g(w) + g(M w),
// which integrates to 1 over the upper hemisphere whether or not folding happens.
// What pdf() does NOT represent: glossy_direction's last resort — a direction that
// is still not strictly above after folding (exactly tangent after rounding) is
// replaced by r. That is a point mass at r of probability zero in exact arithmetic
// and at most a few float grid points of (u, v) in practice; pdf() is a density and
// cannot carry it.
// Edge tolerance: the support test accepts |x|, |y| <= b/2 + 2^-21, because a
// sampled float direction reprojects up to a few 1e-7 outside S; this adds at most
// 4·b·2^-21/b² = 1.9e-6/b of spurious mass at the square's rim.
// Limits: blur below ~1e-19 overflows the density (1/b²) to +inf in float. blur 0
// (or NaN/negative, which glossy_direction treats as 0) is the mirror: a delta,
// eval/pdf 0, sample weight `color` with pdf 1.
// f = color · pdf(w) / cos θi, so sample's weight `color` = f·cos/pdf (consistent).
// It is not reciprocal: f divides by cos θi of wi only, and the square's orientation
// follows the Duff basis of each mirror direction (tests show pairs that differ).
struct GlossySquare {
  static constexpr double kEdge = 4.76837158203125e-07;  // 2^-21

  Color color;
  float blur = 0;

  bool is_delta() const { return !(blur > 0); }

  float pdf(Vec3f wo, Vec3f n, Vec3f wi) const {
    using namespace bsdf_detail;
    if (is_delta()) return 0;
    V3 w = d3(wi), nn = d3(n);
    double len = std::sqrt(dot3(w, w));
    if (!(len > 0)) return 0;
    w = {w.x / len, w.y / len, w.z / len};
    double wn = dot3(w, nn);
    if (!(wn > 0)) return 0;
    Vec3f r = incident(wo, n).mirror(), b1, b2;
    orthonormal_basis(r, b1, b2);
    V3 m{w.x - 2 * wn * nn.x, w.y - 2 * wn * nn.y, w.z - 2 * wn * nn.z};
    return float(square_density(w, r, b1, b2) + square_density(m, r, b1, b2));
  }
  Color eval(Vec3f wo, Vec3f n, Vec3f wi) const {
    float p = pdf(wo, n, wi);
    if (!(p > 0)) return Color(0);
    return color * (p / dot(wi, n));
  }
  // The direction alone, for the Whitted tree: sample().wi without the density's
  // cost (a basis and two reprojections li has no use for). Weight: `color`.
  Vec3f direction(Vec3f wo, Vec3f n, BsdfU u) const {
    Vec3f r = incident(wo, n).mirror();
    return is_delta() ? r : glossy_direction(r, n, blur, u.u, u.v);
  }
  BsdfSample sample(Vec3f wo, Vec3f n, BsdfU u) const {
    BsdfSample s;
    s.wi = direction(wo, n, u);
    s.weight = color;
    if (is_delta()) {
      s.pdf = 1;
      s.kind = LobeKind::Delta;
      return s;
    }
    s.pdf = pdf(wo, n, s.wi);
    s.kind = LobeKind::Glossy;
    // The weight stays `color` even when pdf is 0: that happens only when
    // glossy_direction fell back to r and r itself is not above the surface (grazing
    // incidence, after rounding). li spawns that ray at weight `color` today, so the
    // sample keeps it for bit-identity; a path tracer sees !ok() and drops it.
    return s;
  }

  // g(w) above: the unfolded warp's density at unit w.
  double square_density(bsdf_detail::V3 w, Vec3f r, Vec3f b1, Vec3f b2) const {
    using namespace bsdf_detail;
    double c = dot3(w, d3(r));
    if (!(c > 0)) return 0;
    double x = dot3(w, d3(b1)) / c, y = dot3(w, d3(b2)) / c;
    double h = 0.5 * double(blur) + kEdge;
    if (!(std::fabs(x) <= h) || !(std::fabs(y) <= h)) return 0;
    double b = blur;
    return 1 / (b * b * c * c * c);
  }
};

inline std::string to_string(const GlossySquare& l) {
  return "glossy_square { color " + bsdf_detail::vec(l.color) + " blur " +
         bsdf_detail::num(l.blur) + " }";
}

// ---------------------------------------------------------------------------------
// A smooth dielectric interface (the brief's "delta transmission with Fresnel"):
// reflection with R, refraction with 1 − R, R = 1 and no refraction under TIR.
// `eta` = n_transmitted / n_incident exactly as li computes it:
//     eta = entering ? m.ior : 1.0 / m.ior
// Beer absorption over the path inside is the medium's, applied by the caller to the
// node weight before this (as li does). Radiance transport with no 1/η² factor on
// refraction, as li does today (so it is not the symmetric, "importance" form).
struct FresnelDielectric {
  double eta = 1.5;
  ir::FresnelMode mode = ir::FresnelMode::Exact;

  // Everything li's split tree needs, in li's operations.
  struct Split {
    Interface f;
    double R = 0;      // reflectance(f, mode); exactly 1 under TIR
    DeltaBranch refl;  // normalize(refl), weight Color(float(R))
    DeltaBranch refr;  // weight Color(float(1 - R)); meaningless when !transmits()
    bool transmits() const { return !f.tir; }
    // eta == 1 (which holds exactly when m.ior == 1.0): refr.wi is d itself, bit for
    // bit, and li continues the same ray past the hit instead of spawning a new one.
    bool index_matched() const { return f.eta == 1; }
    double T() const { return 1 - R; }  // R + T == 1 exactly in double (tests)
  };

  Split split(Vec3f wo, Vec3f n) const {
    Incident in = incident(wo, n);
    Split s;
    s.f = make_interface(in.cos_i, eta);
    s.R = reflectance(s.f, mode);
    s.refl = {in.mirror(), Color(float(s.R))};
    s.refr.weight = Color(float(1 - s.R));
    if (s.f.tir) {
      s.refr.wi = Vec3f(0);
    } else if (s.f.eta == 1) {
      s.refr.wi = in.d;
    } else {
      Vec3f d = in.d, nf = in.n;
      Vec3d t = refract({d.x, d.y, d.z}, {nf.x, nf.y, nf.z}, s.f);
      s.refr.wi = normalize(to_float(t.x, t.y, t.z));
    }
    return s;
  }

  // Stochastic branching as li does it: reflect iff TIR or c < float(R), at weight 1
  // (Color(1), so w * weight == w bit for bit). The choice probabilities reported as
  // pdf are float(R) and 1 − float(R), exact for a continuous c (the sampler's
  // 24-bit grid makes them exact to 2^-24). Takes a Split so that a caller that also
  // needs the TIR flag (li counts tir_events) computes the interface once.
  static BsdfSample choose(const Split& sp, float c) {
    bool reflect = sp.f.tir || c < float(sp.R);
    BsdfSample s;
    s.kind = LobeKind::Delta;
    s.weight = Color(1);
    if (reflect) {
      s.wi = sp.refl.wi;
      s.pdf = sp.f.tir ? 1.0f : float(sp.R);
    } else {
      s.wi = sp.refr.wi;
      s.pdf = 1.0f - float(sp.R);
      s.transmitted = true;
    }
    if (!(s.pdf > 0)) s.weight = Color(0);
    return s;
  }
  BsdfSample sample(Vec3f wo, Vec3f n, BsdfU u) const { return choose(split(wo, n), u.c); }
  Color eval(Vec3f, Vec3f, Vec3f) const { return Color(0); }
  float pdf(Vec3f, Vec3f, Vec3f) const { return 0; }
};

inline std::string to_string(const FresnelDielectric::Split& s) {
  return "dielectric_split { " + to_string(s.f) + " R " + bsdf_detail::num(s.R) + " refl " +
         to_string(s.refl) + (s.transmits() ? " refr " + to_string(s.refr) : " tir") +
         (s.index_matched() ? " index_matched" : "") + " }";
}
inline std::string to_string(const FresnelDielectric& l) {
  return "fresnel_dielectric { eta " + bsdf_detail::num(l.eta) + " fresnel " +
         ir::to_string(l.mode) + " }";
}

// ---------------------------------------------------------------------------------
// Glazed: a clear coat of index `ior` over a Lambertian base, seen from the ray's
// side (li: make_interface(cos_i, m.ior) whatever the side). The coat reflects R(wo)
// as a delta; the base is Lambertian scaled by 1 − R(wo), only R at the VIEWING angle
// (no 1 − R(wi) for light entering the coat, no internal reflections), so
// f(wo, wi) != f(wi, wo): not reciprocal (tests). Energy R + (1 − R)·albedo <= 1.
struct GlazedCoat {
  Color albedo;
  double ior = 1.5;
  ir::FresnelMode mode = ir::FresnelMode::Exact;

  struct Split {
    Interface f;
    double R = 0;
    DiffuseLobe base;  // albedo, scale = DiffuseLobe::kInvPi * float(1 - R)
    DeltaBranch coat;  // normalize(refl), weight Color(float(R))
  };

  Split split(Vec3f wo, Vec3f n) const {
    Incident in = incident(wo, n);
    Split s;
    s.f = make_interface(in.cos_i, ior);
    s.R = reflectance(s.f, mode);
    s.base = {albedo, DiffuseLobe::kInvPi * float(1 - s.R)};
    s.coat = {in.mirror(), Color(float(s.R))};
    return s;
  }

  // The continuous part only (the coat is a delta).
  Color eval(Vec3f wo, Vec3f n, Vec3f wi) const { return split(wo, n).base.eval(wo, n, wi); }
  // P(base) · cos/π with P(base) = 1 − float(R), sample()'s choice.
  float pdf(Vec3f wo, Vec3f n, Vec3f wi) const {
    Split sp = split(wo, n);
    return (1.0f - float(sp.R)) * sp.base.pdf(wo, n, wi);
  }
  // Coat with probability float(R) (weight 1 = R / P), else a cosine-sampled base
  // direction with weight f·cos / pdf = albedo · (1 − R) / (1 − float(R)).
  BsdfSample sample(Vec3f wo, Vec3f n, BsdfU u) const {
    Split sp = split(wo, n);
    float pc = float(sp.R);
    BsdfSample s;
    if (u.c < pc) {
      s.wi = sp.coat.wi;
      s.weight = Color(1);
      s.pdf = pc;
      s.kind = LobeKind::Delta;
      return s;
    }
    BsdfSample b = sp.base.sample(wo, n, u);
    float pb = 1.0f - pc;
    if (!b.ok() || !(pb > 0)) return BsdfSample{};
    b.pdf *= pb;
    b.weight = b.weight * (1 / pb);
    return b;
  }
};

inline std::string to_string(const GlazedCoat::Split& s) {
  return "glazed_split { " + to_string(s.f) + " R " + bsdf_detail::num(s.R) + " base " +
         to_string(s.base) + " coat " + to_string(s.coat) + " }";
}
inline std::string to_string(const GlazedCoat& l) {
  return "glazed_coat { albedo " + bsdf_detail::vec(l.albedo) + " ior " + bsdf_detail::num(l.ior) +
         " fresnel " + ir::to_string(l.mode) + " }";
}

// ---------------------------------------------------------------------------------
// A BSDF at a hit: one of the above. A closed variant, not virtual calls: the set is
// small, and std::visit on a variant of trivially copyable structs inlines.
using Bsdf =
    std::variant<DiffuseLobe, DeltaReflection, GlossySquare, FresnelDielectric, GlazedCoat>;

inline BsdfSample sample(const Bsdf& b, Vec3f wo, Vec3f n, BsdfU u) {
  return std::visit([&](const auto& l) { return l.sample(wo, n, u); }, b);
}
inline Color eval(const Bsdf& b, Vec3f wo, Vec3f n, Vec3f wi) {
  return std::visit([&](const auto& l) { return l.eval(wo, n, wi); }, b);
}
inline float pdf(const Bsdf& b, Vec3f wo, Vec3f n, Vec3f wi) {
  return std::visit([&](const auto& l) { return l.pdf(wo, n, wi); }, b);
}
inline std::string to_string(const Bsdf& b) {
  return std::visit([](const auto& l) { return to_string(l); }, b);
}

}  // namespace snell::rt
