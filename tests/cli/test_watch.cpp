// snell watch's parts that need no browser: the pass schedule, that the passes
// together are the full render, the render's cancel flag, the tev packets' bytes and
// the folder watch seeing an editor's rename-save. (The page and the tev stream end to
// end: tests/watch, ctest -L watch.)
#include <unistd.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "cli/file_watch.hpp"
#include "cli/tev.hpp"
#include "cli/watch.hpp"
#include "compiler/compile.hpp"
#include "runtime/render.hpp"

using namespace snell;
using namespace std::chrono_literals;
namespace fs = std::filesystem;

namespace {

ir::Scene scene_of(const std::string& text) {
  auto c = compile::compile_source("watch_test.scn", text, {});
  INFO(c->message);
  REQUIRE(c->status == compile::CompileStatus::Ok);
  return std::move(c->scene);
}

const char* kScene = R"(
settings { resolution <40, 24> samples 16 }
camera { location <0, 1, -5> look_at <0, 0.5, 0> fov 50 }
background <0.1, 0.2, 0.3>
point_light { position <-3, 6, -4> intensity <80, 80, 80> }
plane { normal <0, 1, 0> distance 0 material diffuse 0.6 }
sphere { center <0, 0.8, 0> radius 0.8 material diffuse <0.7, 0.3, 0.2> }
)";

std::uint32_t u32_at(const std::vector<std::uint8_t>& b, std::size_t at) {
  return std::uint32_t(b[at]) | std::uint32_t(b[at + 1]) << 8 | std::uint32_t(b[at + 2]) << 16 |
         std::uint32_t(b[at + 3]) << 24;
}

}  // namespace

TEST_CASE("watch passes: 1, 4, 16, ... samples, ending at the scene's", "[cli][watch]") {
  using P = std::vector<std::pair<std::uint32_t, std::uint32_t>>;
  CHECK(cli::watch_passes(1) == P{{0, 1}});
  CHECK(cli::watch_passes(4) == P{{0, 1}, {1, 4}});
  CHECK(cli::watch_passes(16) == P{{0, 1}, {1, 4}, {4, 16}});
  CHECK(cli::watch_passes(20) == P{{0, 1}, {1, 4}, {4, 16}, {16, 20}});
  CHECK(cli::watch_passes(6) == P{{0, 1}, {1, 4}, {4, 6}});
  CHECK(cli::watch_passes(0) == P{{0, 1}});
  auto big = cli::watch_passes(1u << 20);
  CHECK(big.back().second == 1u << 20);
  for (std::size_t i = 1; i < big.size(); ++i) CHECK(big[i].first == big[i - 1].second);
}

TEST_CASE("watch passes summed are the full render", "[cli][watch]") {
  ir::Scene s = scene_of(kScene);
  rt::RenderResult full = rt::render(s, {});
  std::vector<float> sum(full.image.rgb.size(), 0.0f);
  for (auto [a, b] : cli::watch_passes(16)) {
    rt::RenderOptions o;
    o.sample_range = {a, b};
    rt::RenderResult r = rt::render(s, o);
    for (std::size_t i = 0; i < sum.size(); ++i) sum[i] += r.image.rgb[i] * float(b - a);
  }
  double worst = 0;
  for (std::size_t i = 0; i < sum.size(); ++i)
    worst = std::max(worst, double(std::abs(sum[i] / 16 - full.image.rgb[i])));
  CHECK(worst < 1e-5);
}

TEST_CASE("a render's cancel flag skips its tiles, and unset changes nothing", "[cli][watch]") {
  ir::Scene s = scene_of(kScene);
  rt::RenderResult plain = rt::render(s, {});
  std::atomic<bool> cancel{false};
  rt::RenderOptions o;
  o.cancel = &cancel;
  rt::RenderResult with_flag = rt::render(s, o);
  CHECK_FALSE(with_flag.cancelled);
  CHECK(with_flag.image.rgb == plain.image.rgb);
  cancel = true;
  rt::RenderResult cancelled = rt::render(s, o);
  CHECK(cancelled.cancelled);
  CHECK(cancelled.stats.camera_rays == 0);
}

TEST_CASE("a cancel gives way inside a tile, not only between tiles", "[cli][watch]") {
  // One 16x16 tile at 2^20 spp (a minute's work): the flag, set 100 ms in, used to
  // wait for the whole tile (seconds at such counts in snell watch).
  ir::Scene s = scene_of(kScene);
  s.settings.width = s.settings.height = 16;
  s.settings.samples = 1u << 20;
  std::atomic<bool> cancel{false};
  rt::RenderOptions o;
  o.cancel = &cancel;
  o.threads = 1;
  std::thread setter([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    cancel = true;
  });
  rt::RenderResult r = rt::render(s, o);
  setter.join();
  CHECK(r.cancelled);
  CHECK(r.stats.camera_rays < (std::uint64_t(256) << 20) / 8);
}

