// Direction sampling of the distribution effects that bend rays: glossy reflection.
// (The thin lens lives with the camera, camera.hpp.)
#pragma once

#include "runtime/vec.hpp"

namespace snell::rt {

// §8 glossy: the unit mirror direction `r` perturbed inside a square of side `blur`
// perpendicular to it — the square spanned by the Duff et al. basis around r, so
// the square's orientation is continuous in r and never degenerate — then
// renormalised. (u, v) in [0,1)² picks the point of the square.
//
// Below-surface policy: a perturbed direction with dot(w, nf) < 0 (nf: unit normal
// on the incoming ray's side) is mirrored back above the surface by flipping its
// normal component. Energy is kept (the weight is the material colour whatever the
// sample) and there is no resampling loop; the limit is a slight bias of the lobe
// towards grazing directions for large blur at grazing incidence. A direction that
// still does not leave the surface (exactly tangent after rounding) falls back to
// the unperturbed mirror direction, so no glossy ray ever starts into its surface.
// blur == 0 returns `r` unchanged: a glossy surface of blur 0 is the mirror, bit for
// bit.
inline Vec3f glossy_direction(Vec3f r, Vec3f nf, float blur, float u, float v) {
  if (!(blur > 0)) return r;
  Vec3f b1, b2;
  orthonormal_basis(r, b1, b2);
  Vec3f w = normalize(r + b1 * ((u - 0.5f) * blur) + b2 * ((v - 0.5f) * blur));
  float below = dot(w, nf);
  if (below < 0) w = normalize(w - nf * (2 * below));
  if (!(dot(w, nf) > 0)) return r;
  return w;
}

}  // namespace snell::rt
