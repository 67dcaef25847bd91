// The scene as the integrator sees it: ray queries against every surface, in
// camera-relative float coordinates. The only header in front of Embree; the only
// translation unit that includes Embree is embree_scene.cpp.
//
// What goes where:
// - spheres: Embree user geometry intersected in object space (double), so any
//   affine transform (non-uniform scale, rotation) is exact; robust discriminant
//   (Haines et al., RTG ch. 7).
// - cylinders, cones, discs, tori (§11): user geometry too, each intersected in
//   double in a frame of its own (runtime/geometry/local_set.hpp).
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
#include <span>
#include <string>
#include <vector>

#include "runtime/geometry/ray.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

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
  // The same queries over a batch: found[i] / blocked[i] and hits[i] exactly as
  // the one-ray forms return them, traced as packets of up to 16 rays. They pay
  // for coherent rays: camera rays of neighbouring pixels (2.4-2.9x in
  // bench_trace), and the shadow rays of a packet's hits to one light cell (the
  // lit nodes of a packet's trees at one step), and a shading point's light-grid cells
  // (one origin; since static spheres meet a packet eight lanes at a time, 6-9 %
  // faster whole renders of examples/glass and lights than one ray at a time,
  // where they had been 1.3x slower). Shadow packets use Embree's incoherent
  // (hybrid) mode: the coherent one made boxes' point-light packets 1.8 -> 2.5x
  // one at a time, but spheres' and examples/hello's slower, and a grid's cells
  // from one point 3-6 % slower.
  // `coherent`: Embree's coherent mode (camera rays); off, its incoherent (hybrid)
  // mode, for the rays of a packet's trees after the first bounce.
  void intersect(std::span<const Ray> rays, std::span<Hit> hits, std::span<std::uint8_t> found,
                 bool coherent = true) const;
  void occluded(std::span<const Ray> rays, std::span<std::uint8_t> blocked) const;
  // Up to 16 shadow rays in SoA lanes (ray.hpp): the lanes of `live` (bit i: lane i)
  // that are blocked, each exactly as occluded(Ray) answers it.
  using ShadowLanes16 = rt::ShadowLanes16;
  std::uint32_t occluded(const ShadowLanes16& rays, std::uint32_t live) const;

  ir::Vec3 origin() const { return origin_; }
  // The triangle a hit on a box, triangle or mesh is, in that shape's own list
  // (ir::MeshData::indices / 3 for a mesh).
  std::uint32_t triangle_of(const Hit& hit) const;
  // True when some object moves during the open shutter (ray times matter).
  bool has_motion() const;
  std::string to_string() const;

  struct Impl;

 private:
  ir::Vec3 origin_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace snell::rt
