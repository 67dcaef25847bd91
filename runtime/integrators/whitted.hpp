// The classic (Whitted-style) ray tree of the lecture, §6–§8: direct light through
// shadow rays from point and area lights onto diffuse and glazed surfaces, plus
// recursive mirror, glossy and dielectric rays. Traversal uses an explicit stack,
// so the tree depth (max_depth) never touches the C++ call stack.
//
// Specialisation (architecture: "simulate only the effects a scene calls for"):
// `li` is a template on the render kernel's shading axes (render/kernel.hpp: area,
// dielectric, absorption, interiors, highlights). Without area lights the
// direct-light loop is a single shadow ray per point light; without dielectrics the
// refraction path is not compiled in; without absorption no Beer factor is
// computed; without highlights no Blinn–Phong term is evaluated per light sample.
// Every decision draws the same sampler dimensions in every kernel, so a
// specialised kernel renders the general kernel's picture. Instrumentation comes
// through a Probe (probe.hpp).
#pragma once

#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "runtime/embree_scene.hpp"
#include "runtime/integrators/integrator.hpp"
#include "runtime/integrators/probe.hpp"
#include "runtime/ir/ir.hpp"
#include "runtime/render.hpp"
#include "runtime/render/kernel.hpp"
#include "runtime/render/tile.hpp"
#include "runtime/sampler.hpp"
#include "runtime/shading/area_lanes.hpp"
#include "runtime/shading/interior.hpp"
#include "runtime/shading/lights.hpp"
#include "runtime/shading/materials.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

struct NoInterior {};

// A ray of the tree. `Tracked`: the kernel follows §14 interiors, and each node
// carries the prioritised solids its ray is inside (a kernel without priorities
// keeps the smaller node).
template <bool Tracked>
struct NodeOf {
  Ray ray;
  Vec3f start;  // the surface point the ray leaves, before the origin offset
  Color weight{1, 1, 1};
  std::uint32_t depth = 0;  // reflection/refraction rays after the camera ray
  RayKind kind = RayKind::Camera;
  // glossy_sampling "mis": the density (per unit solid angle) with which the glossy
  // lobe that spawned this ray drew its direction, for the ray's MIS weight where
  // it hits an area light (shading/glossy_mis.hpp); 0: the ray's light counts whole.
  float mis_pdf = 0;
  std::uint64_t key = 0;  // hashed path: names this node's sampler dimensions
  // §8: the Beer coefficient of the dielectric (without priority) the ray travels
  // inside, or null in air: set by a refraction into one, kept by reflections,
  // cleared by a refraction out of one (nested ones are not modelled: leaving the
  // inner one is leaving to air). Read only by kernels with absorption.
  const ir::Vec3* medium = nullptr;
  [[no_unique_address]] std::conditional_t<Tracked, Interior, NoInterior> interior;
};
using Node = NodeOf<false>;

std::string to_string(const NodeOf<false>& n);
std::string to_string(const NodeOf<true>& n);

// The scene's size around `origin` (the camera), at most 1: the largest distance
// of any finite object's bounding corners or any light. Infinite planes do not
// count; nothing finite gives 1. Ray offsets scale with it (offset_ray_origin).
float offset_scale(const ir::Scene& scene, ir::Vec3 origin);

class WhittedIntegrator final : public Integrator {
 public:
  WhittedIntegrator(const ir::Scene& scene, const EmbreeScene& embree, const ImageTextures* images);

