// bench_csg: what §12's CSG and §13's instances cost.
//
// CSG: each pair is one picture area covered two ways — by a CSG object and by
// the plain shape it most resembles (a lens against a sphere, a box with a bite
// against the box, a mesh cube with a bite against the box with one) — rendered
// in one run, interleaved, 1 thread, median of repeats; ns per camera sample and
// the ratio.
//
// Quadrics against triangles: twelve spheres and twelve CSG lenses, analytic and
// tessellated (OBJ meshes written here), ns per camera sample and the ratio.
//
// Holes: a slab drilled with 10 to 10 000 holes (one difference), ns per sample.
//
// Instances: N objects of one mesh value (`object { m ... }`, one prototype, Embree
// instancing) against the same N written as separate meshes (each object's
// triangles copied into the scene's BVH): the resident memory the built scene
// adds and the time to build and render it; then many instances alone.
//
//   bench_csg [--res W] [--spp N] [--repeats N] [--tris N] [--copies N] [--instances N]
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "bench/common/bench_files.hpp"
#include "compiler/compile.hpp"
#include "runtime/render.hpp"

using namespace snell;
using bench::rss_mib;
using bench::write_sphere_obj;
namespace fs = std::filesystem;

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// The lens (the intersection of the spheres of radius 0.6 about (0, 0, ±0.3)) as
// two tessellated caps meeting at the rim: `n` rings of `4n` segments each.
std::string write_lens_obj(const fs::path& dir, int n) {
  std::string path = (dir / "lens.obj").string();
  std::ofstream f(path);
  const double pi = 3.14159265358979323846, tmax = pi / 3;  // cos 60° = 0.3 / 0.6
  int m = 4 * n;
  // Vertices: the two poles, then per cap rings 1..n (ring n is the shared rim).
  f << "v 0 0 0.3\nv 0 0 -0.3\n";
  for (int cap = 0; cap < 2; ++cap)
    for (int i = 1; i <= n; ++i)
      for (int j = 0; j < m; ++j) {
        double th = tmax * i / n, ph = 2 * pi * j / m, z = 0.6 * std::cos(th) - 0.3;
        f << "v " << 0.6 * std::sin(th) * std::cos(ph) << " " << 0.6 * std::sin(th) * std::sin(ph)
          << " " << (cap == 0 ? z : -z) << "\n";
      }
  auto v = [&](int cap, int i, int j) {
    if (i == n && cap == 1) cap = 0;  // the rim is one ring
    return 3 + cap * n * m + (i - 1) * m + (j % m);
  };
  for (int cap = 0; cap < 2; ++cap) {
    bool flip = cap == 1;
    auto tri = [&](int a, int b, int c) {
      f << "f " << a << " " << (flip ? c : b) << " " << (flip ? b : c) << "\n";
    };
    for (int j = 0; j < m; ++j) tri(1 + cap, v(cap, 1, j), v(cap, 1, j + 1));
    for (int i = 1; i < n; ++i)
      for (int j = 0; j < m; ++j) {
        tri(v(cap, i, j), v(cap, i + 1, j), v(cap, i + 1, j + 1));
        tri(v(cap, i, j), v(cap, i + 1, j + 1), v(cap, i, j + 1));
      }
  }
  return path;
}

const char* kCommon = R"(
camera { location <0, 1.5, -5> look_at <0, 0.5, 0> fov 50 }
background <0.6, 0.7, 0.9>
point_light { position <-2, 5, -3> intensity 40 }
plane { normal <0, 1, 0> distance -0.5 material diffuse 0.7 }
)";

ir::Scene compile_scene(const std::string& body, std::uint32_t res, std::uint32_t spp) {
  std::unique_ptr<compile::Compilation> c;
  compile::run_with_large_stack(
      [&] { c = compile::compile_source("bench.scn", std::string(kCommon) + body, {}); });
  if (!c || c->status != compile::CompileStatus::Ok) {
    std::fprintf(stderr, "bench scene does not compile:\n%s\n", body.c_str());
    if (c) c->diags.print(std::cerr, false);
    std::exit(1);
  }
  ir::Scene s = c->scene;
  s.settings.width = res;
  s.settings.height = res * 3 / 4;
  s.settings.samples = spp;
  return s;
}

