#include <cmath>
#include <cstdio>
#include <type_traits>
#include <variant>

#include "runtime/ir/bounds.hpp"
#include "runtime/ir/dump.hpp"
#include "runtime/ir/ir.hpp"

namespace snell::ir {

std::string to_string(const Problem& p, const Scene& scene) {
  return (p.src.line == 0 ? std::string("snell") : to_string(p.src, scene)) + ": error: " + p.what;
}

namespace {
double largest(Vec3 v) {
  return std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z)));
}

// Every number of a kind struct, as the generic checks see it: f(double).
void each_number(double v, auto&& f) {
  f(v);
}
void each_number(Vec3 v, auto&& f) {
  f(v.x), f(v.y), f(v.z);
}
void each_number(std::uint32_t, auto&&) {}  // indices are checked per kind
void each_number(std::uint64_t, auto&&) {}  // integers (a priority) are finite
void each_number(bool, auto&&) {}
template <class E>
requires std::is_enum_v<E>
void each_number(E, auto&&) {}  // spellings (an image's mapping)
void each_number(const Texture& t, auto&& f) {
  std::visit(
      [&](const auto& p) {
        for_each_field(p, [&](const char*, const auto& v) { each_number(v, f); });
      },
      t.pattern);
  for (const ColorStop& c : t.color_map) f(c.at), each_number(c.color, f);
  f(t.turbulence);
  for (int r = 0; r < 4; ++r)
    for (int c = 0; c < 4; ++c) f(t.world_from_pattern.m(r, c)), f(t.world_from_pattern.inv(r, c));
}
template <class T>
bool all_finite(const T& kind) {
  bool ok = true;
  for_each_field(kind, [&](const char*, const auto& v) {
    each_number(v, [&](double x) { ok = ok && std::isfinite(x); });
  });
  return ok;
}
// Whether some colour of a texture is past the radiometric limit.
template <class TooBright>
bool too_bright_texture(const Texture& t, TooBright too_bright) {
  // Colours only (a constant's, a checker's, a colour map's stops): a gradient's
  // direction or a brick's size is a length, and 1e31 of it is fine.
  bool bright = false;
  std::visit(
      [&](const auto& p) {
        for_each_field(p, [&](const char* name, const auto& c) {
          if constexpr (std::is_same_v<std::decay_t<decltype(c)>, Vec3>)
            if (std::string_view(name).starts_with("color")) bright = bright || too_bright(c);
        });
      },
      t.pattern);
  for (const ColorStop& stop : t.color_map) bright = bright || too_bright(stop.color);
  return bright;
}

// Whether some colour of a material's textures is past the radiometric limit.
template <class TooBright>
bool too_bright_colours(const Material& m, TooBright too_bright) {
  bool bright = false;
  std::visit(
      [&](const auto& k) {
        for_each_field(k, [&](const char*, const auto& v) {
          if constexpr (std::is_same_v<std::decay_t<decltype(v)>, Texture>)
            bright = bright || too_bright_texture(v, too_bright);
        });
      },
      m.model);
  return bright;
}

