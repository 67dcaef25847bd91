#include "runtime/shading/interior.hpp"

#include <fmt/format.h>

#include "runtime/geometry/point_inside.hpp"

namespace snell::rt {

namespace {
std::string medium_text(std::uint32_t m) {
  return m == Interior::kAir ? std::string("air") : fmt::format("#{}", m);
}
}  // namespace

std::string to_string(const Interior& in) {
  std::string s = "interior {";
  for (int i = 0; i < in.count; ++i)
    s += fmt::format(" #{} priority {}", in.entries[i].shape, in.entries[i].priority);
  return s + " medium " + medium_text(in.medium()) + " }";
}

std::string to_string(const Crossing& c) {
  return fmt::format("crossing {{ {} {} -> {}{} {} }}", c.counts ? "counts" : "passes",
                     medium_text(c.from), medium_text(c.to), c.overflow ? " overflow" : "",
                     to_string(c.after));
}

Interiors::Interiors(const ir::Scene& scene) : scene_(scene) {
  bool any = false;
  for (const ir::Material& m : scene.materials)
    if (const ir::Dielectric* d = m.as<ir::Dielectric>()) any = any || d->priority > 0;
  if (!any) return;
  priority_.assign(scene.shapes.size(), 0);
  medium_.assign(scene.shapes.size(), 0);
  auto prioritised = [&](std::uint32_t m) -> const ir::Dielectric* {
    if (m >= scene.materials.size()) return nullptr;
    const ir::Dielectric* d = scene.materials[m].as<ir::Dielectric>();
    return d && d->priority > 0 ? d : nullptr;
  };
  for (std::size_t i = 0; i < scene.shapes.size(); ++i) {
    const ir::Shape& s = scene.shapes[i];
    // A solid's medium: its material's, or for a CSG object whose block has no
    // prioritised dielectric, the first of its children's (a glass cup written
    // with the glass on its cylinders is as glass as one with it on the block).
    std::uint32_t m = s.material;
    if (!prioritised(m) && s.as<ir::Csg>())
      ir::surface_materials(scene, s, [&](std::uint32_t leaf) {
        if (!prioritised(m) && prioritised(leaf)) m = leaf;
      });
    const ir::Dielectric* d = prioritised(m);
    if (!d) continue;
    // ir::validate keeps priorities to solids and the language to 32 bits.
    priority_[i] = std::uint32_t(d->priority);
    medium_[i] = m;
  }
  // Camera rays start inside the solids that contain the camera, entered in the
  // scene's order (so among equal priorities the later object is the medium).
  for (std::size_t i = 0; i < priority_.size(); ++i)
    if (priority_[i] > 0 &&
        geom::point_inside(scene, scene.shapes[i], scene.camera.location, geom::InsideRule::Medium))
      camera_.enter(std::uint32_t(i), priority_[i]);
}

double Interiors::ior(std::uint32_t medium) const {
  if (medium == Interior::kAir) return 1;
  return scene_.materials[medium_[medium]].as<ir::Dielectric>()->ior;
}

const ir::Vec3* Interiors::absorb(std::uint32_t medium) const {
  if (medium == Interior::kAir) return nullptr;
  return &scene_.materials[medium_[medium]].as<ir::Dielectric>()->absorb;
}

Crossing Interiors::cross(const Interior& in, std::uint32_t shape, bool entering) const {
  Crossing c;
  c.after = in;
  const std::uint32_t p = priority(shape);
  const int mb = in.medium_index();
  c.from = mb < 0 ? Interior::kAir : in.entries[mb].shape;
  if (entering) {
    c.overflow = !c.after.enter(shape, p);
  } else if (int i = in.find(shape); i >= 0) {
    c.after.remove(i);
  } else if (mb < 0 || p > in.entries[mb].priority) {
    c.from = shape;  // no entry: as if it had been entered first (interior.hpp)
  }
  c.to = c.after.medium();
  c.counts = c.from != c.to;
  return c;
}

std::string Interiors::to_string() const {
  std::size_t solids = 0;
  for (std::uint32_t p : priority_) solids += p > 0;
  return fmt::format("interiors {{ {} prioritised solid(s) camera {} }}", solids,
                     rt::to_string(camera_));
}

}  // namespace snell::rt
