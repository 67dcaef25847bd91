// The scene as the integrator sees it: ray queries against every surface, in
// camera-relative float coordinates. The only header in front of Embree; the only
// translation unit that includes Embree is embree_scene.cpp.
//
// What goes where:
// - spheres: Embree user geometry intersected in object space (double), so any
//   affine transform (non-uniform scale, rotation) is exact; robust discriminant
//   (Haines et al., RTG ch. 7).
// - boxes: 12 triangles, triangles and meshes: triangle geometry; vertices are
//   transformed in double, moved by -camera, then rounded to float. Winding is
//   flipped under mirroring transforms so Ng stays outward.
// - area lights: two triangles each, so camera/reflection/refraction rays see them
//   and they block shadow rays of other lights (an area light is a surface).
// - planes: infinite, so they stay outside the BVH (an infinite box would ruin its
//   quality) and are tested analytically after the Embree query.
// - motion (§8, only for objects that move while the shutter is open; everything
//   else is static geometry): a moving sphere is user geometry bounded by its sweep
//   and intersected at the ray's time; a moving plane is placed at the ray's time; a
//   moving box/triangle/mesh is an Embree motion-blur geometry with enough time
//   steps that linear interpolation follows rotations (embree_scene.cpp). Ray times
//   are shutter fractions in [0, 1], Embree's convention.
// The scene is built with RTC_SCENE_FLAG_ROBUST: rays aimed exactly at the shared
// vertices of a closed mesh missed 12.9 % of the time without it (tests/hardcases,
// robustness #6). Self-intersection is handled by Wächter–Binder offsets either way
// (tests/runtime/test_robust.cpp sees 0 re-hits at scales 1e-2..1e5).
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "runtime/ir/ir.hpp"
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

struct Hit {
  float t = INFINITY;
  Vec3f ng;  // geometric normal, unit, outward for closed shapes (§8)
  // The surface point. On a static triangle it is rebuilt from the barycentrics, on
  // a static sphere or a plane projected onto the surface in double, so it lies on
  // the surface to within a few ulps, and `offset` > 0 is the distance along the
  // normal that a ray leaving it must start at to clear the surface (its error
  // bound, and that of the test that re-tests the surface). On moving shapes it is
  // o + t·d, and `offset` 0 asks for the Wächter–Binder offset (offset_ray_origin),
  // which covers the larger error of o + t·d.
  Vec3f p;
  float offset = 0;
  enum class Kind : std::uint8_t { Shape, AreaLight } kind = Kind::Shape;
  std::uint32_t index = 0;  // into ir::Scene::shapes or ::area_lights
};

// Where a ray leaving `h` to the side of unit `n` starts: `h.p` moved off the
// surface by the hit's bounded offset, or by Wächter–Binder's where it has none
// (`scale`: offset_scale). Robustness #1 and #18: the bounded offset is tens of
// ulps of the triangle's vertices instead of 256 ulps of the point, so slabs
// 1e-5 thick are still two surfaces.
inline Vec3f spawn_origin(const Hit& h, Vec3f n, float scale) {
  if (!(h.offset > 0)) return offset_ray_origin(h.p, n, scale);
  Vec3f o = h.p + n * h.offset;
  // Round away from the surface, so rounding never gives back part of the offset.
  auto away = [](float x, float dir) {
    return dir > 0 ? std::nextafter(x, INFINITY) : dir < 0 ? std::nextafter(x, -INFINITY) : x;
  };
  return {away(o.x, n.x), away(o.y, n.y), away(o.z, n.z)};
}

std::string to_string(const Ray& r);
std::string to_string(const Hit& h);

class EmbreeScene {
 public:
  // `origin`: the world point that becomes (0, 0, 0) (the camera location).
  EmbreeScene(const ir::Scene& scene, ir::Vec3 origin);
  ~EmbreeScene();
  EmbreeScene(const EmbreeScene&) = delete;
  EmbreeScene& operator=(const EmbreeScene&) = delete;

  // Nearest hit with t in (0, ray.tmax); false when the ray escapes.
  bool intersect(const Ray& ray, Hit& hit) const;
  // True when anything lies on the ray with t in (0, ray.tmax).
  bool occluded(const Ray& ray) const;

  ir::Vec3 origin() const { return origin_; }
  // True when some object moves during the open shutter (ray times matter).
  bool has_motion() const;
  std::string to_string() const;

  struct Impl;

 private:
  ir::Vec3 origin_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace snell::rt
