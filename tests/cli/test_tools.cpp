// The accuracy study's measuring instruments: if these are wrong, every figure
// in docs/accuracy.md is wrong.
#include <catch2/catch.hpp>
#include <cmath>
#include <random>

#include "cli/metrics.hpp"
#include "cli/plot_svg.hpp"
#include "cli/sweep.hpp"

using namespace snell;

namespace {
rt::Image flat(std::uint32_t w, std::uint32_t h, float v) {
  rt::Image img;
  img.width = w;
  img.height = h;
  img.rgb.assign(std::size_t(w) * h * 3, v);
  return img;
}
}  // namespace

TEST_CASE("RMSE and relative MSE follow their definitions", "[cli][metrics]") {
  rt::Image a = flat(8, 4, 0.5f), b = flat(8, 4, 0.5f);
  CHECK(cli::rmse(a, b) == 0);
  CHECK(cli::relative_mse(a, b) == 0);
  b = flat(8, 4, 0.75f);
  CHECK(cli::rmse(a, b) == Approx(0.25).epsilon(1e-12));
  // (0.25)² / (0.75² + 0.01)
  CHECK(cli::relative_mse(a, b) == Approx(0.0625 / (0.5625 + 0.01)).epsilon(1e-9));
  // One channel of one pixel off by 1: RMSE = sqrt(1 / (8·4·3)).
  rt::Image c = flat(8, 4, 0.5f);
  c.rgb[5] += 1;
  CHECK(cli::rmse(c, flat(8, 4, 0.5f)) == Approx(std::sqrt(1.0 / 96)).epsilon(1e-9));
  CHECK_THROWS(cli::rmse(flat(2, 2, 0), flat(2, 3, 0)));
}

TEST_CASE("SSIM is 1 for identical images and falls with noise", "[cli][metrics]") {
  rt::Image ref = flat(48, 32, 0.2f);
  for (std::uint32_t y = 0; y < 32; ++y)
    for (std::uint32_t x = 0; x < 48; ++x)
      for (int ch = 0; ch < 3; ++ch) ref.at(x, y)[ch] = 0.05f + 0.9f * float(x) / 48;
  CHECK(cli::ssim(ref, ref) == Approx(1).epsilon(1e-12));
  std::mt19937 rng(7);
  std::normal_distribution<float> n01(0, 1);
  double prev = 1;
  for (float sigma : {0.01f, 0.05f, 0.2f}) {
    rt::Image noisy = ref;
    for (float& v : noisy.rgb) v += sigma * n01(rng);
    double s = cli::ssim(noisy, ref);
    CHECK(s < prev);  // more noise, less similar
    CHECK(s > 0);
    prev = s;
  }
  // A uniform brightness shift lowers the luminance term only a little.
  rt::Image shifted = ref;
  for (float& v : shifted.rgb) v *= 1.02f;
  CHECK(cli::ssim(shifted, ref) > 0.99);
}

TEST_CASE("sweep axes parse KEY=V1,V2 with vector values", "[cli]") {
  cli::SweepAxis a;
  REQUIRE(cli::parse_axis("samples=1,4,16", a));
  CHECK(a.key == "samples");
  CHECK(a.values == std::vector<std::string>{"1", "4", "16"});
  REQUIRE(cli::parse_axis("resolution=<32, 24>,<64, 48>", a));
  CHECK(a.values == std::vector<std::string>{"<32, 24>", "<64, 48>"});
  CHECK_FALSE(cli::parse_axis("samples", a));
  CHECK_FALSE(cli::parse_axis("=1,2", a));
  CHECK_FALSE(cli::parse_axis("samples=1,,2", a));
}

TEST_CASE("the SVG plot places points on log axes", "[cli][plot]") {
  cli::Plot p;
  p.title = "t <&>";
  p.series.push_back({"s", {{0.01, 0.1, "a"}, {1, 0.001, "b"}, {-1, 1, "dropped"}}});
  std::string svg = cli::render_svg(p);
  CHECK(svg.rfind("<svg", 0) == 0);
  CHECK(svg.find("t &lt;&amp;&gt;") != std::string::npos);  // escaped
  CHECK(svg.find(">a</text>") != std::string::npos);
  CHECK(svg.find("dropped") == std::string::npos);  // non-positive x is left out
  CHECK(svg.find("<path d=\"M") != std::string::npos);
}