TEST_CASE("tev packets: length, type and payload as tev reads them", "[cli][watch]") {
  auto c = cli::tev_create_image("img", 300, 2);
  REQUIRE(c.size() == 4 + 1 + 1 + 4 + 12 + 3 * 2);
  CHECK(u32_at(c, 0) == c.size());
  CHECK(c[4] == 4);  // CreateImage
  CHECK(c[5] == 1);  // grab focus
  CHECK(std::memcmp(&c[6], "img\0", 4) == 0);
  CHECK(u32_at(c, 10) == 300);
  CHECK(u32_at(c, 14) == 2);
  CHECK(u32_at(c, 18) == 3);
  CHECK(std::memcmp(&c[22], "R\0G\0B\0", 6) == 0);

  rt::Image im;
  im.width = 3;
  im.height = 2;
  for (int i = 0; i < 18; ++i) im.rgb.push_back(float(i));
  auto u = cli::tev_update_image("img", im, 1, 1, 0, 2, 2);  // G of x 1..2, y 0..1
  REQUIRE(u.size() == 4 + 1 + 1 + 4 + 2 + 16 + 4 * 4);
  CHECK(u32_at(u, 0) == u.size());
  CHECK(u[4] == 3);  // UpdateImage
  CHECK(std::memcmp(&u[6], "img\0G\0", 6) == 0);
  CHECK(u32_at(u, 12) == 1);
  CHECK(u32_at(u, 16) == 0);
  CHECK(u32_at(u, 20) == 2);
  CHECK(u32_at(u, 24) == 2);
  float v[4];
  std::memcpy(v, &u[28], 16);
  CHECK(v[0] == im.at(1, 0)[1]);
  CHECK(v[1] == im.at(2, 0)[1]);
  CHECK(v[2] == im.at(1, 1)[1]);
  CHECK(v[3] == im.at(2, 1)[1]);
}

TEST_CASE("tev addresses are HOST:PORT", "[cli][watch]") {
  std::string h, p, e;
  CHECK(cli::TevStream::parse_address("127.0.0.1:14158", h, p, e));
  CHECK((h == "127.0.0.1" && p == "14158"));
  CHECK(cli::TevStream::parse_address("[::1]:9", h, p, e));
  CHECK(h == "::1");
  CHECK_FALSE(cli::TevStream::parse_address("localhost", h, p, e));
  CHECK_FALSE(cli::TevStream::parse_address(":14158", h, p, e));
  CHECK_FALSE(cli::TevStream::parse_address("host:", h, p, e));
  CHECK_FALSE(cli::TevStream::parse_address("host:12x", h, p, e));
  CHECK_FALSE(cli::TevStream::parse_address("127.0.0.1:99999", h, p, e));
  CHECK_FALSE(cli::TevStream::parse_address("127.0.0.1:0", h, p, e));
  CHECK_FALSE(cli::TevStream::parse_address("127.0.0.1:0000014158", h, p, e));
  CHECK(cli::TevStream::parse_address("127.0.0.1:65535", h, p, e));
}

TEST_CASE("the folder watch sees a rename-save and not other files", "[cli][watch]") {
  fs::path dir = fs::temp_directory_path() / ("snell-filewatch-" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::string scene = (dir / "a.scn").string();
  std::ofstream(scene) << "// one\n";
  cli::FileWatch w;
  REQUIRE(w.error().empty());
  w.set_files({scene}, false);
  CHECK_FALSE(w.wait(50ms));
  std::ofstream(dir / "other.txt") << "x";  // not a file the scene reads
  CHECK_FALSE(w.wait(200ms));
  std::ofstream(dir / "a.scn.tmp") << "// two\n";
  fs::rename(dir / "a.scn.tmp", scene);  // as vim and VS Code save
  CHECK(w.wait(2000ms));
  CHECK_FALSE(w.wait(100ms));  // the save's events were taken as one change
  std::ofstream(scene, std::ios::app) << "// three\n";  // written in place
  CHECK(w.wait(2000ms));
  // After a failed compile, any file in the folder counts (a missing import).
  w.set_files({scene}, true);
  std::ofstream(dir / "lib.scn") << "let x = 1;\n";
  CHECK(w.wait(2000ms));
  fs::remove_all(dir);
}