// Per-kind checks beyond finiteness; `bad(what)` reports one. The template is
// every shape kind without checks of its own.
template <class K, class Bad>
void check_kind(const K&, const Scene&, Bad&&) {}
template <class Bad>
void check_kind(const Sphere& s, const Scene&, Bad&& bad) {
  if (!(s.radius > 0)) bad("sphere radius must be > 0");
}
template <class Bad>
void check_kind(const Plane& p, const Scene&, Bad&& bad) {
  if (std::abs(length(p.normal) - 1) > 1e-9) bad("plane normal must be unit length");
}
template <class Bad>
void check_kind(const Mesh& m, const Scene& scene, Bad&& bad) {
  if (m.mesh >= scene.meshes.size()) bad("mesh index out of range");
}
// §11's constraints, as the compiler checks them (compiler/lower_kinds.cpp).
template <class Bad>
void check_kind(const Cylinder& c, const Scene&, Bad&& bad) {
  if (!(c.radius > 0)) bad("cylinder radius must be > 0");
  if (c.base == c.cap) bad("cylinder base and cap must differ");
}
template <class Bad>
void check_kind(const Cone& c, const Scene&, Bad&& bad) {
  if (!(c.base_radius >= 0 && c.cap_radius >= 0)) bad("cone radii must be >= 0");
  if (c.base_radius == 0 && c.cap_radius == 0) bad("cone radii must not both be 0");
  if (c.base == c.cap) bad("cone base and cap must differ");
}
template <class Bad>
void check_kind(const Disc& d, const Scene&, Bad&& bad) {
  if (!(length(d.normal) > 0)) bad("disc normal must be non-zero");
  if (!(d.radius > 0)) bad("disc radius must be > 0");
  if (!(d.hole >= 0 && d.hole < d.radius)) bad("disc hole must be >= 0 and < its radius");
}
template <class Bad>
void check_kind(const Csg& c, const Scene& scene, Bad&& bad) {
  if (c.node >= scene.csg_nodes.size()) bad("csg node out of range");
}
template <class Bad>
void check_kind(const Instance& i, const Scene& scene, Bad&& bad) {
  if (i.prototype >= scene.prototypes.size()) bad("prototype out of range");
}
template <class Bad>
void check_kind(const Torus& t, const Scene&, Bad&& bad) {
  if (!(t.major > t.minor && t.minor > 0)) bad("torus needs major > minor > 0");
}

// Materials: the template is every kind without checks of its own.
template <class K, class Bad>
void check_kind(const K&, Bad&&) {}
template <class Bad>
void check_texture(const Texture& t, Bad&& bad) {
  if (const Checker* c = std::get_if<Checker>(&t.pattern); c && !(c->size > 0))
    bad("checker size must be > 0");
  // Components, not the length: the length of <1e-300, 0, 0> underflows to 0.
  if (const Gradient* g = std::get_if<Gradient>(&t.pattern);
      g && (g->direction == Vec3{} || !is_finite(g->direction)))
    bad("gradient direction must be non-zero and finite");
  if (const Brick* b = std::get_if<Brick>(&t.pattern);
      b && !(b->size.x > 0 && b->size.y > 0 && b->size.z > 0 && b->mortar >= 0))
    bad("brick size must be > 0 and mortar >= 0");
  if (const Fbm* f = std::get_if<Fbm>(&t.pattern); f && !(f->lacunarity > 0 && f->gain > 0))
    bad("fbm lacunarity and gain must be > 0");
  for (std::size_t i = 1; i < t.color_map.size(); ++i)
    if (!(t.color_map[i - 1].at <= t.color_map[i].at)) bad("colour map stops out of order");
  if (!(t.turbulence >= 0)) bad("turbulence must be >= 0");
  if (const FunctionPattern* f = std::get_if<FunctionPattern>(&t.pattern))
    if (std::string why = check(f->program); !why.empty()) bad("shading program: " + why);
  if (t.octaves < 1 || t.octaves > 32) bad("octaves must be in 1..32");
}
template <class Bad>
void check_highlight(double specular, double shininess, Bad&& bad) {
  if (!(specular >= 0)) bad("specular must be >= 0");
  if (!(shininess > 0)) bad("shininess must be > 0");
}
template <class Bad>
void check_kind(const Diffuse& m, Bad&& bad) {
  check_texture(m.color, bad);
  check_highlight(m.specular, m.shininess, bad);
}
template <class Bad>
void check_kind(const Mirror& m, Bad&& bad) {
  check_texture(m.color, bad);
}
template <class Bad>
void check_kind(const Glossy& m, Bad&& bad) {
  check_texture(m.color, bad);
  if (!(m.blur >= 0) || !std::isfinite(m.blur)) bad("blur must be finite and >= 0");
}
template <class Bad>
void check_kind(const Dielectric& m, Bad&& bad) {
  if (!(m.ior > 0) || !std::isfinite(m.ior)) bad("ior must be finite and > 0");
  if (!(m.absorb.x >= 0 && m.absorb.y >= 0 && m.absorb.z >= 0)) bad("absorb must be >= 0");
}
template <class Bad>
void check_kind(const Glazed& m, Bad&& bad) {
  check_texture(m.color, bad);
  if (!(m.ior > 0) || !std::isfinite(m.ior)) bad("ior must be finite and > 0");
  check_highlight(m.specular, m.shininess, bad);
}
// §14: whether a shape bounds a volume a ray can be inside, as a prioritised
// dielectric needs: not a triangle, a disc or an open tube. A mesh is taken to be
// closed with outward normals (not checked: a leaky one confuses only itself).
bool bounds_volume(const Shape& s) {
  return std::visit(
      Overloaded{[](const Triangle&) { return false; }, [](const Disc&) { return false; },
                 [](const Cylinder& c) { return !c.open; }, [](const Cone& c) { return !c.open; },
                 [](const auto&) { return true; }},
      s.geom);
}

