#include "runtime/integrators/whitted.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "runtime/geometry/point_inside.hpp"
#include "runtime/integrators/whitted_light.hpp"
#include "runtime/ir/bounds.hpp"
#include "runtime/shading/bump.hpp"
#include "runtime/shading/fresnel.hpp"
#include "runtime/shading/shading_normal.hpp"
#include "runtime/uninit.hpp"

namespace snell::rt {

using namespace whitted_detail;

namespace {

Color to_color(ir::Vec3 v) {
  return to_float(v.x, v.y, v.z);
}

// The camera ray's path key (hash_combine(0x5eed, 0)), computed once.
const std::uint64_t kRootKey = hash_combine(0x5eed, 0);

// The Beer factor of coefficient a over distance `dist` (beer: exp(-0·∞) is 1).
Color beer_color(const ir::Vec3& a, double dist) {
  return to_float(beer(a.x, dist), beer(a.y, dist), beer(a.z, dist));
}

std::string fmt_color(Color c) {
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", c.x, c.y, c.z);
}

// The tree's root: the camera ray, leaving the camera, with the root's path key.
// Set field by field in place: a node made on the frame and copied whole stalled
// on store forwarding (2 % of the glass bench).
template <class N>
[[gnu::always_inline]] inline void set_root_node(N& node, const Ray& camera_ray,
                                                 const ir::Vec3* medium) {
  node.ray = camera_ray;
  node.start = camera_ray.org;
  node.weight = Color(1, 1, 1);
  node.depth = 0;
  node.kind = RayKind::Camera;
  node.mis_pdf = 0;
  node.key = kRootKey;
  node.medium = medium;
  node.interior = {};
}

// The walk's next node after one with `nkids` children: its first child (its
// siblings wait on the stack, the reflection is traced first), else the top of the
// stack; `d` that node's direction. False: the tree is done.
template <class N>
[[gnu::always_inline]] inline bool next_node(std::vector<N>& stack, const N* kids, int nkids,
                                             N& node, Vec3f& d) {
  if (nkids > 0) {
    for (int i = nkids - 1; i >= 1; --i) stack.push_back(kids[i]);
    d = kids[0].ray.dir;
    node = kids[0];
  } else if (!stack.empty()) {
    d = stack.back().ray.dir;
    node = stack.back();
    stack.pop_back();
  } else {
    return false;
  }
  return true;
}

struct TraceEntry {
  std::uint32_t depth;
  std::string text;
};

}  // namespace

std::string to_string(RayKind k) {
  switch (k) {
    case RayKind::Camera:
      return "camera";
    case RayKind::Reflection:
      return "reflection";
    case RayKind::Refraction:
      return "refraction";
    case RayKind::Glossy:
      return "glossy";
  }
  return "?";
}

std::string to_string(const SampleContext& c) {
  return fmt::format("sample_context {{ {} pixel {},{} index {} }}", rt::to_string(c.spec), c.px,
                     c.py, c.index);
}

std::string to_string(const NodeOf<false>& n) {
  return fmt::format("node {{ {} {} weight {} depth {} key {:x} }}", rt::to_string(n.kind),
                     rt::to_string(n.ray), fmt_color(n.weight), n.depth, n.key);
}
std::string to_string(const NodeOf<true>& n) {
  return fmt::format("node {{ {} {} weight {} depth {} key {:x} {} }}", rt::to_string(n.kind),
                     rt::to_string(n.ray), fmt_color(n.weight), n.depth, n.key,
                     rt::to_string(n.interior));
}

float offset_scale(const ir::Scene& scene, ir::Vec3 o) {
  double extent = 0;
  for (const ir::Shape& s : scene.shapes)
    ir::world_hull_points(s, scene,
                          [&](ir::Vec3 p) { extent = std::fmax(extent, ir::reach(p, o)); });
  for (const ir::PointLight& l : scene.point_lights)
    extent = std::fmax(extent, ir::reach(l.position, o));
  for (const ir::AreaLight& l : scene.area_lights)
    extent = std::fmax(std::fmax(extent, ir::reach(l.corner, o)),
                       ir::reach(l.corner + l.edge1 + l.edge2, o));
  if (!(extent > 0) || !std::isfinite(extent)) return 1.0f;
  return float(std::fmin(1.0, std::fmax(extent, 1e-30)));
}

WhittedIntegrator::WhittedIntegrator(const ir::Scene& scene, const EmbreeScene& embree,
                                     const ImageTextures* images)
    : scene_(scene),
      embree_(embree),
      lights_(scene, embree.origin()),
      interiors_(scene),
      images_(images) {
  // The angle a pixel spans at the image's centre (fov is horizontal).
  double half = scene.camera.fov * kImagePi / 360;
  pixel_angle_ = float(2 * std::tan(half) / double(std::max(1u, scene.settings.width)));
  offset_scale_ = offset_scale(scene, embree.origin());
  if (scene.background.is_constant())
    background_ = to_color(std::get<ir::Constant>(scene.background.pattern).color);
  else
    background_pattern_ = &scene.background;
  // Only "uv" reads the hit's surface: without it no hit pays for its frame.
  auto uv = [](const ir::Texture& t) {
    const auto* im = std::get_if<ir::ImageTexture>(&t.pattern);
    return im && im->mapping == ir::ImageMapping::Uv;
  };
  for (const ir::Material& m : scene.materials) {
    maps_uv_ = maps_uv_ || uv(m.bump.pattern);
    std::visit(
        [&](const auto& model) {
          ir::for_each_field(model, [&](const char*, const auto& v) {
            if constexpr (std::is_same_v<std::decay_t<decltype(v)>, ir::Texture>)
              maps_uv_ = maps_uv_ || uv(v);
          });
        },
        m.model);
  }
  maps_uv_ = maps_uv_ && images_;
  for (const ir::Material& m : scene.materials) {
    PlainDiffuse& pd = plain_diffuse_.emplace_back();
    const ir::Diffuse* dm = m.as<ir::Diffuse>();
    if (!dm || !dm->color.is_constant() || m.bump.on()) continue;
    pd.on = true;
    pd.albedo = to_color(std::get<ir::Constant>(dm->color.pattern).color);
    pd.highlight = {float(dm->specular), float(dm->shininess)};
  }
  // §8: a camera inside an absorbing dielectric without priority (a diver in a
  // sea that is one plain box): its rays travel in it from the start, to whatever
  // they meet. Tested at the shutter-open placement; among several, the last in
  // the file (nested plain dielectrics are not modelled); a part of an instance
  // is not looked into.
  for (const ir::Shape& s : scene.shapes) {
    if (s.material >= scene.materials.size() || s.as<ir::Instance>()) continue;
    const ir::Dielectric* d = scene.materials[s.material].as<ir::Dielectric>();
    if (!d || d->priority > 0 || (d->absorb.x == 0 && d->absorb.y == 0 && d->absorb.z == 0))
      continue;
    if (geom::point_inside(scene, s, scene.camera.location, geom::InsideRule::Medium))
      camera_medium_ = &d->absorb;
  }
  max_depth_ = scene.settings.max_depth;
  min_weight_ = float(scene.settings.min_weight);
  fresnel_ = scene.settings.fresnel;
  stochastic_branching_ = scene.settings.branching == ir::Branching::Stochastic;
  roulette_ = scene.settings.termination == ir::Termination::Roulette;
  glossy_mis_ =
      scene.settings.glossy_sampling == ir::GlossySampling::Mis && !scene.area_lights.empty();
}

Color WhittedIntegrator::sky(Vec3f dir, float time, RenderStats& stats) const {
  Vec3f u = normalize(dir);
  TexturePoint tp{u,       Vec3f(0.0f), ir::Vec3{0, 0, 0}, nullptr, time, &stats.function_nonfinite,
                  images_, u,           pixel_angle_};
  return texture_color(*background_pattern_, tp);
}

// What node_radiance does with such a root, step for step: the background times
// the root's unit weight added to its zero contribution; or the same normal on the
// ray's side, the same shadow-ray origin (spawn_origin of a hit that is not
// smooth), the lobe scatter(ir::Diffuse) makes of a constant colour, and the unit
// weight of a root. The packet test compares it with one-ray tiles, which never
// take it.
template <class K>
[[gnu::always_inline]] inline bool WhittedIntegrator::plain_root(const Ray& ray, const Hit& hit,
                                                                 bool found, RenderStats& stats,
                                                                 LitNode& dl, Color& out,
                                                                 bool& lit) const {
  if (camera_medium_) return false;  // its rays start in an absorbing medium
  if (!found) {
    if (background_pattern_) return false;
    ++stats.camera_rays;
    out = Color(0) + Color(1, 1, 1) * background_;
    lit = false;
    return true;
  }
  if (hit.kind != Hit::Kind::Shape || hit.smooth) return false;
  const PlainDiffuse& m = plain_diffuse_[hit.material];
  if (!m.on) return false;
  ++stats.camera_rays;
  const Vec3f d = ray.dir, ng = hit.ng;
  const Vec3f nf = dot(d, ng) < 0 ? ng : -ng;
  dl.q.p = hit.p, dl.q.o = spawn_origin(hit, nf, offset_scale_), dl.q.n = nf;
  dl.q.time = ray.time, dl.q.key = kRootKey, dl.q.medium = nullptr;
  if constexpr (K::finish) dl.q.highlight = m.highlight, dl.q.wo = -d;
  dl.lobe.albedo = m.albedo, dl.lobe.scale = DiffuseLobe::kInvPi;
  dl.w = Color(1, 1, 1);
  out = Color(0);
  lit = true;
  return true;
}

template <class K>
void WhittedIntegrator::radiance_lanes(std::uint32_t n, std::uint32_t todo, const Ray* rays,
                                       Hit* hits, const std::uint8_t* found,
                                       const SampleContext* sc, Scratch& scratch,
                                       RenderStats& stats, Color* col) const {
  Probe<false> probe{stats};
  if constexpr (K::interiors) {
    // A prioritised surface that does not count sends the same ray on at once.
    for (std::uint32_t i = 0; i < n; ++i)
      if ((todo >> i) & 1) {
        PrimaryHit primary{&hits[i], found[i] != 0};
        col[i] = li<K>(rays[i], sc[i], scratch, probe, &primary);
      }
  } else {
    LaneTree* const lanes = scratch.lanes;
    LitNode* const light = scratch.lane_light;
    // The step's lanes, their rays and answers (a step after the first traces them).
    std::uint32_t lane[kMaxLanes];
    Uninit<Ray, kMaxLanes> ray_store;
    Uninit<Hit, kMaxLanes> hit_store;
    std::uint8_t step_found[kMaxLanes];
    Uninit<Color, kMaxLanes> step_store;  // each lane's contribution of this step
    Color* const step = step_store.v;
    std::string desc;  // no trace under Probe<false>: never written
    std::uint32_t active = todo;
    for (bool first = true; active; first = false) {
      std::uint32_t m = 0;
      for (std::uint32_t i = 0; i < n; ++i)
        if ((active >> i) & 1) lane[m++] = i;
      if (!first) {
        for (std::uint32_t j = 0; j < m; ++j) ray_store.v[j] = lanes[lane[j]].node->ray;
        // The lanes' rays after the first bounce: each tree's own, so incoherent.
        embree_.intersect(std::span<const Ray>(ray_store.v, m), std::span<Hit>(hit_store.v, m),
                          std::span<std::uint8_t>(step_found, m), false);
      }
      const DirectQuery* q[kMaxLanes];
      const SampleContext* qsc[kMaxLanes];
      std::uint32_t lit_lane[kMaxLanes], nlit = 0;
      for (std::uint32_t j = 0; j < m; ++j) {
        const std::uint32_t i = lane[j];
        LaneTree& t = lanes[i];
        Hit& hit = first ? hits[i] : hit_store.v[j];
        const bool f = first ? found[i] != 0 : step_found[j] != 0;
        bool lit = false;
        int nkids = 0;
        if (first) {
          t.total = Color(0);
          t.stack.clear();
          if (plain_root<K>(rays[i], hit, f, stats, light[i], step[i], lit)) {
            if (lit) q[nlit] = &light[i].q, qsc[nlit] = &sc[i], lit_lane[nlit++] = i;
            active &= ~(1u << i);  // no children
            continue;
          }
          set_root_node(t.kids[0][0], rays[i], camera_medium_);
          t.node = &t.kids[0][0], t.gen = 0, t.on_stack = false;
        }
        // The node's children go to the pair the node is not in.
        const std::uint8_t pair = t.on_stack ? 0 : t.gen ^ 1;
        NodeOf<false>* const kids = t.kids[pair];
        step[i] = node_radiance<K>(*t.node, t.node->ray.dir, hit, f, sc[i], scratch, probe,
                                   light[i], lit, kids, nkids, desc);
        if (lit) q[nlit] = &light[i].q, qsc[nlit] = &sc[i], lit_lane[nlit++] = i;
        // The lane's next node, as li walks: the first child (its siblings wait on
        // the stack), else the stack's top.
        if (t.on_stack) t.stack.pop_back();
        if (nkids > 0) {
          for (int k = nkids - 1; k >= 1; --k) t.stack.push_back(kids[k]);
          t.node = &kids[0], t.gen = pair, t.on_stack = false;
        } else if (!t.stack.empty()) {
          t.node = &t.stack.back(), t.on_stack = true;
        } else {
          active &= ~(1u << i);
        }
      }
      if (nlit > 0) {
        Uninit<Color, kMaxLanes> e_store, spec_store;  // direct_lanes sets them
        Color *const e = e_store.v, *const spec = spec_store.v;
        direct_lanes<K, kMaxLanes>(nlit, q, qsc, stats, nullptr, e, spec);
        for (std::uint32_t j = 0; j < nlit; ++j) {
          const LitNode& l = light[lit_lane[j]];
          step[lit_lane[j]] = lit_radiance<K>(l.lobe, l.q, l.w, e[j], spec[j]);
        }
      }
      for (std::uint32_t j = 0; j < m; ++j) lanes[lane[j]].total += step[lane[j]];
    }
    for (std::uint32_t i = 0; i < n; ++i)
      if ((todo >> i) & 1) col[i] = lanes[i].total;
  }
}

// One node of the tree: li's loop body without the walk. `hit`, `found`: the
// answer to the node's ray (kernels with interiors trace on from it through the
// surfaces that do not count). Returns the node's contribution without its direct
// light: when the node is lit, `lit` is set and `dl` holds its light query, whose
// lit_radiance is then the node's whole contribution. The children are left in
// kids[0, nkids), the reflection first (li: the scratch's pair; a lane: its own).
template <class K, class P>
[[gnu::always_inline]] inline Color WhittedIntegrator::node_radiance(
    NodeOf<K::interiors>& node, const Vec3f d, Hit& hit, bool found, const SampleContext& sc,
    Scratch& scratch, P& probe, LitNode& dl, bool& lit, NodeOf<K::interiors>* const kids,
    int& nkids, std::string& desc) const {
  RenderStats& stats = probe.stats;
  // Null at compile time under Probe<false>: every use below folds away.
  std::string* const trace = probe.trace;
  using N = NodeOf<K::interiors>;
  const auto& mats = scene_.materials;
  Color contrib(0);
  lit = false;
  nkids = 0;
  Vec3f p_surface;
  switch (node.kind) {
    case RayKind::Camera:
      ++stats.camera_rays;
      break;
    case RayKind::Reflection:
      ++stats.reflection_rays;
      break;
    case RayKind::Refraction:
      ++stats.refraction_rays;
      break;
    case RayKind::Glossy:
      ++stats.glossy_rays;
      break;
  }
  // The interior a refracted child starts with: the far side of a prioritised
  // surface that counts, else the node's own (plain dielectrics are not tracked).
  [[maybe_unused]] std::conditional_t<K::interiors, Interior, NoInterior> far_side{};
  if constexpr (K::interiors) far_side = node.interior;
  auto spawn = [&](RayKind kind, Vec3f org, Vec3f dir, Color w, std::uint64_t slot,
                   const ir::Vec3* medium, float tnear = 0) {
    if (w.x == 0 && w.y == 0 && w.z == 0) return;  // nothing to carry: not a prune
    if (node.depth + 1 > max_depth_) {
      ++stats.pruned_by_depth;
      return;
    }
    if (min_weight_ > 0 && max_component(w) < min_weight_) {
      // Cutoff drops the branch (biased dark). Russian roulette keeps it with
      // probability q = weight / min_weight and divides its weight by q, so
      // its expected contribution is unchanged.
      float q = max_component(w) / min_weight_;
      if (!roulette_ || draw1(sc, node_dim(child_key(node.key, slot), 11)) >= q) {
        ++stats.pruned_by_weight;
        return;
      }
      w = w * (1 / q);
    }
    N& k = kids[nkids++];
    k.ray = Ray{org, dir, INFINITY, node.ray.time, tnear};
    k.start = p_surface;
    k.weight = w;
    k.depth = node.depth + 1;
    k.kind = kind;
    k.mis_pdf = 0;
    k.key = child_key(node.key, slot);
    k.medium = medium;
    if constexpr (K::interiors) k.interior = kind == RayKind::Refraction ? far_side : node.interior;
  };

  // §14: surfaces of prioritised solids that do not count are passed straight
  // through: the same ray goes on, with no depth and no weight change, updating
  // its interior. `crossing` is the surface that counts, when the hit is one.
  [[maybe_unused]] bool lost = false, prioritised = false;
  [[maybe_unused]] int passes = 0;
  [[maybe_unused]] std::conditional_t<K::interiors, Crossing, NoInterior> crossing{};
  if constexpr (K::interiors) {
    std::uint32_t solid = 0;
    while (found && hit.kind == Hit::Kind::Shape &&
           interiors_.priority(solid = interiors_.solid(hit)) > 0) {
      crossing = interiors_.cross(node.interior, solid, dot(d, hit.ng) < 0);
      if (crossing.overflow) ++stats.interior_overflows;
      if (crossing.counts) {
        prioritised = true;
        break;
      }
      node.interior = crossing.after;
      ++stats.interior_passes;
      if (++passes > kMaxPassThroughs) {
        lost = true;
        ++stats.interior_lost;
        break;
      }
      node.ray.tnear = std::nextafter(hit.t, float(INFINITY));
      found = embree_.intersect(node.ray, hit);
    }
    far_side = node.interior;
  }
  // The Beer coefficient of the medium the ray travels in, or null in air: the
  // prioritised solid its interior names (§14), else the plain dielectric it
  // entered (§8). Rays that escape or reach a light inside one are absorbed too.
  [[maybe_unused]] auto travel_medium = [&]() -> const ir::Vec3* {
    const ir::Vec3* a = nullptr;
    if constexpr (K::absorption) {
      if constexpr (K::interiors) a = interiors_.absorb(node.interior.medium());
      if (!a) a = node.medium;
    }
    return a;
  };
  if (K::interiors && lost) {
    if (trace) desc = fmt::format("lost: passed through {} surfaces", passes - 1);
  } else if (!found) {
    contrib = node.weight * (background_pattern_ ? sky(d, node.ray.time, stats) : background_);
    // A ray that escapes from inside an absorbing medium (the sea seen from below)
    // has travelled an infinite distance in it.
    if (const ir::Vec3* a = travel_medium()) contrib = contrib * beer_color(*a, INFINITY);
    if (trace) desc = "escapes: background";
  } else if (hit.kind == Hit::Kind::AreaLight) {
    const AreaLightF& l = lights_.areas[hit.index];
    contrib = node.weight * l.le(d);
    if (K::area && node.mis_pdf > 0) {
      // The glossy ray's MIS weight against the light cell it hit (glossy_mis.hpp).
      Vec3f path = (node.ray.org - node.start) + d * hit.t;
      double d2 = double(dot(path, path));
      double p_c = cell_density(d2, double(dot(d, l.n)), l.cell_area());
      contrib = contrib * float(mis_ray_weight(node.mis_pdf, p_c));
    }
    if (const ir::Vec3* a = travel_medium()) {
      Vec3f path = (node.ray.org - node.start) + d * hit.t;
      contrib = contrib * beer_color(*a, double(length(path)));
    }
    if (trace)
      desc = fmt::format("hits area light {} ({}) t={:.6g}", hit.index,
                         ir::to_string(scene_.area_lights[hit.index].src, scene_), hit.t);
  } else {
    const ir::Shape& shape = scene_.shapes[hit.index];
    const ir::Material& mat = mats[hit.material];
    Vec3f p = hit.p;
    p_surface = p;
    Vec3f ng = hit.ng;               // outward
    bool entering = dot(d, ng) < 0;  // §8: against the outward normal
    Vec3f nf = entering ? ng : -ng;  // the normal on the ray's side
    // §17: the footprint is the pixel's width at the hit's distance from the
    // camera (for mirrored and refracted rays too: an estimate, not their own
    // differentials).
    // §17 "uv": the surface hit, found only when some image maps "uv".
    // In the thread's scratch, not on this frame: a SurfaceFrame holds a Transform
    // (280 bytes), and building an identity one per node (even an empty
    // std::optional of one, which GCC zeroes) was 12 % of this function's time.
    SurfaceFrame* surface = nullptr;
    if (maps_uv_) {
      surface = &scratch.surface;
      *surface = surface_frame(scene_, shape, hit.part, hit.outer, 0, double(node.ray.time));
      if (surface->leaf->kind() == ir::ShapeKind::Mesh) surface->tri = embree_.triangle_of(hit);
    }
    const TexturePoint tex{p,
                           ng,
                           embree_.origin(),
                           &shape,
                           node.ray.time,
                           &stats.function_nonfinite,
                           images_,
                           images_ ? normalize(d) : Vec3f{},  // only images read these
                           images_ ? pixel_angle_ * length(p) : 0.0f,
                           surface,
                           leaf_motion(hit)};
    // The lobes' normal: nf, or a smooth mesh's or a bump's (§16) shading normal made
    // valid for this viewer (hard case #20, shading/shading_normal.hpp).
    Vec3f ns_out = hit.ns;
    bool bent = hit.smooth, bumped = false;
    if constexpr (K::finish)
      if (mat.bump.on()) {
        ns_out = bump_normal(mat.bump, tex, hit.smooth ? hit.ns : ng, ng);
        bent = bumped = true;
      }
    const HitFrame frame = HitFrame::make(-d, nf, entering, bent, ns_out, bumped);
    Color w = node.weight;
    if (trace)
      desc =
          fmt::format("hits shape {} ({} {}, {}) t={:.6g} {}", hit.index,
                      ir::to_string(shape.kind()), ir::to_string(mat.kind()),
                      ir::to_string(shape.src, scene_), hit.t, entering ? "entering" : "exiting");
    if (trace && frame.smooth)
      desc +=
          fmt::format(" shading normal ({:.4g}, {:.4g}, {:.4g}) geometric ({:.4g}, {:.4g}, {:.4g})",
                      frame.ns.x, frame.ns.y, frame.ns.z, nf.x, nf.y, nf.z);
    if (trace && frame.smooth &&
        (frame.nl.x != frame.ns.x || frame.nl.y != frame.ns.y || frame.nl.z != frame.ns.z))
      desc +=
          fmt::format(" lit about ({:.4g}, {:.4g}, {:.4g})", frame.nl.x, frame.nl.y, frame.nl.z);
    if constexpr (K::interiors) {
      if (trace) {
        if (passes > 0) desc += fmt::format(" after passing through {} surface(s)", passes);
        desc += " " + (prioritised ? rt::to_string(crossing) : rt::to_string(node.interior));
      }
    }
    // Not compiled in: a kernel without dielectrics has none to shade.
    bool shaded = K::dielectric || !std::holds_alternative<ir::Dielectric>(mat.model);
    // The medium the ray has travelled in: the inside of the dielectric it leaves
    // (§8), the near side of a prioritised surface that counts (§14), else the
    // medium it travels in, whatever it meets there (a mirror, a pebble under the
    // sea): §8's light travelling d inside.
    const ir::Vec3* a = K::absorption && !entering ? medium_absorb(mat) : nullptr;
    bool crossed = false;  // a prioritised surface that counts: its near medium
    // A prioritised surface met from air as far as interiors go may be met inside
    // a plain dielectric (absorbing glass holding clear water): its Beer then.
    if constexpr (K::interiors && K::absorption)
      if (prioritised)
        a = interiors_.absorb(crossing.from), crossed = crossing.from != Interior::kAir;
    if (!a && !crossed) a = travel_medium();
    if (a) {
      // Beer over the path inside this object (nested media are not modelled),
      // measured from the surface point the ray left, not its offset origin:
      // near the origin the offset is 2^-16 absolute, visible in thin slabs.
      // Summed as (origin - start) + t·d rather than p - start: the first is
      // exact (two nearby floats) and t·d is good to ulps of the path itself,
      // where p - start is good only to ulps of p (2.4 % of a 1e-5 slab 3 units
      // from the camera).
      Vec3f path = (node.ray.org - node.start) + d * hit.t;
      double dist = double(length(path));
      w = w * to_float(beer(a->x, dist), beer(a->y, dist), beer(a->z, dist));
    }
    // Where rays leaving on the ray's side start (shadow and reflection rays).
    const Vec3f o_out = spawn_origin(hit, nf, offset_scale_);
    auto lobe1 = [&] { return draw1(sc, node_dim(node.key, 9)); };
    auto lobe2 = [&] { return draw2(sc, node_dim(node.key, 7)); };
    ScatterContext<decltype(lobe1), decltype(lobe2)> cx{
        -d, frame.ns, entering, tex, fresnel_, stochastic_branching_, lobe1, lobe2};
    // The medium a refracted child travels in: the dielectric it enters, air when
    // it leaves one (or crosses a prioritised surface: its interior says).
    [[maybe_unused]] const ir::Vec3* far_medium = nullptr;
    if constexpr (K::absorption)
      if (entering && !(K::interiors && prioritised)) far_medium = medium_absorb(mat);
    if (shaded) {
      const Scatter s = [&] {
        if constexpr (K::interiors) {
          if (prioritised) {
            // §14: the interface between the media on the two sides.
            far_side = crossing.after;
            return scatter_interface(interiors_.ior(crossing.to) / interiors_.ior(crossing.from),
                                     cx);
          }
        }
        return scatter(mat, cx);
      }();
      if (s.tir) ++stats.tir_events;
      if (s.lit) {
        // Smooth: lit by the shading normal's hemisphere, the shadow rays leaving
        // from the point lifted towards the smooth surface (Hanika 2021), so the
        // terminator of a coarse mesh is not a row of black facets.
        Vec3f o_light = o_out;
        if (hit.smooth) {
          Hit lifted = hit;
          lifted.p = hit.ps;
          o_light = spawn_origin(lifted, nf, offset_scale_);
        }
        dl.q.p = p, dl.q.o = o_light, dl.q.n = frame.nl;
        dl.q.time = node.ray.time, dl.q.key = node.key, dl.q.medium = nullptr;
        // A plain medium's Beer on the way to a light inside it; a prioritised
        // one's is the shadow ray's (shadow_blocked).
        if constexpr (K::absorption) {
          dl.q.medium = node.medium;
          if constexpr (K::interiors)
            if (interiors_.absorb(node.interior.medium())) dl.q.medium = nullptr;
        }
        if constexpr (K::finish) dl.q.highlight = s.highlight, dl.q.wo = -d;
        // Field by field: a 16-byte copy of the lobe stalled on store forwarding.
        dl.lobe.albedo = s.lit->albedo, dl.lobe.scale = s.lit->scale;
        dl.w = w;
        lit = true;
      }
      for (int i = 0; i < s.count; ++i) {
        const Branch& b = s.branches[i];
        switch (b.from) {
          case Branch::From::Outside:
            spawn(b.kind, o_out, frame.leave(b.wi, true), w * b.weight, b.slot, node.medium);
            break;
          case Branch::From::Inside:
            spawn(b.kind, spawn_origin(hit, -nf, offset_scale_), frame.leave(b.wi, false),
                  w * b.weight, b.slot, far_medium);
            break;
          case Branch::From::SameRay:
            // Still a refraction for max_depth and min_weight as §6 defines them.
            spawn(b.kind, node.ray.org, d, w * b.weight, b.slot, far_medium,
                  std::nextafter(hit.t, float(INFINITY)));
            break;
        }
      }
      // glossy_sampling "mis": a glossy ray that was traced (not pruned) shares the
      // area lights with one light sample per cell. Not on a bent frame (a smooth
      // mesh or a bump), where the ray is folded above the geometric surface and
      // the lobe's density is no longer p_b.
      if constexpr (K::area) {
        const ir::Glossy* gm;
        if (glossy_mis_ && nkids == 1 && !frame.smooth && (gm = mat.as<ir::Glossy>()) &&
            gm->blur > 0) {
          const GlossySquare lobe{s.branches[0].weight, float(gm->blur)};
          N& k = kids[0];
          float p_b = lobe.pdf(-d, frame.nf, k.ray.dir);
          if (p_b > 0 && std::isfinite(p_b)) {
            k.mis_pdf = p_b;
            const Interior* in_mis = nullptr;
            if constexpr (K::interiors) in_mis = &node.interior;
            std::uint64_t n0 = stats.shadow_rays;
            Color ll = glossy_lights<K>(lobe, -d, p, o_out, nf, node.ray.time, node.key, sc, in_mis,
                                        stats.shadow_rays);
            contrib += k.weight * ll;
            if (trace)
              desc += fmt::format(" glossy mis: lobe pdf {:.6g}, {} light sample(s)", p_b,
                                  stats.shadow_rays - n0);
          }
        }
      }
    }
  }
  return contrib;
}

template <class K, class P>
Color WhittedIntegrator::li(const Ray& camera_ray, const SampleContext& sc, Scratch& scratch,
                            P& probe, const PrimaryHit* primary) const {
  RenderStats& stats = probe.stats;
  // Null at compile time under Probe<false>: every use below folds away.
  std::string* const trace = probe.trace;
  CostClock* const cost = probe.cost;
  Color total(0);
  std::vector<TraceEntry> entries;
  using N = NodeOf<K::interiors>;
  auto& stack = scratch.template stack<K::interiors>();
  stack.clear();
  // Depth-first, reflection before refraction. The first child of a node is
  // traced next without a round trip through the stack; only its siblings wait
  // there (most trees are a single chain, and a diffuse hit has no child).
  N node;
  set_root_node(node, camera_ray, camera_medium_);
  // The next node's direction, read from where the node is copied from: loaded
  // back from the fresh copy it straddled two of the copy's 16-byte stores, and
  // the failed store forwarding was a quarter of this function's time.
  Vec3f d_next = camera_ray.dir;
  if constexpr (K::interiors) node.interior = interiors_.camera();
  // A node's children are collected here; kids[0] (the reflection) is traced next.
  // In the thread's scratch, made once per thread: spawn() sets every field, and
  // default nodes and queries made per tree were a 200-byte memset per sample.
  N* const kids = scratch.template kids<K::interiors>();
  LitNode& dl = scratch.light;  // a lit node's light query

  for (;;) {
    double t_node = cost ? CostClock::now_ns() : 0, nested = 0;
    std::string desc;
    // The root works on the packet's hit in place; every other node on a fresh
    // one in the scratch, made only then (a default Hit is ~90 bytes of stores, and
    // GCC zeroed even an empty std::optional<Hit> here on every node).
    Hit& hit = primary ? *primary->hit : (scratch.hit = Hit{});
    const bool found = primary ? primary->found : embree_.intersect(node.ray, hit);
    primary = nullptr;
    bool lit;
    int nkids;
    Color contrib =
        node_radiance<K>(node, d_next, hit, found, sc, scratch, probe, dl, lit, kids, nkids, desc);
    if (lit) {
      // Direct light is timed as shadow cost and taken out of the node's own time.
      const Interior* in_here = nullptr;  // the interior at the shading point
      if constexpr (K::interiors) in_here = &node.interior;
      Color e, spec(0);
      const SampleContext* scp = &sc;
      const DirectQuery* qp = &dl.q;
      double t0 = cost ? CostClock::now_ns() : 0;
      direct_lanes<K, 1>(1, &qp, &scp, stats, in_here, &e, &spec);
      if constexpr (P::on) {
        if (cost) {
          double dt = cost->since(t0);
          cost->ns[kCostShadow] += dt;
          nested += dt + cost->overhead_ns;
        }
      }
      contrib = lit_radiance<K>(dl.lobe, dl.q, dl.w, e, spec);
    }
    total += contrib;
    if constexpr (P::on) {
      if (cost) cost->ns[int(node.kind)] += std::fmax(0.0, cost->since(t_node) - nested);
    }
    if (P::on && trace) {
      entries.push_back(
          {node.depth,
           fmt::format("{} depth {} weight {}: {} -> contribution {}", rt::to_string(node.kind),
                       node.depth, fmt_color(node.weight), desc, fmt_color(contrib))});
    }
    if (!next_node(stack, kids, nkids, node, d_next)) break;
  }
  if constexpr (P::on) {
    if (trace)
      for (const TraceEntry& e : entries)
        *trace += std::string(2 * std::min<std::uint32_t>(e.depth, 40), ' ') + e.text + "\n";
    if (trace) *trace += fmt::format("sample radiance {}\n", fmt_color(total));
  }
  return total;
}

namespace {
template <class K>
struct WhittedTile {
  // The loops read the camera's axes at run time (render/tile.hpp).
  static constexpr TileFn value = &render_tile<Kernel<K::bits & ~kCameraAxes>, WhittedIntegrator>;
};
}  // namespace

TileFn WhittedIntegrator::tile_kernel(unsigned bits) const {
  static constexpr auto kTable = kernel_table<WhittedTile>();
  return kTable[bits % kTable.size()];
}

std::string WhittedIntegrator::to_string() const {
  return fmt::format(
      "integrator {{ whitted point_lights {} area_lights {} max_depth {} min_weight {} "
      "fresnel {} branching {} termination {} }}",
      lights_.points.size(), lights_.areas.size(), max_depth_, min_weight_, ir::to_string(fresnel_),
      stochastic_branching_ ? "stochastic" : "split", roulette_ ? "roulette" : "cutoff");
}

}  // namespace snell::rt
