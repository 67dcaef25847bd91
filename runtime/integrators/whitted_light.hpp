// The Whitted integrator's direct light (whitted.hpp): the shadow rays of lit
// nodes, cell by cell of each area light, as packets across lanes or across one
// point's cells; the §14 shadow rays through interiors; and the glossy-MIS light
// samples. Member templates of WhittedIntegrator, included only by whitted.cpp,
// where the kernels are instantiated.
#pragma once

#include <bit>
#include <cmath>
#include <cstdint>
#include <span>
#include <type_traits>

#include "runtime/integrators/whitted.hpp"
#include "runtime/shading/glossy_mis.hpp"
#include "runtime/uninit.hpp"

namespace snell::rt {

namespace whitted_detail {

// Child path keys: slot 1 = reflection, 2 = refraction. Sampler dimensions of a node
// are hashed from its key, so a dimension names the same decision in every sample
// of a pixel (what stratification across samples needs).
inline std::uint64_t child_key(std::uint64_t key, std::uint64_t slot) {
  return hash_combine(key, slot);
}
inline std::uint32_t node_dim(std::uint64_t key, std::uint64_t what) {
  return kDimFirstFree + std::uint32_t(hash_combine(key, what) & 0x7fffffffu);
}
// The name of area light li's grid cell (iu, iv) among a node's dimensions.
inline std::uint64_t light_cell(std::size_t li, std::uint32_t iu, std::uint32_t iv) {
  return (std::uint64_t(li + 1) << 40) | (iv << 20) | iu;
}

// The node's dimension of light li's c-th cell, row by row (nu cells to a row);
// `tag` is or-ed into the cell's name (glossy MIS's cells: the top bit).
inline std::uint32_t cell_dim(std::uint64_t key, std::size_t li, std::uint32_t nu, std::uint32_t c,
                              std::uint64_t tag = 0) {
  return node_dim(key, light_cell(li, c % nu, c / nu) | tag);
}

// One point's jitter of a light's cells, taken in cell order (row by row) and
// drawn kDrawLanes cells at a time (draw2_dims): what draw2 gives each cell.
// `dim_of(c)` is the node's dimension of the light's c-th cell.
struct CellJitter {
  alignas(64) float u[kDrawLanes], v[kDrawLanes];
  std::uint32_t first = 0, count = 0;  // the cells held: [first, first + count)
  template <class DimOf>
  Sample2 get(const SampleContext& sc, std::uint32_t c, std::uint32_t cells, DimOf dim_of) {
    if (c < first || c >= first + count) {
      std::uint32_t dims[kDrawLanes];
      first = c, count = std::min(kDrawLanes, cells - c);
      for (std::uint32_t j = 0; j < count; ++j) dims[j] = dim_of(c + j);
      draw2_dims(sc, dims, count, u, v);
    }
    return {u[c - first], v[c - first]};
  }
};

}  // namespace whitted_detail

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
        if (h.kind != Hit::Kind::Shape) return true;
        const std::uint32_t solid = interiors_.solid(h);
        if (interiors_.priority(solid) == 0) return true;
        Crossing c = interiors_.cross(cur, solid, dot(r.dir, h.ng) < 0);
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
  // One unblocked light sample of lane i (its value, geometry factor and `to`): its
  // share of E, and with highlights its f_spec · value · g (the same G as the
  // Lambertian sum: f · L_i · cosθ_i).
  auto add_sample = [&](std::uint32_t i, Color value, float g, Vec3f to,
                        Color tr) [[gnu::always_inline]] {
    (void)tr, (void)to;
    if constexpr (K::absorption)
      if (const ir::Vec3* a = q(i).medium) {
        const double dist = double(length(to));
        value = value * to_float(beer(a->x, dist), beer(a->y, dist), beer(a->z, dist));
      }
    if constexpr (K::interiors)
      e[i] += value * g * tr;
    else
      e[i] += value * g;
    if constexpr (K::finish) {
      if (q(i).highlight.on()) {
        float f = q(i).highlight.eval(q(i).wo, q(i).n, normalize(to));
        Color c = value * (g * f);
        if constexpr (K::interiors) c = c * tr;
        spec[i] += c;
      }
    }
  };
  auto add = [&](std::uint32_t i, Color tr)
                 [[gnu::always_inline]] { add_sample(i, ls[i].value, ls[i].g, ls[i].to, tr); };
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
  // Each lane's jitter in light cell `cell` (its node's dimension for the cell). A
  // packet's lanes find their keys of it together (cell_keys_lanes: the node's
  // dimension, then the pixel's key of it, what key2 finds one by one), then draw:
  // independent in the same hashes, sobol and stratified through sobol2_lanes /
  // stratified2_lanes when the lanes share a sample index (a packet's trees do).
  // The same numbers as draw2 lane by lane (the packet test).
  static_assert(SobolLanes::kLanes == StrataLanes::kLanes && kHashLanes == SobolLanes::kLanes);
  constexpr std::uint32_t kJitter = kLanes > SobolLanes::kLanes ? kLanes : SobolLanes::kLanes;
  // Zeroed: area_lanes reads all sixteen lanes (and masks the ones past `lanes`),
  // where the independent draw writes only the live ones.
  alignas(64) float ju[kJitter] = {}, jv[kJitter] = {};
  // The lanes' node keys, pixel keys and sample indices, the same for every cell
  // (lanes past `lanes` hash zeros, unused).
  static_assert(kLanes == 1 || kLanes <= kHashLanes);
  alignas(64) std::uint64_t node_keys[kHashLanes], pixels[kHashLanes], indices[kHashLanes];
  bool shared = true;  // every lane at one sample index
  if constexpr (kLanes > 1) {
    for (std::uint32_t i = 0; i < kHashLanes; ++i) {
      node_keys[i] = i < lanes ? q(i).key : 0;
      pixels[i] = i < lanes ? sc[i]->pixel : 0;
      indices[i] = i < lanes ? sc[i]->index : 0;
      shared = shared && (i >= lanes || indices[i] == indices[0]);
    }
  }
  // Lane i's jitter of cell `cell` into du[i], dv[i].
  auto draw_cell_to = [&](std::uint64_t cell, float* du, float* dv) {
    if constexpr (kLanes > 1) {
      alignas(64) std::uint64_t key[kHashLanes];
      const ir::SamplerKind kind = sc[0]->spec.kind;
      // node_dim's hash, dim_key's and for independent draws sample2's.
      cell_keys_lanes(node_keys, cell, pixels,
                      kind == ir::SamplerKind::Independent ? indices : nullptr, key);
      if (kind == ir::SamplerKind::Independent) {
        for (std::uint32_t i = 0; i < lanes; ++i) {
          Sample2 s = independent_sample(key[i]);
          du[i] = s.u, dv[i] = s.v;
        }
        return;
      }
      if (shared && kind == ir::SamplerKind::Sobol) {
        Uninit<SobolLanes, 1> keys;
        for (std::uint32_t i = 0; i < lanes; ++i)
          keys.v[0].set(i, dim_key_of_hash(sc[0]->spec, key[i]));
        for (std::uint32_t i = lanes; i % 4; ++i) keys.v[0].set(i, DimKey{});
        sobol2_lanes(keys.v[0], lanes, sc[0]->index, du, dv);
        return;
      }
      if (shared) {
        Uninit<StrataLanes, 1> keys;
        for (std::uint32_t i = 0; i < StrataLanes::kLanes; ++i)
          keys.v[0].key[i] = i < lanes ? key[i] : 0;
        stratified2_lanes(sc[0]->spec, keys.v[0], lanes, sc[0]->index, du, dv);
        return;
      }
    }
    for (std::uint32_t i = 0; i < lanes; ++i) {
      Sample2 s = draw2(*sc[i], whitted_detail::node_dim(q(i).key, cell));
      du[i] = s.u, dv[i] = s.v;
    }
  };
  auto draw_cell = [&](std::uint64_t cell) { draw_cell_to(cell, ju, jv); };
  // count (<= kMaxStrataDims) cells' jitter at once, into gu[j], gv[j]: the numbers
  // of draw_cell_to on each, with the stratified draws of a shared sample index
  // in one call (their permutations' walks interleave).
  [[maybe_unused]] auto draw_cells = [&](const std::uint64_t* cells, std::uint32_t count,
                                         float(*gu)[kJitter], float(*gv)[kJitter]) {
    if constexpr (kLanes > 1) {
      if (shared && sc[0]->spec.kind == ir::SamplerKind::Stratified) {
        Uninit<StrataLanes, kMaxStrataDims> keys;
        const StrataLanes* kp[kMaxStrataDims];
        float *up[kMaxStrataDims], *vp[kMaxStrataDims];
        for (std::uint32_t j = 0; j < count; ++j) {
          alignas(64) std::uint64_t key[kHashLanes];
          cell_keys_lanes(node_keys, cells[j], pixels, nullptr, key);
          for (std::uint32_t i = 0; i < StrataLanes::kLanes; ++i)
            keys.v[j].key[i] = i < lanes ? key[i] : 0;
          kp[j] = &keys.v[j], up[j] = gu[j], vp[j] = gv[j];
        }
        stratified2_lanes(sc[0]->spec, kp, count, lanes, sc[0]->index, up, vp);
        return;
      }
    }
    for (std::uint32_t j = 0; j < count; ++j) draw_cell_to(cells[j], gu[j], gv[j]);
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
    static_assert(kCells == kDrawLanes);  // a batch is one draw
    Uninit<LightSample, kCells> cs;
    Uninit<Ray, kCells> cr;
    std::uint8_t has[kCells], cblocked[kCells];
    for (std::size_t li = 0; li < lights_.areas.size(); ++li) {
      const AreaLightF& l = lights_.areas[li];
      if (l.dark()) continue;
      // Row by row, as the one-by-one loop goes; a batch may end inside a row.
      // Its jitter comes in one draw (CellJitter holds kCells cells).
      whitted_detail::CellJitter jitter;
      const std::uint32_t cells = l.nu * l.nv;
      const auto dim_of = [&](std::uint32_t c) {
        return whitted_detail::cell_dim(q(0).key, li, l.nu, c);
      };
      for (std::uint32_t c0 = 0; c0 < cells; c0 += kCells) {
        const std::uint32_t n = std::min(kCells, cells - c0);
        std::uint32_t m = 0;
        for (std::uint32_t j = 0; j < n; ++j) {
          const std::uint32_t c = c0 + j;
          const Sample2 s = jitter.get(*sc[0], c, cells, dim_of);
          has[j] = l.sample_li(q(0).p, q(0).o, q(0).n, q(0).time, c % l.nu, c / l.nu, s.u, s.v,
                               offset_scale_, cs.v[j]);
          if (has[j]) cr.v[m++] = cs.v[j].shadow;
        }
        stats.shadow_rays += m;
        if (m == 1)
          cblocked[0] = embree_.occluded(cr.v[0]);
        else if (m > 1)
          embree_.occluded(std::span<const Ray>(cr.v, m), std::span<std::uint8_t>(cblocked, m));
        for (std::uint32_t j = 0, k = 0; j < n; ++j)
          if (has[j] && !cblocked[k++] && std::isfinite(cs.v[j].g))
            add_sample(0, cs.v[j].value, cs.v[j].g, cs.v[j].to, Color(1));
      }
    }
    return;
  }
  // The lanes' points in SoA for area_lanes, once for every cell of every light.
  [[maybe_unused]] Uninit<PointLanes, 1> pts;
  [[maybe_unused]] bool pts_made = false;
  // The jitter of kMaxStrataDims cells at a time (area_lanes' path), zeroed once:
  // like ju and jv, the lanes past `lanes` are read, masked, and never written.
  [[maybe_unused]] alignas(64) float gu[kMaxStrataDims][kJitter] = {},
                                     gv[kMaxStrataDims][kJitter] = {};
  for (std::size_t li = 0; li < lights_.areas.size(); ++li) {
    const AreaLightF& l = lights_.areas[li];
    if (l.dark()) continue;
    if constexpr (kLanes > 1 && !K::interiors) {
      // All lanes' samples of a cell at once, and their shadow rays as one packet
      // in the same layout: area sampling only (area_lanes.hpp).
      if (area_lanes_ && !l.solid_angle) {
        PointLanes& pt = pts.v[0];
        if (!pts_made) {
          for (std::uint32_t i = 0; i < kLanes; ++i) {
            const DirectQuery& d = q(i < lanes ? i : 0);
            pt.px[i] = d.p.x, pt.py[i] = d.p.y, pt.pz[i] = d.p.z;
            pt.ox[i] = d.o.x, pt.oy[i] = d.o.y, pt.oz[i] = d.o.z;
            pt.nx[i] = d.n.x, pt.ny[i] = d.n.y, pt.nz[i] = d.n.z;
            pt.time[i] = d.time;
          }
          pts_made = true;
        }
        const std::uint32_t all = (1u << lanes) - 1;  // lanes <= 16
        Uninit<ShadowLanes, 1> sh_store;
        ShadowLanes& sh = sh_store.v[0];
        // The cells in row order, their jitter drawn kMaxStrataDims at a time.
        std::uint32_t iu = 0, iv = 0;
        while (iv < l.nv) {
          std::uint64_t cells[kMaxStrataDims];
          std::uint32_t cu[kMaxStrataDims], cv[kMaxStrataDims], count = 0;
          for (; count < kMaxStrataDims && iv < l.nv; ++count) {
            cells[count] = whitted_detail::light_cell(li, iu, iv);
            cu[count] = iu, cv[count] = iv;
            if (++iu == l.nu) iu = 0, ++iv;
          }
          draw_cells(cells, count, gu, gv);
          for (std::uint32_t j = 0; j < count; ++j) {
            const std::uint32_t lit_mask =
                area_lanes_({&l, cu[j], cv[j], offset_scale_}, pt, gu[j], gv[j], all, sh);
            stats.shadow_rays += std::uint64_t(std::popcount(lit_mask));
            if (!lit_mask) continue;
            const std::uint32_t shadowed = embree_.occluded(
                EmbreeScene::ShadowLanes16{pt.ox, pt.oy, pt.oz, sh.dx, sh.dy, sh.dz, pt.time},
                lit_mask);
            for (std::uint32_t bits = lit_mask & ~shadowed; bits; bits &= bits - 1) {
              const std::uint32_t i = std::uint32_t(std::countr_zero(bits));
              if (std::isfinite(sh.g[i]))
                add_sample(i, l.radiance, sh.g[i], Vec3f(sh.tx[i], sh.ty[i], sh.tz[i]), Color(1));
            }
          }
        }
        continue;
      }
    }
    // One point (through interiors): its cells' jitter drawn as lanes (CellJitter);
    // lanes: each cell's jitter of every lane.
    [[maybe_unused]] whitted_detail::CellJitter point;
    for (std::uint32_t iv = 0; iv < l.nv; ++iv)
      for (std::uint32_t iu = 0; iu < l.nu; ++iu) {
        if constexpr (kLanes == 1) {
          const Sample2 j = point.get(*sc[0], iv * l.nu + iu, l.nu * l.nv, [&](std::uint32_t c) {
            return whitted_detail::cell_dim(q(0).key, li, l.nu, c);
          });
          ju[0] = j.u, jv[0] = j.v;
        } else {
          draw_cell(whitted_detail::light_cell(li, iu, iv));
        }
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
    whitted_detail::CellJitter jitter;
    for (std::uint32_t iv = 0; iv < l.nv; ++iv)
      for (std::uint32_t iu = 0; iu < l.nu; ++iu) {
        const Sample2 j = jitter.get(sc, iv * l.nu + iu, l.nu * l.nv, [&](std::uint32_t c) {
          return whitted_detail::cell_dim(key, li, l.nu, c, std::uint64_t(1) << 63);
        });
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

}  // namespace snell::rt
