// bench_textures: what §17's image lookups cost per hit. One scene — a floor and
// six spheres filling the frame, one point light — rendered with its surfaces
// untextured, checkered (a built-in pattern), and textured by a 1024² 8-bit image
// through each mapping family (planar/spherical, and "uv"). Interleaved in one
// run, 1 thread, median of repeats, after a warm-up render that makes the
// linearised .tx and fills the cache. Prints ns per camera sample, the extra ns
// per hit over the untextured scene, the ratio, and OIIO's cache figures.
//
//   bench_textures [--res W] [--spp N] [--repeats N]
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "compiler/compile.hpp"
#include "runtime/render.hpp"

using namespace snell;
namespace fs = std::filesystem;

namespace {
double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

// A 1024² sRGB image with detail at every scale (so the MIP levels differ).
std::string write_image(const fs::path& dir) {
  const int n = 1024;
  std::vector<unsigned char> px(std::size_t(n) * n * 3);
  for (int y = 0; y < n; ++y)
    for (int x = 0; x < n; ++x)
      for (int c = 0; c < 3; ++c)
        px[(std::size_t(y) * n + x) * 3 + c] = static_cast<unsigned char>(
            ((x >> (2 + c)) ^ (y >> (3 + c))) & 1 ? 40 + 60 * c : 220 - 50 * c);
  std::string path = (dir / "bench_texture.png").string();
  auto out = OIIO::ImageOutput::create(path);
  OIIO::ImageSpec spec(n, n, 3, OIIO::TypeDesc::UINT8);
  if (!out || !out->open(path, spec) || !out->write_image(OIIO::TypeDesc::UINT8, px.data()) ||
      !out->close()) {
    std::fprintf(stderr, "cannot write %s\n", path.c_str());
    std::exit(1);
  }
  return path;
}

struct Variant {
  const char* name;
  std::string floor, ball;  // colour sources
};

ir::Scene compile_scene(const Variant& v, std::uint32_t res, std::uint32_t spp) {
  std::string text = R"(
camera { location <0, 5, -4> look_at <0, 0, 1.2> fov 60 }
background <0.6, 0.7, 0.9>
point_light { position <-2, 6, -3> intensity 60 }
plane { normal <0, 1, 0> material diffuse )" +
                     v.floor + R"( }
for i in 0 .. 6 {
  sphere { center <-2.5 + i, 0.45, 1 + (i % 2)> radius 0.45 material diffuse )" +
                     v.ball + R"( }
}
)";
  std::unique_ptr<compile::Compilation> c;
  compile::run_with_large_stack([&] { c = compile::compile_source("bench.scn", text, {}); });
  if (!c || c->status != compile::CompileStatus::Ok) {
    std::fprintf(stderr, "bench scene %s does not compile\n", v.name);
    std::exit(1);
  }
  ir::Scene s = c->scene;
  s.settings.width = res;
  s.settings.height = res * 3 / 4;
  s.settings.samples = spp;
  return s;
}
}  // namespace

int main(int argc, char** argv) {
  std::uint32_t res = 320, spp = 4;
  int repeats = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string a = argv[i];
    if (a == "--res") res = std::max(16, std::atoi(argv[i + 1]));
    if (a == "--spp") spp = std::max(1, std::atoi(argv[i + 1]));
    if (a == "--repeats") repeats = std::max(1, std::atoi(argv[i + 1]));
  }
  fs::path dir = fs::temp_directory_path() / ("snell-bench-textures-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string img = "\"" + write_image(dir) + "\"";
  const std::vector<Variant> variants = {
      {"untextured", "<0.7, 0.7, 0.7>", "<0.8, 0.3, 0.2>"},
      {"checker", "checker { color1 0.8 color2 0.2 size 0.5 }",
       "checker { color1 0.8 color2 0.2 size 0.2 }"},
      {"image planar", "image { file " + img + " rotate <90, 0, 0> scale 2 }",
       "image { file " + img + " mapping \"spherical\" }"},
      {"image uv", "image { file " + img + " mapping \"uv\" scale <2, 2, 1> }",
       "image { file " + img + " mapping \"uv\" }"},
  };
  std::vector<ir::Scene> scenes;
  for (const Variant& v : variants) scenes.push_back(compile_scene(v, res, spp));
  rt::RenderOptions opt;
  opt.threads = 1;
  std::vector<std::vector<double>> t(variants.size());
  std::vector<std::uint64_t> rays(variants.size());
  std::string cache;
  for (std::size_t k = 0; k < scenes.size(); ++k) rt::render(scenes[k], opt);  // warm-up
  for (int r = 0; r < repeats; ++r)
    for (std::size_t k = 0; k < scenes.size(); ++k) {
      auto t0 = std::chrono::steady_clock::now();
      rt::RenderResult out = rt::render(scenes[k], opt);
      t[k].push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
      rays[k] = out.stats.camera_rays;
      if (k == 2 && r == repeats - 1) cache = out.texture_stats;
    }
  std::printf("%ux%u, %u spp, 1 thread, median of %d (every camera ray hits a surface)\n", res,
              res * 3 / 4, spp, repeats);
  std::printf("%-14s %14s %16s %8s\n", "surfaces", "ns per sample", "extra ns per hit", "ratio");
  double base = median(t[0]) / double(rays[0]) * 1e9;
  for (std::size_t k = 0; k < variants.size(); ++k) {
    double ns = median(t[k]) / double(rays[k]) * 1e9;
    std::printf("%-14s %14.1f %16.1f %8.2f\n", variants[k].name, ns, ns - base, ns / base);
  }
  std::printf("\nOpenImageIO's figures for the planar/spherical render:\n%s\n", cache.c_str());
  std::error_code ec;
  fs::remove_all(dir, ec);
  return 0;
}
