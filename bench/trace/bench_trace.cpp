// Traced rays per second: Snell's render() against a minimal raw-Embree driver that
// casts the same rays (camera ray, then one shadow ray to the point light per hit
// facing it) on the same geometry, and Snell with 1 vs 2 threads. The raw driver
// uses Embree's built-in sphere primitive (RTC_GEOMETRY_TYPE_SPHERE_POINT) where
// Snell uses user geometry with double-precision object-space intersection, so the
// "spheres" ratio also measures that choice; the "boxes" scene is triangles only in
// both, so its ratio is the integrator's own overhead.
//
// Usage: bench_trace [width height spp [rounds [scene [snell]]]]   (default 640 480 4 5, all)
// A sixth argument "snell" runs only Snell's 1-thread render (for profiling it).
// BENCH_GLASS_DEPTH=N sets the glass scene's max_depth (0: camera and shadow rays
// only, the "camera + shadow ray throughput" without the refraction tree).
#include <embree3/rtcore.h>
#include <fmt/format.h>
#include <pmmintrin.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>
#include <xmmintrin.h>

#include <algorithm>
#include <array>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "runtime/camera.hpp"
#include "runtime/embree_scene.hpp"
#include "runtime/render.hpp"

using namespace snell;

namespace {

struct BenchScene {
  std::string name;
  ir::Scene scene;
  bool raw_ok = false;  // diffuse + one point light only: the raw driver can replay it
};

ir::Shape make_box(ir::Vec3 lo, ir::Vec3 hi, std::uint32_t mat) {
  ir::Shape s;
  s.geom = ir::Box{lo, hi};
  s.material = mat;
  return s;
}
ir::Shape make_sphere(ir::Vec3 c, double r, std::uint32_t mat) {
  ir::Shape s;
  s.geom = ir::Sphere{c, r};
  s.material = mat;
  return s;
}

ir::Scene base(std::uint32_t w, std::uint32_t h, std::uint32_t spp) {
  ir::Scene s;
  s.files.push_back("bench");
  s.settings.width = w, s.settings.height = h, s.settings.samples = spp;
  s.settings.sampler = ir::SamplerKind::Independent;
  s.background = ir::Vec3{0.3, 0.4, 0.5};
  s.materials.push_back(ir::Material{});
  s.camera.location = {0, 6, -12};
  s.camera.look_at = {0, 0, 0};
  s.camera.fov = 55;
  return s;
}

std::vector<BenchScene> scenes(std::uint32_t w, std::uint32_t h, std::uint32_t spp) {
  std::vector<BenchScene> out;
  {  // 20×20 diffuse spheres on a box floor, one point light
    ir::Scene s = base(w, h, spp);
    s.shapes.push_back(make_box({-12, -1, -12}, {12, 0, 12}, 0));
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j)
        s.shapes.push_back(make_sphere({-9.5 + i, 0.4, -9.5 + j}, 0.4, 0));
    s.point_lights.push_back({{3, 8, -4}, {200, 200, 200}, {}});
    out.push_back({"spheres", s, true});
  }
  {  // 20×20 diffuse boxes (triangles only), one point light
    ir::Scene s = base(w, h, spp);
    s.shapes.push_back(make_box({-12, -1, -12}, {12, 0, 12}, 0));
    for (int i = 0; i < 20; ++i)
      for (int j = 0; j < 20; ++j)
        s.shapes.push_back(make_box({-9.8 + i, 0, -9.8 + j},
                                    {-9.2 + i, 0.3 + 0.05 * ((i * 7 + j * 3) % 11), -9.2 + j}, 0));
    s.point_lights.push_back({{3, 8, -4}, {200, 200, 200}, {}});
    out.push_back({"boxes", s, true});
  }
  {  // glass and glazed spheres, checker floor, an area light: the full ray tree
    ir::Scene s = base(w, h, spp);
    s.materials.push_back(ir::Diffuse{ir::Checker{{0.9, 0.9, 0.9}, {0.1, 0.1, 0.1}, 1}});
    s.materials.push_back(ir::Dielectric{1.5, {0.1, 0.2, 0.3}});
    s.materials.push_back(ir::Glazed{ir::Vec3(0.6, 0.1, 0.1), 1.5});
    s.shapes.push_back(make_box({-12, -1, -12}, {12, 0, 12}, 1));
    for (int i = 0; i < 5; ++i)
      for (int j = 0; j < 5; ++j)
        s.shapes.push_back(make_sphere({-6 + 3.0 * i, 1, -6 + 3.0 * j}, 1, (i + j) % 2 ? 2 : 3));
    ir::AreaLight l;
    l.corner = {-2, 8, -2};
    l.edge1 = {4, 0, 0};
    l.edge2 = {0, 0, 4};
    l.radiance = {10, 10, 10};
    l.samples_u = l.samples_v = 2;
    s.area_lights.push_back(l);
    if (const char* d = std::getenv("BENCH_GLASS_DEPTH")) s.settings.max_depth = std::atoi(d);
    out.push_back({"glass", s, false});
  }
  return out;
}