// The first part of an instance's value that takes the instance's material and
// has no inside, or null: the parts that take a prioritised instance's material
// must each be a solid (§13: it "applies to the children that have none"; a part
// with its own material is checked as that part). Parts are never instances: a
// value's own instances are placed beside it.
const Shape* part_without_inside(const Shape& s, const Scene& scene) {
  const Instance* in = s.as<Instance>();
  if (!in || in->prototype >= scene.prototypes.size()) return nullptr;
  for (std::uint32_t p : scene.prototypes[in->prototype].parts)
    if (p < scene.parts.size() && scene.parts[p].material == kInheritMaterial &&
        !bounds_volume(scene.parts[p]))
      return &scene.parts[p];
  return nullptr;
}

std::string far_message(const std::string& what, double r) {
  char buf[160];
  std::snprintf(buf, sizeof buf,
                "%s reaches %.3g from the camera; Snell traces in single precision "
                "around the camera and takes scenes within %.0e of it",
                what.c_str(), r, kMaxCameraDistance);
  return buf;
}
}  // namespace

// The float runtime's ranges (kMaxCameraDistance, kMaxRadiometric).
template <class Bad>
void check_ranges(const Scene& scene, Bad&& bad) {
  const Vec3 o = scene.camera.location;
  const double kFar = kMaxCameraDistance;
  const Camera& c = scene.camera;
  if (c.aperture / 2 > kFar) bad(c.src, far_message("the lens (aperture / 2)", c.aperture / 2));
  if (c.focal_distance > kFar) bad(c.src, far_message("the focal plane", c.focal_distance));
  auto too_bright = [](Vec3 v) { return largest(v) > kMaxRadiometric; };
  if (too_bright_texture(scene.background, too_bright))
    bad(scene.background_src, "background radiance must be at most 1e30");
  for (const Material& m : scene.materials)
    if (too_bright_colours(m, too_bright)) bad(m.src, "material colours must be at most 1e30");
  double extent = 1;  // the finite scene's reach from the camera (below)
  for (const Shape& s : scene.shapes) {
    double r = object_reach(s, scene, o);
    if (!(r <= kFar)) bad(s.src, far_message("this " + to_string(s.kind()), r));
    if (!unbounded(s) && r <= kFar) extent = std::fmax(extent, r);
  }
  // §13: a ray meeting an instance is taken into the instance's space by Embree,
  // in float, which refuses coordinates past 1.8e18 (an assertion that ends the
  // process): an instance scaled by 1e-30 did. Ray origins and directions are
  // within the scene's reach, so the inverse's largest stretch times that reach
  // must stay well inside (kInstanceReach); the shutter's placements count too.
  constexpr double kInstanceReach = 1e17;
  for (const Shape& s : scene.shapes) {
    if (!s.as<Instance>()) continue;
    double stretch = 0;
    auto measure = [&](const Transform& t) {
      for (int i = 0; i < 3; ++i)
        stretch = std::fmax(
            stretch, std::fabs(t.inv(i, 0)) + std::fabs(t.inv(i, 1)) + std::fabs(t.inv(i, 2)));
    };
    measure(s.world_from_object());
    if (s.motion().moves())
      for (double u : {0.0, 0.25, 0.5, 0.75, 1.0})
        measure(s.motion().at(u) * s.world_from_object());
    if (!(stretch * 4 * extent <= kInstanceReach)) {
      char buf[320];
      std::snprintf(buf, sizeof buf,
                    "this instance's transform shrinks it by a factor of %.3g: rays taken into "
                    "its space in single precision would reach %.3g there, past what the ray "
                    "tracer takes (%.0e); make the value's own objects smaller, or scale the "
                    "instance by at least %.3g",
                    stretch, stretch * 4 * extent, kInstanceReach, 4 * extent / kInstanceReach);
      bad(s.src, buf);
    }
  }
  for (const PointLight& l : scene.point_lights) {
    if (!(reach(l.position, o) <= kFar))
      bad(l.src, far_message("this point light", reach(l.position, o)));
    if (too_bright(l.intensity)) bad(l.src, "point light intensity must be at most 1e30");
  }
  for (const AreaLight& l : scene.area_lights) {
    double r = 0;
    for (Vec3 p : {l.corner, l.corner + l.edge1, l.corner + l.edge2, l.corner + l.edge1 + l.edge2})
      r = std::fmax(r, reach(p, o));
    if (!(r <= kFar)) bad(l.src, far_message("this area light", r));
    if (too_bright(l.radiance)) bad(l.src, "area light radiance must be at most 1e30");
  }
}

