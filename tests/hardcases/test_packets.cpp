// #17 packets: a ray traced in a packet (EmbreeScene::intersect / occluded over a
// span: rtcIntersect16 / rtcOccluded16 with the user geometry's N-ray callbacks)
// gets exactly the answer it gets traced alone — the same hit or miss, t, normal,
// point, offset, shape, part and material, bit for bit — so images do not depend
// on how rays are batched. Every example scene is tried (they hold every shape
// kind, CSG, instances, meshes, planes, moving shapes and area lights), with
// coherent camera-like rays and incoherent ones from the hit points, in batches of
// 1, 5, 16 and 37 rays (a lone ray, a partial packet, a full one, several).
#include <catch2/catch.hpp>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "runtime/embree_scene.hpp"
#include "tests/hardcases/hc_util.hpp"

using namespace snell;
using namespace snell::hc;
namespace fs = std::filesystem;

namespace {

bool same_bits(float a, float b) {
  return std::memcmp(&a, &b, sizeof a) == 0;
}
bool same_bits(rt::Vec3f a, rt::Vec3f b) {
  return same_bits(a.x, b.x) && same_bits(a.y, b.y) && same_bits(a.z, b.z);
}

std::string differ(const rt::Hit& a, const rt::Hit& b) {
  if (!same_bits(a.t, b.t)) return "t";
  if (!same_bits(a.ng, b.ng)) return "ng";
  if (!same_bits(a.p, b.p)) return "p";
  if (!same_bits(a.offset, b.offset)) return "offset";
  if (a.kind != b.kind || a.index != b.index || a.material != b.material) return "shape";
  if (a.part != b.part || a.outer != b.outer || a.prim != b.prim) return "part";
  if (a.smooth != b.smooth || (a.smooth && !same_bits(a.ns, b.ns))) return "smooth";
  return "";
}

}  // namespace

TEST_CASE("a ray traced in a packet gets the answer it gets alone", "[hardcases][packets]") {
  std::size_t scenes = 0, rays_checked = 0, hits = 0, blocked_count = 0;
  for (const auto& entry : fs::directory_iterator(std::string(SNELL_SOURCE_DIR) + "/examples")) {
    if (entry.path().extension() != ".scn") continue;
    auto c = compile::compile_source(
        entry.path().string(), (std::stringstream() << std::ifstream(entry.path()).rdbuf()).str(),
        compile_options());
    REQUIRE(c);
    INFO(entry.path().string() << "\n" << diagnostics(*c));
    REQUIRE(c->status == compile::CompileStatus::Ok);
    const ir::Scene& s = c->scene;
    rt::EmbreeScene es(s, s.camera.location);
    ++scenes;
    std::mt19937_64 rng(scenes);
    std::uniform_real_distribution<double> u(-1, 1), t01(0, 1);
    ir::Vec3 fwd = ir::normalize(s.camera.look_at - s.camera.location);
    for (std::size_t batch : {1u, 5u, 16u, 37u}) {
      std::vector<rt::Ray> rays;
      // Coherent: a cone about the view direction, from the camera. Incoherent:
      // from points found along those, in any direction, at random times.
      for (std::size_t i = 0; i < batch; ++i) {
        ir::Vec3 d = ir::normalize(fwd + 0.5 * ir::Vec3(u(rng), u(rng), u(rng)));
        rays.push_back({f({0, 0, 0}), f(d), INFINITY, float(t01(rng))});
      }
      for (std::size_t i = 0; i < batch; ++i) {
        rt::Hit h;
        if (!es.intersect(rays[i], h)) continue;
        rt::Vec3f dir = f(unit(rng));
        rays.push_back({rt::spawn_origin(h, dot(dir, h.ng) > 0 ? h.ng : -h.ng, 1), dir, INFINITY,
                        float(t01(rng))});
      }
      for (std::size_t first = 0; first < rays.size(); first += batch) {
        std::size_t n = std::min(batch, rays.size() - first);
        std::span<const rt::Ray> span(rays.data() + first, n);
        std::vector<rt::Hit> packed(n);
        std::vector<std::uint8_t> found(n), blocked(n);
        es.intersect(span, packed, found);
        std::vector<rt::Ray> shadow(span.begin(), span.end());
        for (rt::Ray& r : shadow) r.tmax = 4;
        es.occluded(shadow, blocked);
        for (std::size_t i = 0; i < n; ++i) {
          rt::Hit alone;
          bool f1 = es.intersect(span[i], alone);
          INFO("batch " << batch << " ray " << first + i << ": " << rt::to_string(span[i]));
          REQUIRE(bool(found[i]) == f1);
          if (f1) CHECK(differ(packed[i], alone) == "");
          CHECK(bool(blocked[i]) == es.occluded(shadow[i]));
          ++rays_checked;
          hits += f1;
          blocked_count += blocked[i];
        }
      }
    }
  }
  CHECK(scenes >= 10);
  // The rays did meet things and were blocked (the test is not vacuous).
  CHECK(hits > rays_checked / 4);
  CHECK(blocked_count > 0);
}
