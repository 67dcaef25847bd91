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
  // A solid's medium: its material's (an instance's, for a part that has none), or
  // for a CSG object whose block has no prioritised dielectric, the first of its
  // children's (a glass cup written with the glass on its cylinders is as glass as
  // one with it on the block). ir::validate keeps priorities to solids and the
  // language to 32 bits.
  auto medium_of = [&](const ir::Shape& s, std::uint32_t inherited) -> std::uint32_t {
    std::uint32_t m = s.material == ir::kInheritMaterial ? inherited : s.material;
    if (!prioritised(m) && s.as<ir::Csg>())
      ir::surface_materials(
          scene, s,
          [&](std::uint32_t leaf) {
            if (!prioritised(m) && prioritised(leaf)) m = leaf;
          },
          m);
    return m;
  };
  // Camera rays start inside the solids that contain the camera, entered in the
  // scene's order (so among equal priorities the later object is the medium).
  const ir::Vec3 cam = scene.camera.location;
  auto enter_if_inside = [&](std::uint32_t solid, bool inside) {
    if (inside) camera_.enter(solid, priority_[solid]);
  };
  for (std::size_t i = 0; i < scene.shapes.size(); ++i) {
    const ir::Shape& s = scene.shapes[i];
    if (const ir::Instance* inst = s.as<ir::Instance>()) {
      if (inst->prototype >= scene.prototypes.size()) continue;
      const std::vector<std::uint32_t>& parts = scene.prototypes[inst->prototype].parts;
      std::vector<std::uint32_t> media(parts.size(), 0);
      bool some = false;
      for (std::size_t j = 0; j < parts.size(); ++j)
        if (parts[j] < scene.parts.size()) {
          media[j] = medium_of(scene.parts[parts[j]], s.material);
          some = some || prioritised(media[j]);
        }
      if (!some) continue;
      const std::uint32_t base = std::uint32_t(priority_.size());
      instance_base_[std::uint32_t(i)] = base;
      for (std::size_t j = 0; j < parts.size(); ++j) {
        const ir::Dielectric* d = prioritised(media[j]);
        priority_.push_back(d ? std::uint32_t(d->priority) : 0);
        medium_.push_back(d ? media[j] : 0);
        part_place_.emplace(parts[j], std::uint32_t(j));
        if (d)
          enter_if_inside(base + std::uint32_t(j),
                          geom::point_inside_part(scene, s, scene.parts[parts[j]], cam,
                                                  geom::InsideRule::Medium));
      }
      continue;
    }
    const std::uint32_t m = medium_of(s, s.material);
    const ir::Dielectric* d = prioritised(m);
    if (!d) continue;
    priority_[i] = std::uint32_t(d->priority);
    medium_[i] = m;
    enter_if_inside(std::uint32_t(i), geom::point_inside(scene, s, cam, geom::InsideRule::Medium));
  }
}

std::uint32_t Interiors::solid_of_instance(const Hit& hit) const {
  auto base = instance_base_.find(hit.index);
  if (base == instance_base_.end()) return hit.index;
  // The part hit: an instance's CSG part holds the leaf in `part`, itself in `outer`.
  const std::uint32_t part = hit.outer != ir::kNoPart ? hit.outer : hit.part;
  auto place = part_place_.find(part);
  return place == part_place_.end() ? hit.index : base->second + place->second;
}

double Interiors::ior(std::uint32_t medium) const {
  if (medium == Interior::kAir) return 1;
  return scene_.materials[medium_[medium]].as<ir::Dielectric>()->ior;
}

const ir::Vec3* Interiors::absorb(std::uint32_t medium) const {
  if (medium == Interior::kAir) return nullptr;
  return &scene_.materials[medium_[medium]].as<ir::Dielectric>()->absorb;
}

Crossing Interiors::cross(const Interior& in, std::uint32_t solid, bool entering) const {
  Crossing c;
  c.after = in;
  const std::uint32_t p = priority(solid);
  const int mb = in.medium_index();
  c.from = mb < 0 ? Interior::kAir : in.entries[mb].shape;
  if (entering) {
    c.overflow = !c.after.enter(solid, p);
  } else if (int i = in.find(solid); i >= 0) {
    c.after.remove(i);
  } else if (mb < 0 || p > in.entries[mb].priority) {
    c.from = solid;  // no entry: as if it had been entered first (interior.hpp)
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
