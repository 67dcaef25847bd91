#include "runtime/ir/bounds.hpp"

namespace snell::ir {

namespace {
template <class G>
double kind_reach(const G& g, const Shape& s, const Scene& scene, Vec3 o) {
  double r = 0;
  hull_points(g, scene,
              [&](Vec3 p) { r = std::fmax(r, reach(s.world_from_object().point(p), o)); });
  return r;
}
// Infinite: its nearest point to `o` must be in range.
double kind_reach(const Plane& p, const Shape& s, const Scene&, Vec3 o) {
  Vec3 p0 = s.world_from_object().point(p.normal * p.distance);
  Vec3 n = normalize(s.world_from_object().normal(p.normal));
  return std::fabs(dot(n, p0 - o));
}
}  // namespace

double object_reach(const Shape& s, const Scene& scene, Vec3 o) {
  return std::visit([&](const auto& g) { return kind_reach(g, s, scene, o); }, s.geom);
}

}  // namespace snell::ir
