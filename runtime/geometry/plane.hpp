// Planes (§5): infinite, so they stay outside the BVH (an infinite box would ruin
// its quality) and are tested analytically, in double, by the scene query after
// the BVH query: the unbounded class of traits.hpp. No Embree types.
#pragma once

#include <cstdint>
#include <vector>

#include "runtime/geometry/plane_lanes.hpp"
#include "runtime/geometry/ray.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::rt::geom {

// A grazing hit farther than this (camera-relative) is taken as a miss: no ray
// Embree is given starts beyond its range (FLT_LARGE, 1.8e18); scenes lie within
// 1e12 (ir.hpp).
inline constexpr double kMaxPlaneHit = 1e17;

class PlaneSet {
 public:
  // `moving`: the plane moves while the shutter is open; it is then placed at each
  // ray's time.
  void add(const ir::Shape& s, const ir::Plane& g, std::uint32_t index, ir::Vec3 origin,
           bool moving);
  std::size_t size() const { return planes_.size(); }
  bool empty() const { return planes_.empty(); }
  // The nearest plane hit with t < tmax, or within `tie` (a distance along the
  // plane's normal) beyond it: replaces `hit` and returns true. tmax is updated.
  // Inline when there are no planes: every ray asks.
  bool intersect(const Ray& r, double& tmax, double tie, Hit& hit) const {
    return !planes_.empty() && intersect_planes(r, tmax, tie, hit);
  }
  bool occluded(const Ray& r) const { return !planes_.empty() && occluded_planes(r); }
  // A packet's rays (16 lanes) against every plane after their BVH query, as
  // intersect() takes each lane: tmax[i] and tie[i] in, and for a lane that hits a
  // plane (bit i of hit_lanes) the nearest one's t out in tmax[i] and its index in
  // which[i], for plane_hit. false (nothing done): no SIMD path, or a moving plane;
  // intersect() lane by lane.
  bool intersect_lanes(const PlaneRayLanes& rays, std::uint32_t live, double* tmax, double* tie,
                       std::uint32_t* which, std::uint32_t& hit_lanes) const;
  // What intersect() writes into `hit` when plane `which` is the nearest, at t.
  void plane_hit(std::uint32_t which, const Ray& r, double t, Hit& hit) const;
  // The lanes of `live` (bit i: lane i) of 16 area-light shadow rays that a plane
  // blocks: occluded() of each, the static planes eight lanes at a time
  // (plane_lanes.hpp).
  std::uint32_t occluded_lanes(const ShadowLanes16& rays, std::uint32_t live) const;
  // The same on a given path of plane_lanes_paths() (null: lane by lane), for tests.
  std::uint32_t occluded_lanes(const ShadowLanes16& rays, std::uint32_t live,
                               PlaneLanesFn path) const;

 private:
  struct PlaneData {
    ir::Vec3 n;    // unit world normal
    double d = 0;  // dot(n, x) = d for camera-relative x
    std::uint32_t shape = 0;
    const ir::Shape* moving = nullptr;
    const ir::Plane* plane = nullptr;
  };
  bool intersect_planes(const Ray& r, double& tmax, double tie, Hit& hit) const;
  bool occluded_planes(const Ray& r) const;
  bool hit_plane(const PlaneData& p, const Ray& r, double tmax, double tie, double& t,
                 ir::Vec3& n_out, ir::Vec3* point) const;
  static void write_hit(const PlaneData& p, double t, ir::Vec3 n, ir::Vec3 q, Hit& hit);
  std::vector<PlaneData> planes_;
  bool any_moving_ = false;
  ir::Vec3 origin_;
};

}  // namespace snell::rt::geom
