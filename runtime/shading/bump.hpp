// §16 bump <P, A>: the shading normal normalize(n − A·∇ₜP), ∇ₜP the world-space
// gradient of P's value with its component along n removed: to first order the
// normal of the surface pushed outward by A·P.
//
// The gradient is a central difference in world space, step h = 1e-3 of the
// pattern's unit on each axis (six evaluations): exact for the linear parts of a
// pattern (a gradient's ramp, so the test of a known slope holds to rounding) and
// within O(h²) ≈ 1e-6 relative for the noise families, whose finest octave at the
// default 6 is 2^-5 of a unit. Across a jump of the value (mortar edges, a
// gradient's wrap) it gives a band 2h wide of strongly tilted normals, the bump
// of a step. The tilt is limited so the normal stays at least ~0.6° above the
// geometric surface on its own side; the hit frame (shading_normal.hpp) then pulls
// it back to face the viewer where it does not, as for smooth meshes, so bumps
// seen at grazing angles have no black rims and no light through the surface.
#pragma once

#include <cmath>

#include "runtime/shading/textures.hpp"

namespace snell::rt {

// `n`: the unit outward normal being bumped (the geometric one, or a smooth mesh's
// shading normal); `ng`: the unit outward geometric normal. Returns the bumped
// unit normal on ng's side.
inline Vec3f bump_normal(const ir::Bump& b, const TexturePoint& tp, Vec3f n, Vec3f ng) {
  const ir::Texture& t = b.pattern;
  PatternFrame f = pattern_frame(t, tp);
  ir::Vec3 w = inward_point(tp, 1, 1e4, f.unit);
  double h = 1e-3 * f.unit;
  auto at = [&](ir::Vec3 x) {
    return value_at(t, f.identity ? x : f.space_from_world.point(x), f, tp);
  };
  ir::Vec3 g{(at(w + ir::Vec3{h, 0, 0}) - at(w - ir::Vec3{h, 0, 0})) / (2 * h),
             (at(w + ir::Vec3{0, h, 0}) - at(w - ir::Vec3{0, h, 0})) / (2 * h),
             (at(w + ir::Vec3{0, 0, h}) - at(w - ir::Vec3{0, 0, h})) / (2 * h)};
  ir::Vec3 nd{n.x, n.y, n.z};
  ir::Vec3 gt = g - nd * ir::dot(g, nd);
  ir::Vec3 m = nd - gt * b.amount;
  double len = ir::length(m);
  if (!(len > 0) || !std::isfinite(len)) return n;
  m = m / len;
  // Keep it on the geometric normal's side (cos >= 0.01).
  ir::Vec3 gd{ng.x, ng.y, ng.z};
  double c = ir::dot(m, gd);
  if (c < 0.01) {
    ir::Vec3 tang = m - gd * c;
    double tl = ir::length(tang);
    m = tl > 0 ? tang / tl * std::sqrt(1 - 0.01 * 0.01) + gd * 0.01 : gd;
  }
  return normalize(to_float(m.x, m.y, m.z));
}

}  // namespace snell::rt
