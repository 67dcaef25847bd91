// The classic (Whitted-style) ray tree of the lecture, §6–§8: direct light through
// shadow rays from point and area lights onto diffuse and glazed surfaces, plus
// recursive mirror, glossy and dielectric rays. Traversal uses an explicit stack,
// so the tree depth (max_depth) never touches the C++ call stack.
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

// Where a camera sample comes from: the sampler inputs the tree draws dimensions from.
struct SampleContext {
  SamplerSpec spec;
  std::uint32_t px = 0, py = 0, index = 0;
};

struct Node {
  Ray ray;
  Vec3f start;  // the surface point the ray leaves, before the origin offset
  Color weight{1, 1, 1};
  std::uint32_t depth = 0;  // reflection/refraction rays after the camera ray
  RayKind kind = RayKind::Camera;
  std::uint64_t key = 0;    // hashed path: names this node's sampler dimensions
  std::int32_t trace_id = -1, trace_parent = -1;
};

std::string to_string(const SampleContext& c);
std::string to_string(const Node& n);

class Integrator {
 public:
  Integrator(const ir::Scene& scene, const EmbreeScene& embree);

  // Radiance along a camera ray. `stack` is scratch owned by the caller (one per
  // thread). `trace`, when not null, receives the readable ray tree.
  Color li(const Ray& camera_ray, const SampleContext& sc, RenderStats& stats,
           std::vector<Node>& stack, std::string* trace) const;

  std::string to_string() const;

 private:
  struct LightF {  // area light, camera-relative float
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
  Color direct(Vec3f p, Vec3f n_facing, std::uint64_t key, const SampleContext& sc,
               RenderStats& stats) const;
  Color emitted(const LightF& l, Vec3f dir) const;

  const ir::Scene& scene_;
  const EmbreeScene& embree_;
  std::vector<LightF> area_;
  std::vector<PointF> points_;
  Color background_;
  std::uint32_t max_depth_;
  float min_weight_;
  ir::FresnelMode fresnel_;
};

}  // namespace snell::rt