  // A lit node's direct-light question: the shading point, the shadow rays' origin
  // (p moved off the surface, spawn_origin), the lobes' normal on the viewer's
  // side, the ray's time, the node's path key (its sampler dimensions) and, for
  // the §16 highlight, the lobe and the direction to the viewer.
  struct DirectQuery {
    Vec3f p, o, n;
    float time = 0;
    std::uint64_t key = 0;
    Highlight highlight;
    Vec3f wo;
    // The plain absorbing dielectric the point lies in (§8: a light inside it is
    // reached through it), or null; set by kernels with absorption only.
    const ir::Vec3* medium = nullptr;
  };
  // A lit node's light, gathered once its children are known: its query, the lobe
  // that reflects it and the node's weight (lit_radiance).
  struct LitNode {
    DirectQuery q;
    DiffuseLobe lobe;
    Color w;
  };
  // At most this many trees go through the ray tree at once (the pixel loop's packet).
  static constexpr std::uint32_t kMaxLanes = 16;
  // One lane of a packet's trees (radiance_packet): its next node, its sum so far
  // and its stack. The next node is shaded where
  // it is: the first child in `kids[gen]` (the node's own children go to the other
  // pair) or the stack's top. Copied out of either, an 80-byte node was loaded
  // whole soon after spawn's field-by-field stores, a store-forwarding stall on
  // every node.
  struct LaneTree {
    NodeOf<false>* node;
    bool on_stack;
    std::uint8_t gen;
    Color total;
    NodeOf<false> kids[2][2];
    std::vector<NodeOf<false>> stack;
  };
  // The ray tree's stack: scratch owned by each thread.
  struct Scratch {
    std::vector<NodeOf<false>> plain;
    std::vector<NodeOf<true>> tracked;  // kernels with interiors
    SurfaceFrame surface;               // §17 "uv": the frame of the hit being shaded
    NodeOf<false> plain_kids[2];        // a node's children, before they are traced
    NodeOf<true> tracked_kids[2];
    LitNode light;  // li's lit node
    Hit hit;        // the hit of a node the pixel loop did not trace
    LaneTree lanes[kMaxLanes];
    LitNode lane_light[kMaxLanes];
    template <bool Tracked>
    auto& stack() {
      if constexpr (Tracked)
        return tracked;
      else
        return plain;
    }
    template <bool Tracked>
    auto* kids() {
      if constexpr (Tracked)
        return tracked_kids;
      else
        return plain_kids;
    }
  };
  // Radiance along a camera ray. `probe` takes the counters and, when on, the
  // readable ray tree and the time of each ray by kind. Child and shadow rays keep
  // the camera ray's time.
  template <class K, class P>
  Color radiance(const Ray& camera_ray, const SampleContext& sc, Scratch& stack, P& probe) const {
    return li<Kernel<K::bits & kShadeAxes>>(camera_ray, sc, stack, probe);
  }
  // The radiance of the packet's camera rays in the lanes of `todo` (a bit per
  // lane): col[i] what radiance() gives for rays[i], from its packet hit (hits[i],
  // found[i]). The trees go node by node side by side: each step traces the
  // lanes' next rays as one packet and their lit nodes' shadow rays as packets
  // (cell by cell), and each lane sums its nodes in li's order, so every colour is
  // li's bit for bit. Kernels with interiors go lane by lane through li.
  template <class K>
  void radiance_packet(std::uint32_t n, std::uint32_t todo, const Ray* rays, Hit* hits,
                       const std::uint8_t* found, const SampleContext* sc, Scratch& scratch,
                       RenderStats& stats, Color* col) const {
    radiance_lanes<Kernel<K::bits & kShadeAxes>>(n, todo, rays, hits, found, sc, scratch, stats,
                                                 col);
  }
  // The general kernel with a probe that has every instrument (tests, --pixel).
  Color li(const Ray& camera_ray, const SampleContext& sc, RenderStats& stats, Scratch& stack,
           std::string* trace) const {
    Probe<true> probe{stats, trace, nullptr};
    return li<GeneralKernel>(camera_ray, sc, stack, probe);
  }

  TileFn tile_kernel(unsigned bits) const override;
  std::string to_string() const override;

 private:
  // The kernel axes the ray tree reads; the others (lens, time) are the pixel loop's.
  static constexpr unsigned kShadeAxes = (1u << kAxis_area) | (1u << kAxis_dielectric) |
                                         (1u << kAxis_absorption) | (1u << kAxis_interiors) |
                                         (1u << kAxis_finish);
  // `primary`: the camera ray's hit when the pixel loop traced it in a packet.
  template <class K, class P>
  Color li(const Ray& camera_ray, const SampleContext& sc, Scratch& stack, P& probe,
           const PrimaryHit* primary = nullptr) const;
  template <class K, class P>
  Color node_radiance(NodeOf<K::interiors>& node, Vec3f d, Hit& hit, bool found,
                      const SampleContext& sc, Scratch& scratch, P& probe, LitNode& dl, bool& lit,
                      NodeOf<K::interiors>* kids, int& nkids, std::string& desc) const;
  template <class K>
  void radiance_lanes(std::uint32_t n, std::uint32_t todo, const Ray* rays, Hit* hits,
                      const std::uint8_t* found, const SampleContext* sc, Scratch& scratch,
                      RenderStats& stats, Color* col) const;
  // The two commonest roots of a packet, without node_radiance: a camera ray that
  // escapes to a constant background (`out` its radiance, no light), and one on a
  // plain diffuse surface (plain_diffuse_), whose light query is set as
  // node_radiance sets it (`out` 0, `lit`). False: node_radiance must take it.
  template <class K>
  bool plain_root(const Ray& ray, const Hit& hit, bool found, RenderStats& stats, LitNode& dl,
                  Color& out, bool& lit) const;