std::uint64_t total_rays(const rt::RenderStats& s) {
  return s.camera_rays + s.shadow_rays + s.reflection_rays + s.refraction_rays + s.glossy_rays;
}

struct Measure {
  std::uint64_t rays = 0;
  rt::RenderStats stats;
  double seconds = 0;
  double mrays() const { return seconds > 0 ? rays / seconds * 1e-6 : 0; }
};

Measure run_snell(const ir::Scene& s, int threads) {
  rt::RenderOptions o;
  o.threads = threads;
  rt::RenderResult r = rt::render(s, o);
  return {total_rays(r.stats), r.stats, r.stats.render_seconds};
}

// The raw driver: the same geometry (camera-relative, float), camera and rays.
Measure run_raw(const ir::Scene& s, int threads) {
  RTCDevice dev = rtcNewDevice(nullptr);
  RTCScene sc = rtcNewScene(dev);
  rtcSetSceneBuildQuality(sc, RTC_BUILD_QUALITY_HIGH);
  // The same scene flags as Snell's Embree scene (robust traversal), so the ratio
  // measures Snell's own overhead and its sphere representation, not the flag.
  rtcSetSceneFlags(sc, RTC_SCENE_FLAG_ROBUST);
  ir::Vec3 o = s.camera.location;
  std::vector<float> sph;
  std::vector<float> verts;
  std::vector<unsigned> idx;
  for (const ir::Shape& sh : s.shapes) {
    if (const ir::Sphere* sp = sh.as<ir::Sphere>()) {
      ir::Vec3 c = sh.world_from_object().point(sp->center) - o;
      sph.insert(sph.end(), {float(c.x), float(c.y), float(c.z), float(sp->radius)});
    } else if (const ir::Box* b = sh.as<ir::Box>()) {
      unsigned base = unsigned(verts.size() / 3);
      for (int i = 0; i < 8; ++i) {
        ir::Vec3 p(i & 1 ? b->max.x : b->min.x, i & 2 ? b->max.y : b->min.y,
                   i & 4 ? b->max.z : b->min.z);
        p = sh.world_from_object().point(p) - o;
        verts.insert(verts.end(), {float(p.x), float(p.y), float(p.z)});
      }
      const unsigned f[12][3] = {{0, 4, 6}, {0, 6, 2}, {1, 3, 7}, {1, 7, 5}, {0, 1, 5}, {0, 5, 4},
                                 {2, 6, 7}, {2, 7, 3}, {0, 2, 3}, {0, 3, 1}, {4, 5, 7}, {4, 7, 6}};
      for (auto& t : f) idx.insert(idx.end(), {base + t[0], base + t[1], base + t[2]});
    }
  }
  if (!sph.empty()) {
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_SPHERE_POINT);
    auto* b = static_cast<float*>(rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_VERTEX, 0,
                                                          RTC_FORMAT_FLOAT4, 16, sph.size() / 4));
    std::copy(sph.begin(), sph.end(), b);
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
  }
  if (!idx.empty()) {
    RTCGeometry g = rtcNewGeometry(dev, RTC_GEOMETRY_TYPE_TRIANGLE);
    auto* vb = static_cast<float*>(rtcSetNewGeometryBuffer(
        g, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3, 12, verts.size() / 3));
    std::copy(verts.begin(), verts.end(), vb);
    auto* ib = static_cast<unsigned*>(
        rtcSetNewGeometryBuffer(g, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 12, idx.size() / 3));
    std::copy(idx.begin(), idx.end(), ib);
    rtcCommitGeometry(g);
    rtcAttachGeometry(sc, g);
    rtcReleaseGeometry(g);
  }
  rtcCommitScene(sc);

  const ir::Camera& c = s.camera;
  ir::Vec3 fw = ir::normalize(c.look_at - c.location), rt_ = ir::normalize(ir::cross(fw, c.up)),
           up = ir::cross(rt_, fw);
  double tx = std::tan(c.fov * 0.5 * 3.14159265358979 / 180),
         ty = tx * s.settings.height / s.settings.width;
  ir::Vec3 lp = s.point_lights[0].position - o;
  std::uint32_t W = s.settings.width, H = s.settings.height, spp = s.settings.samples;
  std::atomic<std::uint64_t> rays{0};
  std::vector<float> img(std::size_t(W) * H * 3);
  auto t0 = std::chrono::steady_clock::now();
  tbb::task_arena arena(threads);
  arena.execute([&] {
    tbb::parallel_for(0u, H, [&](std::uint32_t y) {
      _MM_SET_FLUSH_ZERO_MODE(_MM_FLUSH_ZERO_ON);
      _MM_SET_DENORMALS_ZERO_MODE(_MM_DENORMALS_ZERO_ON);
      std::uint64_t n = 0;
      for (std::uint32_t x = 0; x < W; ++x) {
        float acc = 0;
        for (std::uint32_t k = 0; k < spp; ++k) {
          double jx = ((k * 0.618034) - std::floor(k * 0.618034)),
                 jy = ((k * 0.7548777) - std::floor(k * 0.7548777));
          double sx = (2 * (x + jx) / W - 1) * tx, sy = (1 - 2 * (y + jy) / H) * ty;
          ir::Vec3 d = ir::normalize(fw + rt_ * sx + up * sy);
          RTCIntersectContext ctx;
          rtcInitIntersectContext(&ctx);
          RTCRayHit rh{};
          rh.ray.dir_x = float(d.x), rh.ray.dir_y = float(d.y), rh.ray.dir_z = float(d.z);
          rh.ray.tfar = INFINITY;
          rh.ray.mask = ~0u;
          rh.hit.geomID = RTC_INVALID_GEOMETRY_ID;
          rtcIntersect1(sc, &ctx, &rh);
          ++n;
          if (rh.hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
          float px = rh.ray.tfar * rh.ray.dir_x, py = rh.ray.tfar * rh.ray.dir_y,
                pz = rh.ray.tfar * rh.ray.dir_z;
          float nx = rh.hit.Ng_x, ny = rh.hit.Ng_y, nz = rh.hit.Ng_z;
          float nl = std::sqrt(nx * nx + ny * ny + nz * nz);
          nx /= nl, ny /= nl, nz /= nl;
          if (nx * rh.ray.dir_x + ny * rh.ray.dir_y + nz * rh.ray.dir_z > 0)
            nx = -nx, ny = -ny, nz = -nz;
          float lx = float(lp.x) - px, ly = float(lp.y) - py, lz = float(lp.z) - pz;
          float cosl = nx * lx + ny * ly + nz * lz;
          if (cosl <= 0) continue;
          RTCRay sh{};
          float eps = 1e-4f * (1 + std::fabs(px) + std::fabs(py) + std::fabs(pz));
          sh.org_x = px + nx * eps, sh.org_y = py + ny * eps, sh.org_z = pz + nz * eps;
          sh.dir_x = lx, sh.dir_y = ly, sh.dir_z = lz;
          sh.tfar = 1;
          sh.mask = ~0u;
          rtcOccluded1(sc, &ctx, &sh);
          ++n;
          if (sh.tfar >= 0) acc += cosl / std::pow(lx * lx + ly * ly + lz * lz, 1.5f);
        }
        img[3 * (std::size_t(y) * W + x)] = acc / spp;
      }
      rays += n;
    });
  });
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  rtcReleaseScene(sc);
  rtcReleaseDevice(dev);
  return {rays.load(), {}, secs};
}

}  // namespace

