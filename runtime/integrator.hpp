// The classic (Whitted-style) ray tree of the lecture, §6–§8: direct light through
// shadow rays from point and area lights onto diffuse and glazed surfaces, plus
// recursive mirror, glossy and dielectric rays. Traversal uses an explicit stack,
// so the tree depth (max_depth) never touches the C++ call stack.
//
// Specialisation (architecture: "simulate only the effects a scene calls for"):
// `li` is a template on ShadeFlags. Without area lights the direct-light loop is a
// single shadow ray per point light; without dielectrics the refraction path is not
// compiled in; without absorption no Beer factor is computed. The general kernel is
// ShadeFlags<true, true, true>. Every decision draws the same sampler dimensions in
// every kernel, so a specialised kernel renders the general kernel's picture.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/embree_scene.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/render.hpp"
#include "runtime/sampler.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

enum class RayKind : std::uint8_t { Camera, Reflection, Refraction, Glossy };
std::string to_string(RayKind k);

template <bool Area, bool Dielectric, bool Absorption>
struct ShadeFlags {
  static constexpr bool area = Area;
  static constexpr bool dielectric = Dielectric;
  static constexpr bool absorption = Dielectric && Absorption;
};
using GeneralShade = ShadeFlags<true, true, true>;

// Per-effect time, measured on a subset of camera samples (render.cpp picks which;
// docs/effects.md). Indexed by CostKind; nanoseconds of one thread.
enum CostKind : int {
  kCostCamera = 0,  // same order as RayKind
  kCostReflection,
  kCostRefraction,
  kCostGlossy,
  kCostShadow,
  kCostLens,
  kCostTime,
  kCostKinds
};
struct CostClock {
  double overhead_ns = 0;  // one now_ns() pair, subtracted from every interval
  double ns[kCostKinds] = {};
  static double now_ns();
  double since(double t0) const;  // now - t0 - overhead, never negative
};

// Where a camera sample comes from: the sampler inputs the tree draws dimensions from.
struct SampleContext {
  SamplerSpec spec;
  std::uint32_t px = 0, py = 0, index = 0;
  std::uint64_t pixel = 0;  // pixel_hash(spec, px, py)
};

struct Node {
  Ray ray;
  Vec3f start;  // the surface point the ray leaves, before the origin offset
  Color weight{1, 1, 1};
  std::uint32_t depth = 0;  // reflection/refraction rays after the camera ray
  RayKind kind = RayKind::Camera;
  std::uint64_t key = 0;  // hashed path: names this node's sampler dimensions
  std::int32_t trace_id = -1, trace_parent = -1;
};

std::string to_string(const SampleContext& c);
std::string to_string(const Node& n);

// The scene's size around `origin` (the camera), at most 1: the largest distance
// of any finite object's bounding corners or any light. Infinite planes do not
// count; nothing finite gives 1. Ray offsets scale with it (offset_ray_origin).
float offset_scale(const ir::Scene& scene, ir::Vec3 origin);

class Integrator {
 public:
  Integrator(const ir::Scene& scene, const EmbreeScene& embree);

  // Radiance along a camera ray. `stack` is scratch owned by the caller (one per
  // thread). `trace`, when not null, receives the readable ray tree. `cost`, when
  // not null, receives the time of each ray by kind. Child and shadow rays keep
  // the camera ray's time.
  template <class K>
  Color li(const Ray& camera_ray, const SampleContext& sc, RenderStats& stats,
           std::vector<Node>& stack, std::string* trace, CostClock* cost) const;
  // The general kernel.
  Color li(const Ray& camera_ray, const SampleContext& sc, RenderStats& stats,
           std::vector<Node>& stack, std::string* trace) const {
    return li<GeneralShade>(camera_ray, sc, stats, stack, trace, nullptr);
  }

  std::string to_string() const;

 private:
  struct LightF {             // area light, camera-relative float
    Vec3f corner, e1, e2, n;  // n: unit cross(e1, e2)
    float area = 0;
    Color radiance;
    std::uint32_t nu = 1, nv = 1;
    bool two_sided = false;
  };
  struct PointF {
    Vec3f pos;
    Color intensity;
  };

  Color texture(const ir::Texture& t, Vec3f p, Vec3f n_out) const;
  template <class K>
  // `o`: the shadow rays' origin, p moved off the surface (spawn_origin).
  Color direct(Vec3f p, Vec3f o, Vec3f n_facing, float time, std::uint64_t key,
               const SampleContext& sc, RenderStats& stats) const;
  Color emitted(const LightF& l, Vec3f dir) const;

  const ir::Scene& scene_;
  const EmbreeScene& embree_;
  std::vector<LightF> area_;
  std::vector<PointF> points_;
  Color background_;
  std::uint32_t max_depth_;
  float min_weight_;
  ir::FresnelMode fresnel_;
  float offset_scale_ = 1;             // the scene's size around the camera, at most 1
  bool stochastic_branching_ = false;  // settings.branching "stochastic"
  bool roulette_ = false;              // settings.termination "roulette"
};

}  // namespace snell::rt
