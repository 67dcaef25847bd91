// bench_scale: what big scenes cost — many spheres, and one mesh of many
// triangles — from the scene text to the traced rays, in one run:
//
//   compile   seconds to evaluate and lower the scene, and the resident memory the
//             compiled IR adds, per object (for the mesh: per triangle);
//   build     seconds to build the runtime scene (Embree BVH, the shape sets);
//   render    peak resident memory while rendering, over the compiled scene;
//             camera + shadow rays per second with 1 thread and with 2, and their
//             ratio (one point light, so one shadow ray per lit hit).
//
// Resident memory comes from /proc/self/statm, sampled before and after the
// compile and from the render's progress callback (so while the built scene is
// alive). It includes what the allocator keeps of freed memory: an upper bound on
// what the objects hold, which is what a user pays.
//
//   bench_scale [--spheres N] [--tris N] [--res W] [--spp N] [--rounds N]
//   defaults: 100000 spheres, 1000000 triangles, 640x480, 4 spp, 3 rounds (the best
//   of the interleaved 1- and 2-thread renders).
//   bench_scale --spheres 10000000 --tris 0 --rounds 1   # #18: 10 M spheres
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>

#include "bench/common/bench_files.hpp"
#include "compiler/compile.hpp"
#include "runtime/render.hpp"

using namespace snell;
using bench::rss_mib;
namespace fs = std::filesystem;

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::string common(int res, int spp) {
  return "settings { resolution <" + std::to_string(res) + ", " + std::to_string(res * 3 / 4) +
         "> samples " + std::to_string(spp) +
         " }\n"
         "camera { location <0, 2, -14> look_at <0, 0, 0> fov 45 }\n"
         "point_light { position <-6, 10, -8> intensity <200, 200, 200> }\n"
         "plane { normal <0, 1, 0> distance -5 material diffuse 0.6 }\n";
}

// n spheres on a k×k×k lattice filling [-5, 5]³ (the last layer partly), radius a
// third of the spacing: camera rays pass many spheres' bounds before a hit.
std::string spheres_scene(long n, int res, int spp) {
  long k = std::max(1L, long(std::ceil(std::cbrt(double(n)))));
  double step = 10.0 / double(k), r = step / 3;
  char buf[512];
  std::snprintf(buf, sizeof buf,
                "let m = diffuse <0.7, 0.5, 0.3>;\n"
                "for i in 0 .. %ld {\n"
                "  sphere { center <-5 + %.9g * (i %% %ld), -5 + %.9g * floor(i / %ld %% %ld),\n"
                "                   -5 + %.9g * floor(i / %ld)> radius %.9g material m }\n"
                "}\n",
                n, step, k, step, k, k, step, k * k, r);
  return common(res, spp) + buf;
}

std::string mesh_scene(const std::string& obj, int res, int spp) {
  return common(res, spp) + "mesh { file \"" + obj +
         "\" material diffuse <0.3, 0.5, 0.7> scale 4 }\n";
}

struct Args {
  long spheres = 100000, tris = 1000000;
  int res = 640, spp = 4, rounds = 3;
};

void run(const char* name, const std::string& text, long objects, const char* per, const Args& a) {
  double before = rss_mib();
  auto t0 = std::chrono::steady_clock::now();
  std::unique_ptr<compile::Compilation> c;
  compile::CompileOptions copts;
  copts.step_budget = 4000000000ull;
  compile::run_with_large_stack([&] { c = compile::compile_source("bench.scn", text, copts); });
  if (!c || c->status != compile::CompileStatus::Ok) {
    std::fprintf(stderr, "bench scene %s does not compile\n", name);
    if (c)
      for (const auto& d : c->diags.diagnostics())
        std::fprintf(stderr, "%s\n", c->diags.format(d).c_str());
    std::exit(1);
  }
  double compile_s = seconds_since(t0);
  double ir_mib = rss_mib() - before;
  const ir::Scene& scene = c->scene;

  double best[2] = {1e30, 1e30}, build = 1e30, peak = 0;
  std::uint64_t rays = 0;
  for (int round = 0; round < a.rounds; ++round)
    for (int t = 1; t <= 2; ++t) {
      double base = rss_mib(), top = base;
      rt::RenderOptions o;
      o.threads = t;
      o.progress = [&](double) { top = std::fmax(top, rss_mib()); };
      rt::RenderResult r = rt::render(scene, o);
      best[t - 1] = std::fmin(best[t - 1], r.stats.render_seconds);
      build = std::fmin(build, r.stats.build_seconds);
      peak = std::fmax(peak, top - base);
      rays = r.stats.camera_rays + r.stats.shadow_rays;
    }
  double mrays1 = double(rays) / best[0] / 1e6, mrays2 = double(rays) / best[1] / 1e6;
  std::printf(
      "%-10s %10ld %-4s compile %6.2f s, IR %7.1f MiB (%5.0f B/%s); build %6.2f s; render "
      "+%7.1f MiB (%5.0f B/%s)\n",
      name, objects, per, compile_s, ir_mib, ir_mib * 1048576.0 / double(objects), per, build, peak,
      peak * 1048576.0 / double(objects), per);
  std::printf("%-10s %10s      %.2f Mrays/s 1 thread, %.2f 2 threads: 2T/1T %.2f (%llu rays)\n", "",
              "", mrays1, mrays2, best[0] / best[1], static_cast<unsigned long long>(rays));
  std::fflush(stdout);
}
}  // namespace

int main(int argc, char** argv) {
  Args a;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string k = argv[i];
    long v = std::atol(argv[i + 1]);
    if (k == "--spheres")
      a.spheres = v;
    else if (k == "--tris")
      a.tris = v;
    else if (k == "--res")
      a.res = int(v);
    else if (k == "--spp")
      a.spp = int(v);
    else if (k == "--rounds")
      a.rounds = int(std::max(1L, v));
    else {
      std::fprintf(stderr,
                   "usage: bench_scale [--spheres N] [--tris N] [--res W] [--spp N] "
                   "[--rounds N]\n");
      return 2;
    }
  }
  std::printf("bench_scale: %dx%d, %d spp, best of %d interleaved rounds\n", a.res, a.res * 3 / 4,
              a.spp, a.rounds);
  if (a.spheres > 0) run("spheres", spheres_scene(a.spheres, a.res, a.spp), a.spheres, "obj", a);
  if (a.tris > 0) {
    fs::path dir = fs::temp_directory_path();
    std::string obj = bench::write_sphere_obj(dir, a.tris, false, "bench_scale_sphere.obj");
    int n = bench::sphere_obj_rings(a.tris);
    long tris = 2L * n * (n - 1);
    run("mesh", mesh_scene(obj, a.res, a.spp), tris, "tri", a);
    fs::remove(obj);
  }
  return 0;
}
