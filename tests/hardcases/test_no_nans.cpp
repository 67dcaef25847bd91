// No silent NaNs (robustness.md §1 #37): every example scene and every
// tests/lang/compile/*.scn file that compiles renders, at a small resolution and 2
// samples per pixel, with no non-finite sample dropped and every pixel finite and
// non-negative (#27: radiance is never negative).
#include <algorithm>
#include <catch2/catch.hpp>
#include <filesystem>
#include <string>
#include <vector>

#include "hc_util.hpp"

using namespace snell;
using namespace snell::hc;
namespace fs = std::filesystem;

namespace {

std::vector<fs::path> scenes(const fs::path& dir) {
  std::vector<fs::path> out;
  if (!fs::is_directory(dir)) return out;
  for (const auto& e : fs::directory_iterator(dir))
    if (e.path().extension() == ".scn") out.push_back(e.path());
  std::sort(out.begin(), out.end());
  return out;
}

// Compiles `path` with the small-render overrides; renders it when it compiles.
// Returns false (and says why) only for a compile failure.
bool render_checked(const fs::path& path, bool must_compile) {
  compile::CompileOptions o = compile_options();
  o.overrides = {{"resolution", "<48, 27>"}, {"samples", "2"}};
  auto c = compile::compile_file(path.string(), o);
  if (c->status != compile::CompileStatus::Ok) {
    if (must_compile) {
      INFO(path << "\n" << diagnostics(*c));
      FAIL("does not compile");
    }
    return false;
  }
  REQUIRE(ir::validate(c->scene).empty());
  rt::RenderResult r = rt::render(c->scene, {});
  INFO(path << "\n" << r.stats.to_string());
  CHECK(r.stats.nonfinite_samples == 0);
  CHECK(all_finite(r.image));
  float lo = 0;
  for (float v : r.image.rgb) lo = std::min(lo, v);
  CHECK(lo >= 0.0f);
  CHECK(r.image.width == 48);
  CHECK(r.image.height == 27);
  return true;
}

}  // namespace

TEST_CASE("hc37 every example renders without a non-finite sample", "[hardcase][nan][examples]") {
  auto files = scenes(fs::path(SNELL_SOURCE_DIR) / "examples");
  REQUIRE(files.size() >= 2);
  for (const auto& f : files) {
    INFO(f);
    render_checked(f, true);
  }
}

TEST_CASE("hc37 every compilable tests/lang scene renders without a non-finite sample",
          "[hardcase][nan]") {
  int rendered = 0;
  for (const auto& f : scenes(fs::path(SNELL_SOURCE_DIR) / "tests/lang/compile"))
    rendered += render_checked(f, false);
  CHECK(rendered >= 3);  // most files there are error cases
}