// ns per camera sample of scenes a and b, rendered interleaved, 1 thread, median.
std::pair<double, double> ns_per_sample(const ir::Scene& a, const ir::Scene& b, int repeats) {
  rt::RenderOptions o;
  o.threads = 1;
  std::vector<double> ta, tb;
  double samples = double(a.settings.width) * a.settings.height * a.settings.samples;
  for (int r = 0; r < repeats; ++r) {
    ta.push_back(rt::render(a, o).stats.render_seconds);
    tb.push_back(rt::render(b, o).stats.render_seconds);
  }
  return {median(ta) / samples * 1e9, median(tb) / samples * 1e9};
}

struct Pair {
  const char* name;
  std::string plain, csg;
};
}  // namespace

int main(int argc, char** argv) {
  std::uint32_t res = 240, spp = 4;
  int repeats = 5;
  long tris = 200000, copies = 20, instances = 1000;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string a = argv[i];
    if (a == "--res") res = std::uint32_t(std::max(8, std::atoi(argv[i + 1])));
    if (a == "--spp") spp = std::uint32_t(std::max(1, std::atoi(argv[i + 1])));
    if (a == "--repeats") repeats = std::max(1, std::atoi(argv[i + 1]));
    if (a == "--tris") tris = std::max(100L, std::atol(argv[i + 1]));
    if (a == "--copies") copies = std::max(1L, std::atol(argv[i + 1]));
    if (a == "--instances") instances = std::max(1L, std::atol(argv[i + 1]));
  }
  fs::path dir = fs::temp_directory_path() / ("snell-bench-csg-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string cube = (dir / "cube.obj").string();
  {
    std::ofstream f(cube);
    for (int i = 0; i < 8; ++i)
      f << "v " << (i & 1 ? 1 : -1) << " " << (i & 2 ? 1 : -1) << " " << (i & 4 ? 1 : -1) << "\n";
    f << "f 1 5 7 3\nf 2 4 8 6\nf 1 2 6 5\nf 3 7 8 4\nf 1 3 4 2\nf 5 6 8 7\n";
  }
  const std::string grid = "for i in 0 .. 4 { for j in 0 .. 3 { ";
  const std::string place = " translate <-1.8 + 1.2 * i, 0, 1.2 * j> } } }";
  const std::vector<Pair> pairs = {
      {"lens vs sphere", grid + "sphere { radius 0.5 material diffuse 0.8 " + place,
       grid +
           "intersection { sphere { center <0, 0, 0.3> radius 0.6 } sphere { center <0, 0, "
           "-0.3> radius 0.6 } material diffuse 0.8 " +
           place},
      {"bite vs box",
       grid + "box { min <-0.45, -0.45, -0.45> max <0.45, 0.45, 0.45> material diffuse 0.8 " +
           place,
       grid +
           "difference { box { min <-0.45, -0.45, -0.45> max <0.45, 0.45, 0.45> } sphere { "
           "center <0.45, 0.45, -0.45> radius 0.4 } material diffuse 0.8 " +
           place},
      {"mesh bite vs box",
       grid + "box { min <-0.45, -0.45, -0.45> max <0.45, 0.45, 0.45> material diffuse 0.8 " +
           place,
       grid + "difference { mesh { file \"" + cube +
           "\" scale 0.45 } sphere { center <0.45, 0.45, -0.45> radius 0.4 } material diffuse "
           "0.8 " +
           place},
  };
  std::printf("CSG: %ux%u, %u spp, 1 thread, median of %d\n", res, res * 3 / 4, spp, repeats);
  std::printf("%-18s %14s %14s %8s\n", "pair", "plain ns/spl", "CSG ns/spl", "ratio");
  for (const Pair& p : pairs) {
    auto [x, y] =
        ns_per_sample(compile_scene(p.plain, res, spp), compile_scene(p.csg, res, spp), repeats);
    std::printf("%-18s %14.1f %14.1f %8.2f\n", p.name, x, y, y / x);
    std::fflush(stdout);
  }

  // Quadrics and CSG against the same objects tessellated (about 20k triangles a
  // sphere, 12k a lens: fine enough to look the same at this size).
  {
    std::string ball = "\"" + write_sphere_obj(dir, 20000) + "\"";
    std::string lens = "\"" + write_lens_obj(dir, 40) + "\"";
    const std::string grid8 = "for i in 0 .. 4 { for j in 0 .. 3 { ";
    const std::string at = " translate <-1.8 + 1.2 * i, 0, 1.2 * j> } ";
    std::string analytic =
        grid8 + "sphere { radius 0.45 material diffuse 0.8" + at +
        "intersection { sphere { center <0, 0, 0.3> radius 0.6 } sphere { center <0, 0, -0.3> "
        "radius 0.6 } material diffuse 0.8 translate <-1.8 + 1.2 * i, 0.9, 1.2 * j> } } }";
    std::string meshes = grid8 + "mesh { file " + ball + " scale 0.45 material diffuse 0.8" + at +
                         "mesh { file " + lens +
                         " material diffuse 0.8 translate <-1.8 + 1.2 * i, 0.9, 1.2 * j> } } }";
    auto [x, y] =
        ns_per_sample(compile_scene(analytic, res, spp), compile_scene(meshes, res, spp), repeats);
    std::printf("\nQuadrics and CSG against the same tessellated (12 spheres, 12 lenses):\n");
    std::printf("%-18s %14s %14s %8s\n", "", "analytic ns", "triangles ns", "ratio");
    std::printf("%-18s %14.1f %14.1f %8.2f\n", "per sample", x, y, x / y);
    std::fflush(stdout);
  }

  // A slab drilled with N holes (spheres on an m x m grid, so each is the same
  // fraction of the slab whatever N): what a CSG object's size costs per sample.
  // The leaves' BVH and the counting inside test should keep it nearly flat; a ray
  // that tests every leaf grows with N.
  {
    std::printf("\nA slab with N holes (one difference), ns per sample and against N = 10:\n");
    std::printf("%-18s %14s %8s\n", "holes", "ns/spl", "ratio");
    double first = 0;
    for (long holes : {10L, 100L, 1000L, 10000L}) {
      long m = long(std::ceil(std::sqrt(double(holes))));
      std::string ms = std::to_string(m);
      std::string body =
          "difference { box { min <-2, -0.3, -1.5> max <2, 0.3, 1.5> } for k in 0 .. " +
          std::to_string(holes) + " { sphere { center <-2 + 4 * (k % " + ms + " + 0.5) / " + ms +
          ", 0.3, -1.5 + 3 * (floor(k / " + ms + ") + 0.5) / " + ms + "> radius 1.05 / " + ms +
          " } } material diffuse 0.8 }";
      ir::Scene s = compile_scene(body, res, spp);
      auto [x, y] = ns_per_sample(s, s, repeats);
      double ns = std::fmin(x, y);
      if (first == 0) first = ns;
      std::printf("%-18ld %14.1f %8.2f\n", holes, ns, ns / first);
      std::fflush(stdout);
    }
  }

  std::string sphere = "\"" + write_sphere_obj(dir, tris) + "\"";
  auto layout = [&](long n, const std::string& obj) {
    return "for k in 0 .. " + std::to_string(n) + " { " + obj +
           " scale 0.1 translate <-2 + 0.2 * (k % 20), 0.1 * floor(k / 400), 0.2 * floor((k % 400) "
           "/ 20)> } }";
  };
  auto measure = [&](const char* name, const std::string& body) {
    ir::Scene s = compile_scene(body, 160, 1);
    double before = rss_mib(), peak = before;
    auto t0 = std::chrono::steady_clock::now();
    rt::RenderOptions o;
    o.threads = 1;
    // Sampled while the render runs, when the built scene is alive.
    o.progress = [&](double) { peak = std::fmax(peak, rss_mib()); };
    rt::render(s, o);
    double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    std::printf("%-24s %8.0f MiB while rendering %8.2f s build+render\n", name, peak - before,
                secs);
    std::fflush(stdout);
    return secs;
  };
  std::printf(
      "\nInstances: a %ld-triangle mesh, 160x120, 1 spp (resident memory during the "
      "render less before it)\n",
      tris);
  std::string n = std::to_string(copies);
  double tc = measure(("copies x" + n).c_str(),
                      layout(copies, "mesh { file " + sphere + " material diffuse 0.8"));
  double ti = measure(("instances x" + n).c_str(), "let m = mesh { file " + sphere +
                                                       " material diffuse 0.8 };\n" +
                                                       layout(copies, "object { m"));
  std::printf("%-24s %8.2f\n", "time, copies / instances", tc / ti);
  measure(("instances x" + std::to_string(instances)).c_str(), "let m = mesh { file " + sphere +
                                                                   " material diffuse 0.8 };\n" +
                                                                   layout(instances, "object { m"));
  std::error_code ec;
  fs::remove_all(dir, ec);
  return 0;
}