std::vector<Problem> validate(const Scene& scene) {
  std::vector<Problem> problems;
  auto bad = [&](const SourceRef& src, const std::string& what) {
    problems.push_back({src, what});
  };
  const Settings& st = scene.settings;
  if (st.width < 1 || st.height < 1) bad(st.src, "resolution must be at least 1x1");
  if (st.samples < 1) bad(st.src, "samples must be at least 1");
  if (!(st.min_weight >= 0) || !std::isfinite(st.min_weight))
    bad(st.src, "min_weight must be >= 0");
  const Camera& c = scene.camera;
  if (!is_finite(c.location) || !is_finite(c.look_at) || !is_finite(c.up))
    bad(c.src, "camera vectors must be finite");
  Vec3 fwd = c.look_at - c.location;
  if (length(fwd) == 0)
    bad(c.src, "camera look_at equals location");
  else if (length(cross(fwd, c.up)) == 0)
    bad(c.src, "camera up is parallel to the view direction");
  if (!(c.fov > 0 && c.fov < 180)) bad(c.src, "fov must be in (0, 180)");
  if (!(c.aperture >= 0)) bad(c.src, "aperture must be >= 0");
  if (!(c.focal_distance > 0)) bad(c.src, "focal_distance must be > 0");
  if (!(c.shutter_open <= c.shutter_close)) bad(c.src, "shutter open must be <= close");
  if (const Constant* bg = std::get_if<Constant>(&scene.background.pattern))
    if (!is_finite(bg->color)) bad({}, "background must be finite");
  auto finite_transform = [](const Transform& t) {
    for (double v : t.m.m)
      if (!std::isfinite(v)) return false;
    for (double v : t.inv.m)
      if (!std::isfinite(v)) return false;
    return true;
  };
  for (const Material& m : scene.materials) {
    auto bad_here = [&](const std::string& what) { bad(m.src, what); };
    std::visit(
        [&](const auto& k) {
          check_kind(k, bad_here);
          if (!all_finite(k)) bad(m.src, "material colours and absorb must be finite");
        },
        m.model);
    if (m.bump.on()) {
      check_texture(m.bump.pattern, bad_here);
      bool finite = std::isfinite(m.bump.amount);
      each_number(m.bump.pattern, [&](double x) { finite = finite && std::isfinite(x); });
      if (!finite) bad(m.src, "bump pattern and amount must be finite");
    }
  }
  auto check_shape = [&](const Shape& s, bool part) {
    auto bad_here = [&](const std::string& what) { bad(s.src, what); };
    bool finite = std::visit([](const auto& g) { return all_finite(g); }, s.geom);
    if (!finite || !finite_transform(s.world_from_object()))
      bad(s.src, to_string(s.kind()) + " has a non-finite position, size or transform");
    auto check_block = [&](const std::vector<TransformOp>& ops, bool has_pivot, Vec3 pivot) {
      for (const TransformOp& op : ops)
        if (!is_finite(op.value)) bad(s.src, "motion has a non-finite value");
      if (has_pivot && !is_finite(pivot)) bad(s.src, "motion has a non-finite pivot");
    };
    const Motion& mo = s.motion();
    check_block(mo.ops, mo.has_pivot, mo.pivot);
    for (const MotionBlock& b : mo.nested) {
      check_block(b.ops, b.has_pivot, b.pivot);
      if (!finite_transform(b.world_from_frame))
        bad(s.src, "motion has a non-finite frame (the transforms of the objects around it)");
    }
    if (s.material >= scene.materials.size()) {
      if (!(part && s.material == kInheritMaterial)) bad(s.src, "material index out of range");
    } else if (const Dielectric* d = scene.materials[s.material].as<Dielectric>();
               d && d->priority > 0) {
      const Shape* open_part = bounds_volume(s) ? part_without_inside(s, scene) : &s;
      if (open_part) {
        bool open =
            open_part->kind() == ShapeKind::Cylinder || open_part->kind() == ShapeKind::Cone;
        std::string what = std::string(open ? "open " : "") + to_string(open_part->kind());
        bad(s.src, "a dielectric with a 'priority' must fill a solid (§14), and this " +
                       (open_part == &s ? what + " has no inside"
                                        : "object holds " + std::string(open ? "an " : "a ") +
                                              what + ", which has no inside"));
      }
    }
    std::visit([&](const auto& g) { check_kind(g, scene, bad_here); }, s.geom);
  };
  for (const Shape& s : scene.shapes) check_shape(s, false);
  for (const Shape& s : scene.parts) {
    check_shape(s, true);
    if (s.kind() == ShapeKind::Instance) bad(s.src, "an instance cannot be a part");
  }
  // Children come before their parents, so a tree has no cycles.
  for (std::size_t i = 0; i < scene.csg_nodes.size(); ++i) {
    const CsgNode& n = scene.csg_nodes[i];
    if (n.leaf() ? n.part >= scene.parts.size() : n.children.empty())
      problems.push_back({{}, "csg node #" + std::to_string(i) + " is empty or out of range"});
    for (std::uint32_t child : n.children)
      if (child >= i)
        problems.push_back({{}, "csg node #" + std::to_string(i) + " child out of order"});
  }
  // A CSG leaf may move inside its CSG object (§12); a prototype is static
  // geometry the BVH instances (§13), so nothing of it moves.
  for (const Prototype& p : scene.prototypes)
    for (std::uint32_t i : p.parts)
      if (i >= scene.parts.size())
        bad(p.src, "prototype part out of range");
      else if (moves(scene.parts[i], scene))
        bad(scene.parts[i].src, "a part of an instanced object value does not move");
  for (const MeshData& m : scene.meshes) {
    for (const Vec3& p : m.positions)
      if (!is_finite(p)) {
        problems.push_back({{}, m.path + ": non-finite vertex position"});
        break;
      }
    if (m.indices.size() % 3 != 0)
      problems.push_back({{}, m.path + ": index count not a multiple of 3"});
    for (std::uint32_t i : m.indices)
      if (i >= m.positions.size()) {
        problems.push_back({{}, m.path + ": vertex index out of range"});
        break;
      }
    if (m.smooth() && m.normal_indices.size() != m.indices.size())
      problems.push_back({{}, m.path + ": normal index count differs from the vertex index count"});
    for (std::uint32_t i : m.normal_indices)
      if (i != MeshData::kNoNormal && i >= m.normals.size()) {
        problems.push_back({{}, m.path + ": normal index out of range"});
        break;
      }
    for (const Vec3& n : m.normals)
      if (!is_finite(n)) {
        problems.push_back({{}, m.path + ": non-finite normal"});
        break;
      }
  }
  for (const PointLight& l : scene.point_lights)
    if (!is_finite(l.position) || !is_finite(l.intensity))
      bad(l.src, "point light position and intensity must be finite");
  for (const AreaLight& l : scene.area_lights) {
    if (!is_finite(l.corner) || !is_finite(l.edge1) || !is_finite(l.edge2) ||
        !is_finite(l.radiance))
      bad(l.src, "area light corner, edges and radiance must be finite");
    if (length(cross(l.edge1, l.edge2)) == 0) bad(l.src, "area light has zero area");
    if (l.samples_u < 1 || l.samples_v < 1) bad(l.src, "area light samples must be >= 1");
  }
  if (!problems.empty()) return problems;  // the ranges below assume finite numbers
  check_ranges(scene, bad);
  return problems;
}

}  // namespace snell::ir
