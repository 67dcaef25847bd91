// bench_interiors: what §14's interior tracking costs. Each pair is one picture
// written two ways: with the core's explicit interfaces (an inner sphere whose
// ior is the ratio of the two media; no priority, so the kernel without
// interiors runs) and with prioritised solids (the kernel that carries the
// interior stack, passes false hits and looks media up). Both are rendered in one
// run, interleaved, 1 thread, median of repeats; the pictures agree to rounding.
// A third row renders the core scene with the general kernel (interiors compiled
// in but unused): the cost of the axis itself.
//
//   bench_interiors [--res W] [--spp N] [--repeats N]
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "compiler/compile.hpp"
#include "runtime/render.hpp"

using namespace snell;

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

const char* kCommon = R"(
camera { location <0, 1.3, -4> look_at <0, 0.8, 0> fov 50 }
background <0.6, 0.7, 0.9>
point_light { position <-2, 5, -3> intensity <40, 40, 40> }
plane { normal <0, 1, 0> distance 0 material diffuse checker { color1 0.8 color2 0.2 size 0.5 } }
)";

struct Pair {
  const char* name;
  std::string core, nested;
};

// Water in a glass ball and an air bubble in water: core interfaces vs priorities.
// The glass is clear: the core applies Beer only on leaving a dielectric, so it
// would not absorb in the glass between the two entries, and the pictures differ.
std::vector<Pair> pairs() {
  return {
      {"water in glass",
       R"(sphere { center <0, 0.9, 0> radius 0.9 material dielectric <1.5, 0> }
          sphere { center <0, 0.9, 0> radius 0.7 material dielectric <1.33 / 1.5, <0.3, 0.08, 0.04>> })",
       R"(sphere { center <0, 0.9, 0> radius 0.9 material dielectric { ior 1.5 priority 1 } }
          sphere { center <0, 0.9, 0> radius 0.7 material dielectric { ior 1.33 absorb <0.3, 0.08, 0.04> priority 2 } })"},
      {"bubble in water",
       R"(sphere { center <0, 0.9, 0> radius 0.9 material dielectric <1.33, 0> }
          sphere { center <0, 0.9, 0> radius 0.45 material dielectric <1 / 1.33, 0> })",
       R"(sphere { center <0, 0.9, 0> radius 0.9 material dielectric { ior 1.33 priority 1 } }
          sphere { center <0, 0.9, 0> radius 0.45 material dielectric { ior 1 priority 2 } })"},
  };
}

ir::Scene compile_scene(const std::string& body, std::uint32_t res, std::uint32_t spp) {
  std::unique_ptr<compile::Compilation> c;
  compile::run_with_large_stack(
      [&] { c = compile::compile_source("bench.scn", std::string(kCommon) + body, {}); });
  if (!c || c->status != compile::CompileStatus::Ok) {
    std::fprintf(stderr, "bench scene does not compile\n");
    std::exit(1);
  }
  ir::Scene s = c->scene;
  s.settings.width = res;
  s.settings.height = res * 3 / 4;
  s.settings.samples = spp;
  s.settings.max_depth = 12;
  return s;
}
}  // namespace

int main(int argc, char** argv) {
  std::uint32_t res = 240, spp = 4;
  int repeats = 3;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string a = argv[i];
    if (a == "--res") res = std::uint32_t(std::max(8, std::atoi(argv[i + 1])));
    if (a == "--spp") spp = std::uint32_t(std::max(1, std::atoi(argv[i + 1])));
    if (a == "--repeats") repeats = std::max(1, std::atoi(argv[i + 1]));
  }
  std::printf("%-16s %9s %9s %9s %8s %8s %10s\n", "scene", "core s", "prio s", "general s",
              "prio/core", "gen/core", "max diff");
  for (const Pair& p : pairs()) {
    ir::Scene core = compile_scene(p.core, res, spp), nested = compile_scene(p.nested, res, spp);
    std::vector<double> tc, tn, tg;
    double worst = 0;
    for (int r = 0; r < repeats; ++r) {
      rt::RenderOptions o;
      o.threads = 1;
      rt::RenderResult a = rt::render(core, o);
      rt::RenderResult b = rt::render(nested, o);
      o.general_kernel = true;
      rt::RenderResult g = rt::render(core, o);
      tc.push_back(a.stats.render_seconds);
      tn.push_back(b.stats.render_seconds);
      tg.push_back(g.stats.render_seconds);
      for (std::size_t i = 0; i < a.image.rgb.size(); ++i)
        worst = std::fmax(worst, std::fabs(double(a.image.rgb[i]) - b.image.rgb[i]));
    }
    double c = median(tc), n = median(tn), g = median(tg);
    std::printf("%-16s %9.3f %9.3f %9.3f %8.3f %8.3f %10.2g\n", p.name, c, n, g, n / c, g / c,
                worst);
    std::fflush(stdout);
  }
  return 0;
}
