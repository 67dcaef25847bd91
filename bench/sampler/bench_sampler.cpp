// bench_sampler: the cost of one draw of each sampler kind, in ns, and its ratio to
// the independent sampler's, measured in one run (interleaved rounds, median of
// them, 1 thread). The draws follow the renderer's pattern: per pixel, per sample
// index, the fixed dimensions (pixel 2-D, lens 2-D, time 1-D) and a run of hashed
// per-node dimensions (an area-light grid's cells, 2-D). The checksum of every
// value drawn is printed too: two builds that print the same checksums draw the
// same numbers.
//
//   bench_sampler [--rounds N] [--pixels P]
#include <algorithm>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "runtime/sampler.hpp"

using namespace snell;
using namespace snell::rt;

namespace {

struct Result {
  double ns_per_draw = 0;
  std::uint64_t checksum = 0;
};

std::uint64_t bits(float f) {
  std::uint32_t b;
  std::memcpy(&b, &f, 4);
  return b;
}

// One round: `pixels` pixels of `spp` samples, each with 2 + 1 fixed draws and
// `node_dims` per-node 2-D draws. Keyed: the draws as the render loop makes them,
// the fixed dimensions' keys once per pixel (dim_key), the per-node ones through
// the pixel's DimCache; its checksum, and Point's, must equal the plain round's (the
// keys and lanes change the cost, never the numbers).
// Point: the keyed draws, with the per-node dimensions of a sample drawn as SIMD
// lanes, one lane per dimension (what one shading point's light cells do,
// draw2_dims in render/tile.hpp); independent ones stay lane by lane.
enum class Mode { Plain, Keyed, Point };
template <Mode mode>
Result round(const SamplerSpec& spec, std::uint32_t spp, std::uint32_t pixels,
             std::uint32_t node_dims) {
  constexpr bool keyed = mode != Mode::Plain;
  constexpr std::uint32_t L = StrataLanes::kLanes;
  const bool point = mode == Mode::Point && spec.kind != ir::SamplerKind::Independent;
  auto t0 = std::chrono::steady_clock::now();
  std::uint64_t sum = 0, draws = 0;
  for (std::uint32_t p = 0; p < pixels; ++p) {
    std::uint32_t px = p % 640, py = p / 640;
    std::uint64_t pixel = pixel_hash(spec, px, py);
    const DimKey film = dim_key(spec, pixel, kDimPixel), lens = dim_key(spec, pixel, kDimLens);
    const DimKey time = dim_key1(spec, pixel, kDimTime);
    DimCache cache;
    for (std::uint32_t s = 0; s < spp; ++s) {
      Sample2 a = keyed ? sample2(spec, film, s) : sample2(spec, pixel, s, kDimPixel);
      Sample2 b = keyed ? sample2(spec, lens, s) : sample2(spec, pixel, s, kDimLens);
      float t = keyed ? sample1(spec, time, s) : sample1(spec, pixel, s, kDimTime);
      sum = sum * 31 + bits(a.u) + 3 * bits(a.v) + 5 * bits(b.u) + 7 * bits(b.v) + 11 * bits(t);
      if (point) {
        for (std::uint32_t d0 = 0; d0 < node_dims; d0 += L) {
          const std::uint32_t n = std::min(L, node_dims - d0);
          alignas(64) float u[L], v[L];
          if (spec.kind == ir::SamplerKind::Stratified) {
            StrataLanes k;
            for (std::uint32_t d = 0; d < n; ++d)
              k.set(d, cache.get<false>(spec, pixel, 0x9e3779b9u * (d0 + d + 17)));
            stratified2_lanes(spec, k, n, s, u, v);
          } else {
            SobolLanes k;
            for (std::uint32_t d = 0; d < n; ++d)
              k.set(d, cache.get<false>(spec, pixel, 0x9e3779b9u * (d0 + d + 17)));
            sobol2_lanes(k, n, s, u, v);
          }
          for (std::uint32_t d = 0; d < n; ++d) sum = sum * 31 + bits(u[d]) + 3 * bits(v[d]);
        }
        draws += 3 + node_dims;
        continue;
      }
      for (std::uint32_t d = 0; d < node_dims; ++d) {
        std::uint32_t dim = 0x9e3779b9u * (d + 17);
        Sample2 c = keyed ? sample2(spec, cache.get<false>(spec, pixel, dim), s)
                          : sample2(spec, pixel, s, dim);
        sum = sum * 31 + bits(c.u) + 3 * bits(c.v);
      }
      draws += 3 + node_dims;
    }
  }
  double ns =
      std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
  return {ns / double(draws), sum};
}

// The renderer's other pattern: 16 pixels side by side (a packet) drawing one
// sample index together. Sobol draws go through sobol2_lanes on `path`, stratified
// ones through stratified2_lanes; independent ones (and any kind on path "scalar")
// draw lane by lane with their keys, as the render loop does for them. The
// same pixels, samples and dimensions as round(), in another order, so the
// checksum is order-free (a sum of a bijection of each draw).
Result lanes_round(const SamplerSpec& spec, std::uint32_t spp, std::uint32_t pixels,
                   std::uint32_t node_dims, const std::string& path) {
  constexpr std::uint32_t L = SobolLanes::kLanes;
  constexpr std::uint64_t kOdd = 0x9e3779b97f4a7c15ull;
  // The path is looked up once, as the renderer picks it once at start-up.
  const Sobol2LanesFn sobol_fn =
      spec.kind == ir::SamplerKind::Sobol && path != "scalar" ? sobol2_lanes_path(path) : nullptr;
  const StratifiedLanesFn strata_fn = spec.kind == ir::SamplerKind::Stratified && path != "scalar"
                                          ? stratified_lanes_path(path)
                                          : nullptr;
  auto t0 = std::chrono::steady_clock::now();
  std::uint64_t sum = 0, draws = 0;
  std::vector<std::uint32_t> dims(node_dims);
  for (std::uint32_t d = 0; d < node_dims; ++d) dims[d] = 0x9e3779b9u * (d + 17);
  std::vector<SobolLanes> node_lanes(node_dims);
  std::vector<StrataLanes> node_strata(node_dims);
  std::vector<DimKey> node_keys(std::size_t(node_dims) * L);
  for (std::uint32_t p0 = 0; p0 < pixels; p0 += L) {
    const std::uint32_t n = std::min(L, pixels - p0);
    SobolLanes film, lens;
    StrataLanes film_s, lens_s;
    DimKey film_k[L], lens_k[L];
    for (std::uint32_t l = 0; l < n; ++l) {
      std::uint32_t p = p0 + l, px = p % 640, py = p / 640;
      std::uint64_t pixel = pixel_hash(spec, px, py);
      film_k[l] = dim_key(spec, pixel, kDimPixel), lens_k[l] = dim_key(spec, pixel, kDimLens);
      film.set(l, film_k[l]), lens.set(l, lens_k[l]);
      film_s.set(l, film_k[l]), lens_s.set(l, lens_k[l]);
      for (std::uint32_t d = 0; d < node_dims; ++d) {
        node_keys[d * L + l] = dim_key(spec, pixel, dims[d]);
        node_lanes[d].set(l, node_keys[d * L + l]);
        node_strata[d].set(l, node_keys[d * L + l]);
      }
    }
    alignas(64) float u[L], v[L];
    auto draw = [&](const SobolLanes& lanes, const DimKey* keys, std::uint32_t s) {
      if (sobol_fn) {
        sobol_fn(lanes, n, s, u, v);
      } else {
        for (std::uint32_t l = 0; l < n; ++l) {
          Sample2 c = sample2(spec, keys[l], s);
          u[l] = c.u, v[l] = c.v;
        }
      }
      // Times an odd constant: a bijection of each draw, so unequal numbers give
      // unequal sums, at the cost of one product (a hash here would cost as much as
      // an independent draw and hide the samplers' differences).
      for (std::uint32_t l = 0; l < n; ++l) sum += (bits(u[l]) << 32 | bits(v[l])) * kOdd;
      draws += n;
    };
    // Stratified draws go as the renderer groups them: the film and lens
    // dimensions in one call (camera_rays), a light's cells kMaxStrataDims at a
    // time (whitted_light.hpp); the other kinds one dimension a call.
    auto draw_group = [&](const StrataLanes* const* k, std::uint32_t count, std::uint32_t s) {
      alignas(64) float gu[kMaxStrataDims][L], gv[kMaxStrataDims][L];
      float *up[kMaxStrataDims], *vp[kMaxStrataDims];
      for (std::uint32_t c = 0; c < count; ++c) up[c] = gu[c], vp[c] = gv[c];
      strata_fn(spec, k, count, n, s, up, vp);
      for (std::uint32_t c = 0; c < count; ++c)
        for (std::uint32_t l = 0; l < n; ++l) sum += (bits(gu[c][l]) << 32 | bits(gv[c][l])) * kOdd;
      draws += count * n;
    };
    for (std::uint32_t s = 0; s < spp; ++s) {
      if (strata_fn) {
        const StrataLanes* camera[2] = {&film_s, &lens_s};
        draw_group(camera, 2, s);
        for (std::uint32_t d = 0; d < node_dims; d += kMaxStrataDims) {
          const StrataLanes* k[kMaxStrataDims];
          const std::uint32_t count = std::min(kMaxStrataDims, node_dims - d);
          for (std::uint32_t c = 0; c < count; ++c) k[c] = &node_strata[d + c];
          draw_group(k, count, s);
        }
        continue;
      }
      draw(film, film_k, s);
      draw(lens, lens_k, s);
      for (std::uint32_t d = 0; d < node_dims; ++d) draw(node_lanes[d], &node_keys[d * L], s);
    }
  }
  double ns =
      std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count();
  return {ns / double(draws), sum};
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char** argv) {
  int rounds = 7;
  std::uint32_t pixels = 4096;
  for (int i = 1; i < argc; ++i) {
    if (!std::strcmp(argv[i], "--rounds") && i + 1 < argc)
      rounds = std::max(1, std::atoi(argv[++i]));
    else if (!std::strcmp(argv[i], "--pixels") && i + 1 < argc)
      pixels = std::uint32_t(std::max(1, std::atoi(argv[++i])));
    else {
      std::fprintf(stderr, "usage: bench_sampler [--rounds N] [--pixels P]\n");
      return 2;
    }
  }
  const ir::SamplerKind kinds[] = {ir::SamplerKind::Independent, ir::SamplerKind::Stratified,
                                   ir::SamplerKind::Sobol};
  std::printf("%-6s %-11s %10s %9s %12s %9s %12s %9s  %s\n", "spp", "sampler", "ns/draw", "÷indep",
              "keyed ns", "÷indep", "point ns", "÷indep", "checksum");
  for (std::uint32_t spp : {1u, 4u, 16u, 64u, 100u}) {
    // Fewer pixels at high counts, so every row draws about as many numbers.
    std::uint32_t px = std::max<std::uint32_t>(1, pixels * 16 / spp);
    std::vector<double> ns[3], keyed[3], point[3];
    std::uint64_t sums[3] = {}, keyed_sums[3] = {}, point_sums[3] = {};
    for (int r = 0; r < rounds; ++r)
      for (int k = 0; k < 3; ++k) {
        Result res = round<Mode::Plain>(SamplerSpec{kinds[k], 7, spp}, spp, px, 16);
        ns[k].push_back(res.ns_per_draw);
        sums[k] = res.checksum;
        res = round<Mode::Keyed>(SamplerSpec{kinds[k], 7, spp}, spp, px, 16);
        keyed[k].push_back(res.ns_per_draw);
        keyed_sums[k] = res.checksum;
        res = round<Mode::Point>(SamplerSpec{kinds[k], 7, spp}, spp, px, 16);
        point[k].push_back(res.ns_per_draw);
        point_sums[k] = res.checksum;
      }
    double base = median(ns[0]), keyed_base = median(keyed[0]), point_base = median(point[0]);
    for (int k = 0; k < 3; ++k) {
      std::printf("%-6u %-11s %10.2f %9.2f %12.2f %9.2f %12.2f %9.2f  %016llx\n", spp,
                  std::string(ir::to_string(kinds[k])).c_str(), median(ns[k]), median(ns[k]) / base,
                  median(keyed[k]), median(keyed[k]) / keyed_base, median(point[k]),
                  median(point[k]) / point_base, (unsigned long long)sums[k]);
      if (keyed_sums[k] != sums[k] || point_sums[k] != sums[k]) {
        std::fprintf(stderr, "bench_sampler: keyed draws differ from the plain ones\n");
        return 1;
      }
    }
  }
  // Packets: 2-D draws only (film, lens, 16 node dimensions), 16 pixels at once.
  std::vector<std::string> paths = {"scalar"};
  for (const std::string& p : sobol2_lanes_paths()) paths.push_back(p);
  std::vector<std::string> strata_paths = {"scalar"};
  for (const std::string& p : stratified_lanes_paths()) strata_paths.push_back(p);
  std::printf(
      "\npackets of %u pixels, 2-D draws; by SIMD path (sobol2_lanes: %s, stratified2_lanes: "
      "%s)\n",
      SobolLanes::kLanes, paths[1].c_str(), strata_paths[1].c_str());
  std::printf("%-6s %-20s %10s %9s  %s\n", "spp", "sampler", "ns/draw", "÷indep", "checksum");
  for (std::uint32_t spp : {4u, 9u, 16u, 36u, 64u, 100u}) {
    std::uint32_t px = std::max<std::uint32_t>(16, pixels * 16 / spp);
    struct Row {
      ir::SamplerKind kind;
      std::string path, name;
      std::vector<double> ns;
      std::uint64_t sum = 0;
    };
    std::vector<Row> rows = {{kinds[0], "scalar", "independent", {}}};
    for (const std::string& p : strata_paths) rows.push_back({kinds[1], p, "stratified " + p, {}});
    for (const std::string& p : paths) rows.push_back({kinds[2], p, "sobol " + p, {}});
    for (int r = 0; r < rounds; ++r)
      for (Row& row : rows) {
        Result res = lanes_round(SamplerSpec{row.kind, 7, spp}, spp, px, 16, row.path);
        row.ns.push_back(res.ns_per_draw);
        row.sum = res.checksum;
      }
    double base = median(rows[0].ns);
    for (const Row& row : rows)
      std::printf("%-6u %-20s %10.2f %9.2f  %016llx\n", spp, row.name.c_str(), median(row.ns),
                  median(row.ns) / base, (unsigned long long)row.sum);
    // Every path of a kind draws what its scalar row draws.
    for (const Row& row : rows)
      for (const Row& scalar : rows)
        if (scalar.kind == row.kind && scalar.path == "scalar" && row.sum != scalar.sum) {
          std::fprintf(stderr, "bench_sampler: %s draws other numbers than scalar\n",
                       row.name.c_str());
          return 1;
        }
  }
  return 0;
}