// The scene query alone (rt::EmbreeScene, as the integrator calls it): every
// pixel's centre ray, in 4×4-pixel blocks (coherent), and from each hit one
// shadow ray to the first light, traced one at a time and as spans (packets of 16:
// rtcIntersect16 / rtcOccluded16), 1 thread, best of `rounds`. Returns
// {camera 1-ray, camera packets, shadow 1-ray, shadow packets} in Mrays/s.
std::array<double, 4> run_query(const ir::Scene& s, int rounds) {
  const std::uint32_t w = s.settings.width, h = s.settings.height;
  rt::EmbreeScene es(s, s.camera.location);
  rt::Camera cam(s.camera, w, h);
  std::vector<rt::Ray> cam_rays;
  for (std::uint32_t by = 0; by < h; by += 4)
    for (std::uint32_t bx = 0; bx < w; bx += 4)
      for (std::uint32_t y = by; y < std::min(h, by + 4); ++y)
        for (std::uint32_t x = bx; x < std::min(w, bx + 4); ++x)
          cam_rays.push_back(cam.generate(x + 0.5, y + 0.5));
  std::vector<rt::Hit> hits(cam_rays.size());
  std::vector<std::uint8_t> found(cam_rays.size()), blocked(cam_rays.size());
  es.intersect(cam_rays, hits, found);
  ir::Vec3 lp = s.point_lights.empty()
                    ? s.area_lights.front().corner +
                          0.5 * (s.area_lights.front().edge1 + s.area_lights.front().edge2)
                    : s.point_lights.front().position;
  lp = lp - s.camera.location;
  rt::Vec3f light = rt::to_float(lp.x, lp.y, lp.z);
  std::vector<rt::Ray> shadow;
  for (std::size_t i = 0; i < hits.size(); ++i)
    if (found[i]) {
      rt::Vec3f n = rt::dot(hits[i].ng, light - hits[i].p) > 0 ? hits[i].ng : -hits[i].ng;
      rt::Vec3f o = rt::spawn_origin(hits[i], n, 1);
      shadow.push_back({o, light - o, 1.0f, 0});
    }
  auto best = [&](auto&& f) {
    double t = 1e30;
    for (int r = 0; r < rounds; ++r) {
      auto t0 = std::chrono::steady_clock::now();
      f();
      t = std::min(t, std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    }
    return t;
  };
  std::uint64_t sink = 0;
  double c1 = best([&] {
    for (std::size_t i = 0; i < cam_rays.size(); ++i) sink += es.intersect(cam_rays[i], hits[i]);
  });
  double c16 = best([&] { es.intersect(cam_rays, hits, found); });
  double s1 = best([&] {
    for (const rt::Ray& r : shadow) sink += es.occluded(r);
  });
  double s16 = best([&] { es.occluded(shadow, std::span(blocked.data(), shadow.size())); });
  if (sink == 42) std::printf(" ");
  return {cam_rays.size() / c1 * 1e-6, cam_rays.size() / c16 * 1e-6, shadow.size() / s1 * 1e-6,
          shadow.size() / s16 * 1e-6};
}

int main(int argc, char** argv) {
  std::uint32_t w = 640, h = 480, spp = 4;
  int rounds = 5;
  std::string only;
  if (argc >= 4) w = std::atoi(argv[1]), h = std::atoi(argv[2]), spp = std::atoi(argv[3]);
  if (argc >= 5) rounds = std::max(1, std::atoi(argv[4]));
  if (argc >= 6) only = argv[5];
  const bool snell_only = argc >= 7 && std::string(argv[6]) == "snell";
  fmt::print("bench_trace: {}x{} at {} spp; Mrays/s, best of {} interleaved rounds\n", w, h, spp,
             rounds);
  fmt::print("{:<8} {:>12} {:>12} {:>10} {:>12} {:>12} {:>10} {:>10}\n", "scene", "snell 1T",
             "raw 1T", "snell/raw", "snell 2T", "raw 2T", "2T/1T", "rays");
  for (const BenchScene& b : scenes(w, h, spp)) {
    if (!only.empty() && b.name != only) continue;
    // Round r runs every configuration once, so slow drift of the shared machine's
    // load hits all of them alike; the best round of each is reported.
    Measure s1, s2, r1, r2;
    auto keep = [](Measure& best, Measure m) {
      if (best.seconds == 0 || m.seconds < best.seconds) best = m;
    };
    if (snell_only) {
      for (int r = 0; r < rounds; ++r) keep(s1, run_snell(b.scene, 1));
      const rt::RenderStats& st = s1.stats;
      fmt::print(
          "{:<8} {:>12.2f}  (camera {}, shadow {}, reflection {}, refraction {}, glossy {})\n",
          b.name, s1.mrays(), st.camera_rays, st.shadow_rays, st.reflection_rays,
          st.refraction_rays, st.glossy_rays);
      continue;
    }
    for (int r = 0; r < rounds; ++r) {
      keep(s1, run_snell(b.scene, 1));
      if (b.raw_ok) keep(r1, run_raw(b.scene, 1));
      keep(s2, run_snell(b.scene, 2));
      if (b.raw_ok) keep(r2, run_raw(b.scene, 2));
    }
    auto ratio = [](double a, double c) {
      return c > 0 ? fmt::format("{:.2f}", a / c) : std::string("-");
    };
    fmt::print("{:<8} {:>12.2f} {:>12} {:>10} {:>12.2f} {:>12} {:>10} {:>10}\n", b.name, s1.mrays(),
               b.raw_ok ? fmt::format("{:.2f}", r1.mrays()) : "-", ratio(s1.mrays(), r1.mrays()),
               s2.mrays(), b.raw_ok ? fmt::format("{:.2f}", r2.mrays()) : "-",
               ratio(s2.mrays(), s1.mrays()), s1.rays);
    if (b.raw_ok)
      fmt::print("{:<8} ray counts: snell {} raw {} (should agree to a few %)\n", "", s1.rays,
                 r1.rays);
    auto q = run_query(b.scene, rounds);
    fmt::print(
        "{:<8} query 1T: camera {:.2f} one at a time, {:.2f} in packets of 16 ({:.2f}x); shadow "
        "{:.2f}, {:.2f} ({:.2f}x)\n",
        "", q[0], q[1], q[1] / q[0], q[2], q[3], q[3] / q[2]);
  }
  return 0;
}