 private:
  // `lanes` queries' direct light, each as direct() alone would sum it: e[i] the
  // Lambertian sum E, spec[i] the §16 highlight's (finish kernels). The light
  // samples go light by light, cell by cell; each cell's shadow rays of all lanes
  // are one occlusion query (a packet when lanes > 1). `in`: the interior at the
  // shading point, lanes == 1 only (null without interiors).
  template <class K, std::uint32_t kLanes>
  void direct_lanes(std::uint32_t lanes, const DirectQuery* const* q,
                    const SampleContext* const* sc, RenderStats& stats, const Interior* in,
                    Color* e, Color* spec) const;
  // What a lit node reflects of E (and the highlight's sum), li's order.
  template <class K>
  static Color lit_radiance(const DiffuseLobe& lobe, const DirectQuery& q, Color w, Color e,
                            Color spec);
  // Whether a shadow ray is blocked; `tr` is multiplied by the Beer factor of the
  // medium it crosses when it is not (interiors only).
  template <class K>
  bool shadow_blocked(const Ray& r, const Interior* in, Color& tr) const;
  // glossy_sampling "mis": the area lights' share seen through light samples at a
  // glossy hit (p the shading point, o the shadow rays' origin, nf the normal on the
  // viewer's side, `lobe` the lobe the glossy ray was drawn from): the sum of
  // Le · x / (1 + x²) over one sample per light cell (shading/glossy_mis.hpp), to be
  // multiplied by the glossy ray's weight. Counts its shadow rays in `n_rays`.
  template <class K>
  Color glossy_lights(const GlossySquare& lobe, Vec3f wo, Vec3f p, Vec3f o, Vec3f nf, float time,
                      std::uint64_t key, const SampleContext& sc, const Interior* in,
                      std::uint64_t& n_rays) const;

  // §12: the motion of the CSG leaf a hit is on, when the leaf moves inside its CSG
  // object (space "object" patterns move with it); null otherwise.
  const ir::Motion* leaf_motion(const Hit& hit) const {
    if (hit.part == ir::kNoPart || hit.part >= scene_.parts.size()) return nullptr;
    const ir::Motion& m = scene_.parts[hit.part].motion();
    return m.empty() ? nullptr : &m;
  }

  const ir::Scene& scene_;
  const EmbreeScene& embree_;
  Lights lights_;
  Interiors interiors_;  // §14; empty unless the scene uses priorities
  // §17: the escaping ray's colour, the pattern's at its unit direction (the
  // direction is the pattern point, in world space, not moved inward).
  Color sky(Vec3f dir, float time, RenderStats& stats) const;
  Color background_;                                 // a constant background
  const ir::Texture* background_pattern_ = nullptr;  // or a pattern one
  const ImageTextures* images_;                      // §17; null without images
  bool maps_uv_ = false;  // some surface's image maps "uv": hits find their SurfaceFrame
  const ir::Vec3* camera_medium_ = nullptr;  // the plain absorbing dielectric around the camera
  float pixel_angle_ = 0;  // radians per pixel: the footprint's width at distance 1
  std::uint32_t max_depth_;
  float min_weight_;
  ir::FresnelMode fresnel_;
  float offset_scale_ = 1;                 // the scene's size around the camera, at most 1
  AreaLanesFn area_lanes_ = area_lanes();  // a packet's light cells in SIMD, or null
  bool stochastic_branching_ = false;      // settings.branching "stochastic"
  bool roulette_ = false;                  // settings.termination "roulette"
  bool glossy_mis_ = false;                // settings.glossy_sampling "mis" with area lights
  // Per material: a diffuse one with a constant colour and no bump, whose camera-ray
  // hits the pixel loop's packet shades without node_radiance (plain_root). The
  // commonest root of all; the general node was a quarter of a diffuse scene's time.
  struct PlainDiffuse {
    bool on = false;
    Color albedo;
    Highlight highlight;
  };
  std::vector<PlainDiffuse> plain_diffuse_;
};

}  // namespace snell::rt
