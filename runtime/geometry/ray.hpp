// What the integrators and the scene query exchange: rays in camera-relative float
// coordinates and the hits they find, with the bounded offset a ray leaving a hit
// starts from. No Embree types.
#pragma once

#include <cmath>
#include <cstdint>
#include <string>

#include "runtime/vec.hpp"

namespace snell::rt {

struct Ray {
  Vec3f org, dir;  // dir need not be unit length; t is in units of |dir|
  float tmax = INFINITY;
  float time = 0;  // shutter fraction in [0, 1): 0 = shutter open, Embree's ray time
  // Hits at t <= tnear are ignored. 0 except where a ray continues straight
  // through an index-matched interface (integrator.cpp): there it is the next
  // float after the interface's t, so the same ray goes on bit for bit.
  float tnear = 0;
};

// Up to 16 shadow rays in SoA lanes, each pointer to 16 floats (camera-relative;
// tnear 0, tmax kAreaShadowEnd, as an area light sample's): what the direct light
// of a packet's lit nodes makes (shading/area_lanes.hpp) and the scene query and
// the plane test take as they are.
// Where an area light's shadow ray ends: short of its target (the light sample moved
// off the light by offset_ray_origin) by 16 ulps of t. The target's offset is ulps
// of the sample's coordinates, which near the camera (the origin of Embree's
// space) are far finer than t's own rounding over a ray of length ~1: a light
// 0.003 from the camera shadowed every ray to itself, and the image was black.
// Occluders within 2e-6 of the ray's length of the light cast no shadow.
inline constexpr float kAreaShadowEnd = 1.0f - 0x1p-19f;  // 16 ulps of 1

struct ShadowLanes16 {
  const float *ox, *oy, *oz, *dx, *dy, *dz, *time;
  // Lane k as a ray of its own (the one-ray queries').
  Ray ray(unsigned k) const {
    return {{ox[k], oy[k], oz[k]}, {dx[k], dy[k], dz[k]}, kAreaShadowEnd, time[k]};
  }
};

struct Hit {
  float t = INFINITY;
  Vec3f ng;  // geometric normal, unit, outward for closed shapes (§8)
  // The surface point. On a static triangle it is rebuilt from the barycentrics, on
  // a static sphere, plane, cylinder, cone, disc or torus projected onto the surface
  // in double, so it lies on the surface to within a few ulps, and `offset` > 0 is
  // the distance along the normal that a ray leaving it must start at to clear the
  // surface (its error bound, and that of the test that re-tests the surface). On
  // moving shapes it is o + t·d, and `offset` <= 0 asks for the Wächter–Binder
  // offset (offset_ray_origin), which covers the larger error of o + t·d: -offset
  // is then the largest coordinate that error comes from (unbounded_offset), for
  // near_scale; 0 takes the scene's scale.
  Vec3f p;
  float offset = 0;
  enum class Kind : std::uint8_t { Shape, AreaLight } kind = Kind::Shape;
  // A smooth mesh face: `ns` is its interpolated shading normal (unit, on the side
  // of `ng`). Shading bends the lobes with it; `ng` still decides sides and offsets
  // (shading/shading_normal.hpp). `ps`: where its shadow rays start from, `p`
  // lifted towards the smooth surface on the ray's side (Hanika 2021; triangles.cpp).
  // False everywhere else, and `ns`, `ps` unset.
  bool smooth = false;
  Vec3f ns, ps;
  std::uint32_t index = 0;  // into ir::Scene::shapes or ::area_lights
  // The surface's own parameters (§17 mapping "uv") are found from these at shading
  // time, not here, so hits pay only the stores: `part` is the leaf hit (into
  // ir::Scene::parts: a CSG leaf, or an instance's part), `outer` the instance's
  // part holding a CSG leaf; kNoPart (~0u) when none. `prim` is Embree's primitive
  // and `tri_layer` the static-triangle table it indexes (EmbreeScene::
  // triangle_of), null for a moving triangle shape, whose prim is its own.
  std::uint32_t part = ~0u, outer = ~0u, prim = 0;
  const void* tri_layer = nullptr;
  // Into ir::Scene::materials: the surface's, which for a CSG object is the leaf's
  // and for an instance the part's (or the instance's, where the part has none).
  std::uint32_t material = 0;
};

// Where a ray leaving `h` to the side of unit `n` starts: `h.p` moved off the
// surface by the hit's bounded offset, or by Wächter–Binder's where it has none
// (`scale`: offset_scale). Robustness #1 and #18: the bounded offset is tens of
// ulps of the triangle's vertices instead of 256 ulps of the point, so slabs
// 1e-5 thick are still two surfaces.
[[gnu::always_inline]] inline Vec3f spawn_origin(const Hit& h, Vec3f n, float scale) {
  if (!(h.offset > 0))
    return offset_ray_origin(h.p, n, h.offset < 0 ? near_scale(scale, -h.offset) : scale);
  Vec3f o = h.p + n * h.offset;
  // Round away from the surface, so rounding never gives back part of the offset.
  auto away = [](float x, float dir) { return dir > 0 ? next_up(x) : dir < 0 ? next_down(x) : x; };
  return {away(o.x, n.x), away(o.y, n.y), away(o.z, n.z)};
}

// Hit::offset of a point o + t·d with no bound of its own: minus the largest
// coordinate of the ray's origin and the point (|t·d| is at most their sum).
[[gnu::always_inline]] inline float unbounded_offset(const Ray& r, Vec3f p) {
  return -std::fmax(max_abs(r.org), max_abs(p));
}

std::string to_string(const Ray& r);
std::string to_string(const Hit& h);

}  // namespace snell::rt
