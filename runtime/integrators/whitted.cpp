#include "runtime/integrators/whitted.hpp"

#include <fmt/format.h>

#include <chrono>
#include <cmath>

#include "runtime/ir/bounds.hpp"
#include "runtime/shading/bump.hpp"
#include "runtime/shading/fresnel.hpp"
#include "runtime/shading/glossy_mis.hpp"
#include "runtime/shading/shading_normal.hpp"

namespace snell::rt {

namespace {

Color to_color(ir::Vec3 v) {
  return to_float(v.x, v.y, v.z);
}

// Child path keys: slot 1 = reflection, 2 = refraction. Sampler dimensions of a node
// are hashed from its key, so a dimension names the same decision in every sample
// of a pixel (what stratification across samples needs).
std::uint64_t child_key(std::uint64_t key, std::uint64_t slot) {
  return hash_combine(key, slot);
}
std::uint32_t node_dim(std::uint64_t key, std::uint64_t what) {
  return kDimFirstFree + std::uint32_t(hash_combine(key, what) & 0x7fffffffu);
}
// The name of area light li's grid cell (iu, iv) among a node's dimensions.
std::uint64_t light_cell(std::size_t li, std::uint32_t iu, std::uint32_t iv) {
  return (std::uint64_t(li + 1) << 40) | (iv << 20) | iu;
}

// An array of n trivially destructible T made without running T's default
// member initialisers (each element is assigned before it is read).
template <class T, std::uint32_t n>
union Uninit {
  static_assert(std::is_trivially_destructible_v<T>);
  Uninit() {}
  T v[n];
};

// The camera ray's path key (hash_combine(0x5eed, 0)), computed once.
const std::uint64_t kRootKey = hash_combine(0x5eed, 0);

std::string fmt_color(Color c) {
  return fmt::format("({:.6g}, {:.6g}, {:.6g})", c.x, c.y, c.z);
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

// Irradiance-like sum E so that a Lambertian surface of albedo ρ reflects ρ/π · E:
// point lights I·cosθ/d²; area lights a jittered nu×nv grid over the parallelogram,
// each sample L·cosθ_surf·cosθ_light·A/(d²·nu·nv) (area-to-solid-angle factor).
// Shadow rays leave from the offset hit point and end at the offset light sample, so
// the light's own surface never blocks them; everything else does (§7).
//
// §14: a shadow ray leaving a point inside prioritised solids passes through the
// surfaces a ray would pass through there (they are not there for any ray), is
// blocked by the first that counts, and carries the Beer factor of the medium it
// travels in. From air the first surface always counts, so there it is the plain
// occlusion query.
template <class K>
bool WhittedIntegrator::shadow_blocked(const Ray& ray, const Interior* in, Color& tr) const {
  if constexpr (K::interiors) {
    if (in && !in->empty()) {
      Ray r = ray;
      Interior cur = *in;
      for (int passes = 0; passes <= kMaxPassThroughs; ++passes) {
        Hit h;
        if (!embree_.intersect(r, h)) {
          if constexpr (K::absorption) {
            if (const ir::Vec3* a = interiors_.absorb(in->medium())) {
              double dist = double(length(r.dir)) * double(r.tmax);
              tr = tr * to_float(beer(a->x, dist), beer(a->y, dist), beer(a->z, dist));
            }
          }
          return false;
        }
        if (h.kind != Hit::Kind::Shape || interiors_.priority(h.index) == 0) return true;
        Crossing c = interiors_.cross(cur, h.index, dot(r.dir, h.ng) < 0);
        if (c.counts) return true;
        cur = c.after;
        r.tnear = std::nextafter(h.t, float(INFINITY));
      }
      return true;  // past kMaxPassThroughs: taken as blocked
    }
  }
  (void)in, (void)tr;
  return embree_.occluded(ray);
}

template <class K, std::uint32_t kLanes>
void WhittedIntegrator::direct_lanes(std::uint32_t lanes_in, const DirectQuery* const* qs,
                                     const SampleContext* const* sc, RenderStats& stats,
                                     const Interior* in, Color* e, Color* spec) const {
  static_assert(kLanes == 1 || !K::interiors, "shadow rays through interiors go one by one");
  // A constant for one lane, so the tree's own direct light has no lane loops.
  const std::uint32_t lanes = kLanes == 1 ? 1 : lanes_in;
  auto q = [qs](std::uint32_t i) -> const DirectQuery& { return *qs[i]; };
  // Left unset: every lane's sample is written before it is read (sample_li), and
  // default-made ones were a 1.6 KB memset per call.
  Uninit<LightSample, kLanes> ls_store;
  Uninit<Ray, kLanes> ray_store;
  LightSample* const ls = ls_store.v;
  Ray* const rays = ray_store.v;
  std::uint8_t lit[kLanes] = {}, blocked[kLanes];
  std::uint32_t slot[kLanes];  // lane i's shadow ray: rays[slot[i]]
  for (std::uint32_t i = 0; i < lanes; ++i) {
    e[i] = Color(0);
    if constexpr (K::finish) spec[i] = Color(0);
  }
  (void)spec, (void)in;
  // One unblocked light sample of lane i: its share of E, and with highlights its
  // f_spec · value · g (the same G as the Lambertian sum: f · L_i · cosθ_i).
  auto add_sample = [&](std::uint32_t i, const LightSample& s, Color tr) [[gnu::always_inline]] {
    (void)tr;
    if constexpr (K::interiors)
      e[i] += s.value * s.g * tr;
    else
      e[i] += s.value * s.g;
    if constexpr (K::finish) {
      if (q(i).highlight.on()) {
        float f = q(i).highlight.eval(q(i).wo, q(i).n, normalize(s.to));
        Color c = s.value * (s.g * f);
        if constexpr (K::interiors) c = c * tr;
        spec[i] += c;
      }
    }
  };
  auto add = [&](std::uint32_t i, Color tr) [[gnu::always_inline]] { add_sample(i, ls[i], tr); };
  // The lanes' samples of one light (lit[i]: lane i has one) traced and added.
  auto trace = [&]() [[gnu::always_inline]] {
    std::uint32_t m = 0;
    for (std::uint32_t i = 0; i < lanes; ++i)
      if (lit[i]) slot[i] = m, rays[m++] = ls[i].shadow;
    stats.shadow_rays += m;
    if constexpr (kLanes == 1) {
      Color tr(1);
      if (m && !shadow_blocked<K>(rays[0], in, tr) && std::isfinite(ls[0].g)) add(0, tr);
    } else {
      if (m == 0) return;
      embree_.occluded(std::span<const Ray>(rays, m), std::span<std::uint8_t>(blocked, m));
      for (std::uint32_t i = 0; i < lanes; ++i)
        if (lit[i] && !blocked[slot[i]] && std::isfinite(ls[i].g)) add(i, Color(1));
    }
  };
  // Each lane's jitter in light cell `cell` (its node's dimension for the cell):
  // sobol and stratified draws of a packet go through sobol2_lanes /
  // stratified2_lanes (all lanes at once, the same numbers as one by one), when
  // the lanes share a sample index and a path key (a packet's roots do).
  static_assert(SobolLanes::kLanes == StrataLanes::kLanes);
  constexpr std::uint32_t kJitter = kLanes > SobolLanes::kLanes ? kLanes : SobolLanes::kLanes;
  alignas(64) float ju[kJitter], jv[kJitter];
  auto draw_cell = [&](std::uint64_t cell) {
    if constexpr (kLanes > 1) {
      const ir::SamplerKind kind = sc[0]->spec.kind;
      bool shared = kind != ir::SamplerKind::Independent;
      for (std::uint32_t i = 1; i < lanes && shared; ++i)
        shared = sc[i]->index == sc[0]->index && q(i).key == q(0).key;
      if (shared && kind == ir::SamplerKind::Sobol) {
        const std::uint32_t dim = node_dim(q(0).key, cell);
        Uninit<SobolLanes, 1> keys;
        for (std::uint32_t i = 0; i < lanes; ++i) keys.v[0].set(i, key2(*sc[i], dim));
        for (std::uint32_t i = lanes; i % 4; ++i) keys.v[0].set(i, DimKey{});
        sobol2_lanes(keys.v[0], lanes, sc[0]->index, ju, jv);
        return;
      }
      if (shared) {
        const std::uint32_t dim = node_dim(q(0).key, cell);
        Uninit<StrataLanes, 1> keys;
        for (std::uint32_t i = 0; i < lanes; ++i) keys.v[0].set(i, key2(*sc[i], dim));
        for (std::uint32_t i = lanes; i < StrataLanes::kLanes; ++i) keys.v[0].key[i] = 0;
        stratified2_lanes(sc[0]->spec, keys.v[0], lanes, sc[0]->index, ju, jv);
        return;
      }
    }
    for (std::uint32_t i = 0; i < lanes; ++i) {
      Sample2 s = draw2(*sc[i], node_dim(q(i).key, cell));
      ju[i] = s.u, jv[i] = s.v;
    }
  };
  for (const PointLightF& l : lights_.points) {
    for (std::uint32_t i = 0; i < lanes; ++i)
      lit[i] = l.sample_li(q(i).p, q(i).o, q(i).n, q(i).time, ls[i]);
    trace();
  }
  if constexpr (!K::area) return;
  if constexpr (kLanes == 1 && !K::interiors) {
    // One shading point: its cells' shadow rays leave one origin towards one light,
    // so they are traced as one packet (up to kCells at a time), then added in
    // cell order, the order and the sums of tracing them one by one.
    constexpr std::uint32_t kCells = 16;
    Uninit<LightSample, kCells> cs;
    Uninit<Ray, kCells> cr;
    std::uint8_t has[kCells], cblocked[kCells];
    for (std::size_t li = 0; li < lights_.areas.size(); ++li) {
      const AreaLightF& l = lights_.areas[li];
      if (l.dark()) continue;
      // Row by row, as the one-by-one loop goes; a batch may end inside a row.
      for (std::uint32_t iu = 0, iv = 0; iv < l.nv;) {
        std::uint32_t n = 0, m = 0;
        for (; iv < l.nv && n < kCells; ++n) {
          draw_cell(light_cell(li, iu, iv));
          has[n] = l.sample_li(q(0).p, q(0).o, q(0).n, q(0).time, iu, iv, ju[0], jv[0],
                               offset_scale_, cs.v[n]);
          if (has[n]) cr.v[m++] = cs.v[n].shadow;
          if (++iu == l.nu) iu = 0, ++iv;
        }
        stats.shadow_rays += m;
        if (m == 1)
          cblocked[0] = embree_.occluded(cr.v[0]);
        else if (m > 1)
          embree_.occluded(std::span<const Ray>(cr.v, m), std::span<std::uint8_t>(cblocked, m));
        for (std::uint32_t j = 0, k = 0; j < n; ++j)
          if (has[j] && !cblocked[k++] && std::isfinite(cs.v[j].g))
            add_sample(0, cs.v[j], Color(1));
      }
    }
    return;
  }
  for (std::size_t li = 0; li < lights_.areas.size(); ++li) {
    const AreaLightF& l = lights_.areas[li];
    if (l.dark()) continue;
    for (std::uint32_t iv = 0; iv < l.nv; ++iv)
      for (std::uint32_t iu = 0; iu < l.nu; ++iu) {
        const std::uint64_t cell = light_cell(li, iu, iv);
        draw_cell(cell);
        for (std::uint32_t i = 0; i < lanes; ++i)
          lit[i] = l.sample_li(q(i).p, q(i).o, q(i).n, q(i).time, iu, iv, ju[i], jv[i],
                               offset_scale_, ls[i]);
        trace();
      }
  }
}

// The cells' jitter: the node's dimensions named by the cell with the top bit set,
// which no direct-light cell (< 2^63) uses; a glossy node is never lit, so its
// dimensions are its own either way. Instantiated only for kernels with area lights
// (li calls it under K::area).
template <class K>
Color WhittedIntegrator::glossy_lights(const GlossySquare& lobe, Vec3f wo, Vec3f p, Vec3f o,
                                       Vec3f nf, float time, std::uint64_t key,
                                       const SampleContext& sc, const Interior* in,
                                       std::uint64_t& n_rays) const {
  Color sum(0);
  const Vec3f r = incident(wo, nf).mirror();
  for (std::size_t li = 0; li < lights_.areas.size(); ++li) {
    const AreaLightF& l = lights_.areas[li];
    if (l.dark()) continue;
    const Vec3f half = (l.e1 + l.e2) * 0.5f;
    if (!lobe_meets_ball(r, nf, lobe.blur, l.corner + half - p,
                         0.5 * double(std::fmax(length(l.e1 + l.e2), length(l.e1 - l.e2)))))
      continue;
    for (std::uint32_t iv = 0; iv < l.nv; ++iv)
      for (std::uint32_t iu = 0; iu < l.nu; ++iu) {
        const std::uint64_t cell = light_cell(li, iu, iv);
        Sample2 j = draw2(sc, node_dim(key, cell | (std::uint64_t(1) << 63)));
        float u = (float(iu) + j.u) / float(l.nu), v = (float(iv) + j.v) / float(l.nv);
        LightSample ls;
        float cos_s, cos_l, d2;
        if (!l.shadow_to(l.corner + l.e1 * u + l.e2 * v, p, o, nf, time, offset_scale_, ls, cos_s,
                         cos_l, d2))
          continue;
        const double d = std::sqrt(double(d2));
        const Vec3f wi = ls.to * float(1 / d);
        const double x = mis_light_factor(
            lobe.pdf(wo, nf, wi), cell_density(double(d2), double(cos_l) / d, l.cell_area()));
        if (!(x > 0)) continue;  // the lobe cannot reach it: no shadow ray
        ++n_rays;
        Color tr(1);
        if (shadow_blocked<K>(ls.shadow, in, tr)) continue;
        sum += ls.value * tr * float(x);
      }
  }
  return sum;
}

template <class K>
Color WhittedIntegrator::lit_radiance(const DiffuseLobe& lobe, const DirectQuery& q, Color w,
                                      Color e, [[maybe_unused]] Color spec) {
  Color c = lobe.reflect(w, e);
  // §16: the highlight's radiance f_spec · L_i · cosθ_i, weighted like the diffuse
  // light; never carried by a branch.
  if constexpr (K::finish)
    if (q.highlight.on()) c += w * spec;
  (void)q;
  return c;
}

// Lanes whose tree did not defer are skipped; the others' queries go to
// direct_lanes together, in lane order.
template <class K>
void WhittedIntegrator::finish_deferred_in(std::uint32_t n, Deferred* defer,
                                           const SampleContext* sc, RenderStats& stats,
                                           Color* col) const {
  if constexpr (K::interiors) {
    (void)n, (void)defer, (void)sc, (void)stats, (void)col;
  } else {
    const DirectQuery* q[kMaxDeferred];
    const SampleContext* qsc[kMaxDeferred];
    std::uint32_t lane[kMaxDeferred], m = 0;
    for (std::uint32_t i = 0; i < n; ++i)
      if (defer[i].on) q[m] = &defer[i].q, qsc[m] = &sc[i], lane[m++] = i;
    if (m == 0) return;
    Color e[kMaxDeferred], spec[kMaxDeferred];
    direct_lanes<K, kMaxDeferred>(m, q, qsc, stats, nullptr, e, spec);
    for (std::uint32_t j = 0; j < m; ++j) {
      Deferred& d = defer[lane[j]];
      col[lane[j]] += lit_radiance<K>(d.lobe, d.q, d.w, e[j], spec[j]);
      d.on = false;
    }
  }
}

template <class K, class P>
Color WhittedIntegrator::li(const Ray& camera_ray, const SampleContext& sc, Scratch& scratch,
                            P& probe, const PrimaryHit* primary, Deferred* defer) const {
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
  node.ray = camera_ray;
  // The next node's direction, read from where the node is copied from: loaded
  // back from the fresh copy it straddled two of the copy's 16-byte stores, and
  // the failed store forwarding was a quarter of this function's time.
  Vec3f d_next = camera_ray.dir;
  node.start = camera_ray.org;
  node.key = kRootKey;
  if constexpr (K::interiors) node.interior = interiors_.camera();
  const auto& mats = scene_.materials;
  // A node's children are collected here; kids[0] (the reflection) is traced next.
  // In the thread's scratch, made once per thread: spawn() sets every field, and
  // default nodes and queries made per tree were a 200-byte memset per sample.
  N* const kids = scratch.template kids<K::interiors>();
  Deferred& own_light = scratch.light;  // a lit node's light when it is not deferred

  for (;;) {
    double t_node = cost ? CostClock::now_ns() : 0, nested = 0;
    // Direct light is timed as shadow cost and taken out of the node's own time.
    const Interior* in_here = nullptr;  // the interior at the shading point (shadow rays)
    if constexpr (K::interiors) in_here = &node.interior;
    auto direct_timed = [&](const DirectQuery& q, Color& spec) {
      Color e;
      const SampleContext* scp = &sc;
      const DirectQuery* qp = &q;
      double t0 = cost ? CostClock::now_ns() : 0;
      direct_lanes<K, 1>(1, &qp, &scp, stats, in_here, &e, &spec);
      if (cost) {
        double dt = cost->since(t0);
        cost->ns[kCostShadow] += dt;
        nested += dt + cost->overhead_ns;
      }
      return e;
    };
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
    Color contrib(0);
    std::string desc;
    // The root works on the packet's hit in place; every other node on a fresh
    // one in the scratch, made only then (a default Hit is ~90 bytes of stores, and
    // GCC zeroed even an empty std::optional<Hit> here on every node).
    Hit& hit = primary ? *primary->hit : (scratch.hit = Hit{});
    const Vec3f d = d_next;
    int nkids = 0;
    Vec3f p_surface;
    // A lit node's direct light, gathered once its children are known: the root
    // of a packet's tree with none leaves it to the pixel loop (defer). Written in
    // place, field by field: building it and copying it over stalled on store
    // forwarding (a tenth of this function's time).
    bool lit = false;
    Deferred& dl = defer ? *defer : own_light;
    // The interior a refracted child starts with: the far side of a prioritised
    // surface that counts, else the node's own (plain dielectrics are not tracked).
    [[maybe_unused]] std::conditional_t<K::interiors, Interior, NoInterior> far_side{};
    if constexpr (K::interiors) far_side = node.interior;
    auto spawn = [&](RayKind kind, Vec3f org, Vec3f dir, Color w, std::uint64_t slot,
                     float tnear = 0) {
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
      if constexpr (K::interiors)
        k.interior = kind == RayKind::Refraction ? far_side : node.interior;
    };

    bool found;
    if (primary) {  // the root, traced in the pixel loop's packet
      found = primary->found;
      primary = nullptr;
    } else {
      found = embree_.intersect(node.ray, hit);
    }
    // §14: surfaces of prioritised solids that do not count are passed straight
    // through: the same ray goes on, with no depth and no weight change, updating
    // its interior. `crossing` is the surface that counts, when the hit is one.
    [[maybe_unused]] bool lost = false, prioritised = false;
    [[maybe_unused]] int passes = 0;
    [[maybe_unused]] std::conditional_t<K::interiors, Crossing, NoInterior> crossing{};
    if constexpr (K::interiors) {
      while (found && hit.kind == Hit::Kind::Shape && interiors_.priority(hit.index) > 0) {
        crossing = interiors_.cross(node.interior, hit.index, dot(d, hit.ng) < 0);
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
    // The Beer factor of the medium the ray travels in, over `dist` (interiors:
    // rays that escape or reach a light inside an absorbing solid).
    [[maybe_unused]] auto medium_beer = [&](double dist) {
      Color f(1);
      if constexpr (K::interiors && K::absorption)
        if (const ir::Vec3* a = interiors_.absorb(node.interior.medium()))
          f = to_float(beer(a->x, dist), beer(a->y, dist), beer(a->z, dist));
      return f;
    };
    if (K::interiors && lost) {
      if (trace) desc = fmt::format("lost: passed through {} surfaces", passes - 1);
    } else if (!found) {
      contrib = node.weight * (background_pattern_ ? sky(d, node.ray.time, stats) : background_);
      if constexpr (K::interiors && K::absorption)
        if (!node.interior.empty()) contrib = contrib * medium_beer(INFINITY);
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
      if constexpr (K::interiors && K::absorption)
        if (!node.interior.empty()) {
          Vec3f path = (node.ray.org - node.start) + d * hit.t;
          contrib = contrib * medium_beer(double(length(path)));
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
        desc += fmt::format(
            " shading normal ({:.4g}, {:.4g}, {:.4g}) geometric ({:.4g}, {:.4g}, {:.4g})",
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
      // (§8), or with interiors the medium its interior names (§14).
      const ir::Vec3* a = K::absorption && !entering ? medium_absorb(mat) : nullptr;
      if constexpr (K::interiors && K::absorption) {
        if (prioritised)
          a = interiors_.absorb(crossing.from);
        else if (!a)
          a = interiors_.absorb(node.interior.medium());
      }
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
          dl.q.time = node.ray.time, dl.q.key = node.key;
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
              spawn(b.kind, o_out, frame.leave(b.wi, true), w * b.weight, b.slot);
              break;
            case Branch::From::Inside:
              spawn(b.kind, spawn_origin(hit, -nf, offset_scale_), frame.leave(b.wi, false),
                    w * b.weight, b.slot);
              break;
            case Branch::From::SameRay:
              // Still a refraction for max_depth and min_weight as §6 defines them.
              spawn(b.kind, node.ray.org, d, w * b.weight, b.slot,
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
              Color ll = glossy_lights<K>(lobe, -d, p, o_out, nf, node.ray.time, node.key, sc,
                                          in_mis, stats.shadow_rays);
              contrib += k.weight * ll;
              if (trace)
                desc += fmt::format(" glossy mis: lobe pdf {:.6g}, {} light sample(s)", p_b,
                                    stats.shadow_rays - n0);
            }
          }
        }
      }
    }
    if (lit) {
      if (defer && nkids == 0 && !K::interiors) {
        defer->on = true;
      } else {
        Color spec(0);
        Color e = direct_timed(dl.q, spec);
        contrib = lit_radiance<K>(dl.lobe, dl.q, dl.w, e, spec);
      }
    }
    defer = nullptr;  // only the root defers
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
    if (nkids > 0) {
      for (int i = nkids - 1; i >= 1; --i) stack.push_back(kids[i]);
      d_next = kids[0].ray.dir;
      node = kids[0];
    } else if (!stack.empty()) {
      d_next = stack.back().ray.dir;
      node = stack.back();
      stack.pop_back();
    } else {
      break;
    }
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
  static constexpr TileFn value = &render_tile<K, WhittedIntegrator>;
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
