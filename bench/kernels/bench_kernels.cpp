// bench_kernels: per example scene, the render time of the general kernel
// (--features=all) divided by that of the kernel specialised on ir::Features, both
// measured in one run (interleaved, median of repeats, 1 thread), and whether the
// two pictures are bit-identical.
//
//   bench_kernels [--scale S] [--repeats N] [--with AXIS] [SCENE.scn ...]
// Default: every examples/*.scn at 1/2 resolution (S = 0.5), 3 repeats.
// --with AXIS (an axis of SNELL_KERNEL_AXES, e.g. finish): instead of the general
// kernel, the specialised one with that axis compiled in as well, so the "general"
// column is what the effect's code costs a scene that does not use it.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "compiler/compile.hpp"
#include "runtime/render.hpp"
#include "runtime/render/kernel.hpp"

using namespace snell;

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}
}  // namespace

int main(int argc, char** argv) {
  double scale = 0.5;
  int repeats = 3;
  unsigned with = 0;
  std::vector<std::string> scenes;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--scale" && i + 1 < argc)
      scale = std::atof(argv[++i]);
    else if (a == "--repeats" && i + 1 < argc)
      repeats = std::max(1, std::atoi(argv[++i]));
    else if (a == "--with" && i + 1 < argc) {
      std::string axis = argv[++i];
#define SNELL_AXIS_BIT(name, feature, needs, on, off) \
  if (axis == #name) with |= 1u << rt::kAxis_##name;
      SNELL_KERNEL_AXES(SNELL_AXIS_BIT)
#undef SNELL_AXIS_BIT
      if (!with) {
        std::fprintf(stderr, "bench_kernels: no kernel axis '%s'\n", axis.c_str());
        return 2;
      }
    } else
      scenes.push_back(a);
  }
  if (scenes.empty()) {
    for (const auto& e : std::filesystem::directory_iterator(SNELL_EXAMPLES_DIR))
      if (e.path().extension() == ".scn") scenes.push_back(e.path().string());
    std::sort(scenes.begin(), scenes.end());
  }
  std::printf("%-20s %-9s %10s %10s %8s  %-9s %s\n", "scene", "size",
              with ? "+axis s" : "general s", "special s", "ratio", "identical", "kernel");
  for (const std::string& path : scenes) {
    std::unique_ptr<compile::Compilation> c;
    compile::run_with_large_stack([&] { c = compile::compile_file(path, {}); });
    if (!c || c->status != compile::CompileStatus::Ok) {
      std::printf("%-20s does not compile\n", path.c_str());
      continue;
    }
    ir::Scene s = c->scene;
    s.settings.width = std::max<std::uint32_t>(1, std::uint32_t(s.settings.width * scale));
    s.settings.height = std::max<std::uint32_t>(1, std::uint32_t(s.settings.height * scale));
    std::vector<double> tg, ts;
    bool same = true;
    std::string kernel;
    for (int r = 0; r < repeats; ++r) {
      rt::RenderOptions o;
      o.threads = 1;
      rt::RenderResult spec = rt::render(s, o);
      if (with)
        o.extra_axes = with;
      else
        o.general_kernel = true;
      rt::RenderResult gen = rt::render(s, o);
      ts.push_back(spec.stats.render_seconds);
      tg.push_back(gen.stats.render_seconds);
      same = same && spec.image.rgb == gen.image.rgb;
      kernel = spec.stats.kernel;
    }
    double g = median(tg), sp = median(ts);
    std::string name = std::filesystem::path(path).filename().string();
    std::printf("%-20s %4ux%-4u %10.3f %10.3f %8.3f  %-9s %s\n", name.c_str(), s.settings.width,
                s.settings.height, g, sp, sp > 0 ? g / sp : 0, same ? "yes" : "NO", kernel.c_str());
    std::fflush(stdout);
  }
  return 0;
}
