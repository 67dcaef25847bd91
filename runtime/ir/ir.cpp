#include "runtime/ir/ir.hpp"

#include <charconv>
#include <cmath>
#include <cstdio>

namespace snell::ir {
namespace {

// Shortest round-trip text of a double: dumps are stable and exact.
std::string num(double v) {
  if (v == 0) return "0";  // also folds -0
  char buf[32];
  auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

std::string quoted(const std::string& s) {
  return "\"" + s + "\"";
}

}  // namespace

std::string to_string(Vec3 v) {
  return "<" + num(v.x) + ", " + num(v.y) + ", " + num(v.z) + ">";
}

std::string to_string(const Transform& t) {
  if (t.is_identity()) return "identity";
  std::string s = "[";
  for (int r = 0; r < 3; ++r) {
    if (r) s += "; ";
    for (int c = 0; c < 4; ++c) s += (c ? " " : "") + num(t.m(r, c));
  }
  return s + "]";
}

bool Motion::moves() const {
  for (const TransformOp& op : ops) {
    switch (op.kind) {
      case TransformOp::Kind::Translate:
      case TransformOp::Kind::Rotate:
        if (op.value != Vec3{}) return true;
        break;
      case TransformOp::Kind::Scale:
        if (op.value != Vec3{1, 1, 1}) return true;
        break;
    }
  }
  return false;
}

Transform Motion::at(double u) const {
  Transform t;
  for (const TransformOp& op : ops) {
    switch (op.kind) {
      case TransformOp::Kind::Translate:
        t = Transform::translate(op.value * u) * t;
        break;
      case TransformOp::Kind::Rotate:
        t = Transform::rotate_xyz(op.value * u) * t;
        break;
      case TransformOp::Kind::Scale:
        t = Transform::scale(Vec3{1, 1, 1} * (1 - u) + op.value * u) * t;
        break;
    }
  }
  return t;
}

Features Features::all() {
  Features f;
  f.motion_blur = f.depth_of_field = f.point_lights = f.area_lights = f.mirror = f.glossy =
      f.dielectric = f.absorption = f.glazed = f.textures = true;
  f.reasons.push_back({"all", "--features=all forces the general kernel"});
  return f;
}

Features analyze_features(const Scene& scene) {
  Features f;
  auto why = [&](const char* effect, std::string reason) {
    f.reasons.push_back({effect, std::move(reason)});
  };
  const Camera& cam = scene.camera;
  bool shutter_open = cam.shutter_close > cam.shutter_open;
  std::size_t movers = 0;
  std::size_t first_mover = 0;
  for (std::size_t i = 0; i < scene.shapes.size(); ++i)
    if (scene.shapes[i].motion.moves()) {
      if (movers++ == 0) first_mover = i;
    }
  if (shutter_open && movers > 0) {
    f.motion_blur = true;
    why("motion blur", std::to_string(movers) + " object(s) move, the first at " +
                           to_string(scene.shapes[first_mover].src, scene) +
                           ", and the shutter is open from " + num(cam.shutter_open) + " to " +
                           num(cam.shutter_close));
  } else if (movers > 0) {
    why("motion blur (off)", "objects have motion but the shutter is closed (shutter <" +
                                 num(cam.shutter_open) + ", " + num(cam.shutter_close) + ">)");
  } else if (shutter_open) {
    why("motion blur (off)", "the shutter is open but nothing moves");
  }
  if (cam.aperture > 0) {
    f.depth_of_field = true;
    why("depth of field", "camera aperture " + num(cam.aperture) + " > 0 at " +
                              to_string(cam.src, scene) + ", focused at " +
                              num(cam.focal_distance));
  }
  if (!scene.point_lights.empty()) {
    f.point_lights = true;
    why("point lights", std::to_string(scene.point_lights.size()) +
                            " point light(s): one shadow ray each per shading point");
  }
  if (!scene.area_lights.empty()) {
    f.area_lights = true;
    std::uint64_t rays = 0;
    for (const AreaLight& l : scene.area_lights) rays += std::uint64_t(l.samples_u) * l.samples_v;
    why("area lights", std::to_string(scene.area_lights.size()) + " area light(s): " +
                           std::to_string(rays) + " shadow rays per shading point in all");
  }
  std::vector<bool> used(scene.materials.size(), false);
  for (const Shape& s : scene.shapes)
    if (s.material < used.size()) used[s.material] = true;
  for (std::size_t i = 0; i < scene.materials.size(); ++i) {
    if (!used[i]) continue;
    const Material& m = scene.materials[i];
    std::string where = to_string(m.src, scene);
    auto once = [&](bool& flag, const char* effect, std::string reason) {
      if (!flag) {
        flag = true;
        why(effect, std::move(reason));
      }
    };
    if (m.color.kind == Texture::Kind::Checker)
      once(f.textures, "textures", "a checker pattern at " + where);
    switch (m.kind) {
      case MaterialKind::Diffuse:
        break;
      case MaterialKind::Mirror:
        once(f.mirror, "mirror", "a mirror material at " + where);
        break;
      case MaterialKind::Glossy:
        if (m.blur > 0)
          once(f.glossy, "glossy", "a glossy material with blur " + num(m.blur) + " at " + where);
        else
          once(f.mirror, "mirror", "a glossy material with blur 0 (a mirror) at " + where);
        break;
      case MaterialKind::Dielectric:
        once(f.dielectric, "dielectric", "a dielectric of ior " + num(m.ior) + " at " + where);
        if (max_component(m.absorb) > 0)
          once(f.absorption, "absorption", "absorb " + to_string(m.absorb) + " at " + where);
        break;
      case MaterialKind::Glazed:
        once(f.glazed, "glazed", "a glazed material at " + where);
        break;
    }
  }
  return f;
}

std::string to_string(const Problem& p, const Scene& scene) {
  return (p.src.line == 0 ? std::string("snell") : to_string(p.src, scene)) + ": error: " + p.what;
}

namespace {
// The largest |coordinate| of the corners of the box lo..hi placed by `xf`,
// relative to `origin`.
double largest(Vec3 v) {
  return std::fmax(std::fabs(v.x), std::fmax(std::fabs(v.y), std::fabs(v.z)));
}
double reach(Vec3 p, Vec3 origin) {
  return largest(p - origin);
}
double placed_box_reach(const Transform& xf, Vec3 lo, Vec3 hi, Vec3 origin) {
  double r = 0;
  for (int i = 0; i < 8; ++i)
    r = std::fmax(
        r,
        reach(xf.point({i & 1 ? hi.x : lo.x, i & 2 ? hi.y : lo.y, i & 4 ? hi.z : lo.z}), origin));
  return r;
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
  if (too_bright(scene.background)) bad({}, "background radiance must be at most 1e30");
  for (const Material& m : scene.materials)
    if (too_bright(m.color.color) || too_bright(m.color.color2))
      bad(m.src, "material colours must be at most 1e30");
  for (const Shape& s : scene.shapes) {
    double r = 0;
    switch (s.kind) {
      case ShapeKind::Sphere:
        r = placed_box_reach(s.world_from_object, s.center - Vec3(s.radius),
                             s.center + Vec3(s.radius), o);
        break;
      case ShapeKind::Box:
        r = placed_box_reach(s.world_from_object, s.min, s.max, o);
        break;
      case ShapeKind::Triangle:
        for (Vec3 p : {s.a, s.b, s.c}) r = std::fmax(r, reach(s.world_from_object.point(p), o));
        break;
      case ShapeKind::Mesh:
        if (s.mesh < scene.meshes.size())
          for (const Vec3& p : scene.meshes[s.mesh].positions)
            r = std::fmax(r, reach(s.world_from_object.point(p), o));
        break;
      case ShapeKind::Plane: {
        // Infinite: its nearest point to the camera must be in range.
        Vec3 p0 = s.world_from_object.point(s.normal * s.distance);
        Vec3 n = normalize(s.world_from_object.normal(s.normal));
        r = std::fabs(dot(n, p0 - o));
        break;
      }
    }
    if (!(r <= kFar)) bad(s.src, far_message("this " + to_string(s.kind), r));
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
  if (!is_finite(scene.background)) bad({}, "background must be finite");
  for (const Material& m : scene.materials) {
    if (m.kind == MaterialKind::Dielectric || m.kind == MaterialKind::Glazed)
      if (!(m.ior > 0) || !std::isfinite(m.ior)) bad(m.src, "ior must be finite and > 0");
    if (!(m.absorb.x >= 0 && m.absorb.y >= 0 && m.absorb.z >= 0)) bad(m.src, "absorb must be >= 0");
    if (!(m.blur >= 0) || !std::isfinite(m.blur)) bad(m.src, "blur must be finite and >= 0");
    if (m.color.kind == Texture::Kind::Checker && !(m.color.size > 0))
      bad(m.src, "checker size must be > 0");
  }
  auto finite_transform = [](const Transform& t) {
    for (double v : t.m.m)
      if (!std::isfinite(v)) return false;
    for (double v : t.inv.m)
      if (!std::isfinite(v)) return false;
    return true;
  };
  for (const Material& m : scene.materials)
    if (!is_finite(m.color.color) || !is_finite(m.color.color2) || !is_finite(m.absorb))
      bad(m.src, "material colours and absorb must be finite");
  for (const Shape& s : scene.shapes) {
    if (!is_finite(s.center) || !std::isfinite(s.radius) || !is_finite(s.normal) ||
        !std::isfinite(s.distance) || !is_finite(s.min) || !is_finite(s.max) || !is_finite(s.a) ||
        !is_finite(s.b) || !is_finite(s.c) || !finite_transform(s.world_from_object))
      bad(s.src, to_string(s.kind) + " has a non-finite position, size or transform");
    for (const TransformOp& op : s.motion.ops)
      if (!is_finite(op.value)) bad(s.src, "motion has a non-finite value");
    if (s.material >= scene.materials.size()) bad(s.src, "material index out of range");
    if (s.kind == ShapeKind::Mesh && s.mesh >= scene.meshes.size())
      bad(s.src, "mesh index out of range");
    if (s.kind == ShapeKind::Sphere && !(s.radius > 0)) bad(s.src, "sphere radius must be > 0");
    if (s.kind == ShapeKind::Plane && std::abs(length(s.normal) - 1) > 1e-9)
      bad(s.src, "plane normal must be unit length");
  }
  for (const Mesh& m : scene.meshes) {
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

std::string to_string(const SourceRef& ref, const Scene& scene) {
  if (ref.line == 0) return "<built-in>";
  std::string file = ref.file < scene.files.size() ? scene.files[ref.file] : "?";
  return file + ":" + std::to_string(ref.line) + ":" + std::to_string(ref.col);
}

std::string to_string(MaterialKind k) {
  switch (k) {
    case MaterialKind::Diffuse:
      return "diffuse";
    case MaterialKind::Mirror:
      return "mirror";
    case MaterialKind::Glossy:
      return "glossy";
    case MaterialKind::Dielectric:
      return "dielectric";
    case MaterialKind::Glazed:
      return "glazed";
  }
  return "?";
}

std::string to_string(ShapeKind k) {
  switch (k) {
    case ShapeKind::Sphere:
      return "sphere";
    case ShapeKind::Plane:
      return "plane";
    case ShapeKind::Box:
      return "box";
    case ShapeKind::Triangle:
      return "triangle";
    case ShapeKind::Mesh:
      return "mesh";
  }
  return "?";
}

std::string to_string(SamplerKind k) {
  switch (k) {
    case SamplerKind::Independent:
      return "independent";
    case SamplerKind::Stratified:
      return "stratified";
    case SamplerKind::Sobol:
      return "sobol";
  }
  return "?";
}

std::string to_string(FresnelMode m) {
  return m == FresnelMode::Exact ? "exact" : "schlick";
}
std::string to_string(Branching b) {
  return b == Branching::Split ? "split" : "stochastic";
}
std::string to_string(Termination t) {
  return t == Termination::Cutoff ? "cutoff" : "roulette";
}

std::string to_string(const Texture& t) {
  if (t.kind == Texture::Kind::Constant) return to_string(t.color);
  return "checker { color1 " + to_string(t.color) + " color2 " + to_string(t.color2) + " size " +
         num(t.size) + " }";
}

std::string to_string(const Material& m) {
  std::string s = to_string(m.kind) + " {";
  switch (m.kind) {
    case MaterialKind::Diffuse:
    case MaterialKind::Mirror:
      s += " color " + to_string(m.color);
      break;
    case MaterialKind::Glossy:
      s += " color " + to_string(m.color) + " blur " + num(m.blur);
      break;
    case MaterialKind::Dielectric:
      s += " ior " + num(m.ior) + " absorb " + to_string(m.absorb);
      break;
    case MaterialKind::Glazed:
      s += " color " + to_string(m.color) + " ior " + num(m.ior);
      break;
  }
  return s + " }";
}

std::string to_string(const Shape& sh) {
  std::string s = to_string(sh.kind) + " {";
  switch (sh.kind) {
    case ShapeKind::Sphere:
      s += " center " + to_string(sh.center) + " radius " + num(sh.radius);
      break;
    case ShapeKind::Plane:
      s += " normal " + to_string(sh.normal) + " distance " + num(sh.distance);
      break;
    case ShapeKind::Box:
      s += " min " + to_string(sh.min) + " max " + to_string(sh.max);
      break;
    case ShapeKind::Triangle:
      s += " a " + to_string(sh.a) + " b " + to_string(sh.b) + " c " + to_string(sh.c);
      break;
    case ShapeKind::Mesh:
      s += " mesh #" + std::to_string(sh.mesh);
      break;
  }
  s += " material #" + std::to_string(sh.material);
  if (!sh.world_from_object.is_identity())
    s += " world_from_object " + to_string(sh.world_from_object);
  if (!sh.motion.ops.empty()) {
    s += " motion {";
    for (const TransformOp& op : sh.motion.ops) {
      const char* k = op.kind == TransformOp::Kind::Translate ? " translate "
                      : op.kind == TransformOp::Kind::Rotate  ? " rotate "
                                                              : " scale ";
      s += k + to_string(op.value);
    }
    s += " }";
  }
  return s + " }";
}

std::string to_string(const PointLight& l) {
  return "point_light { position " + to_string(l.position) + " intensity " +
         to_string(l.intensity) + " }";
}

std::string to_string(const AreaLight& l) {
  return "area_light { corner " + to_string(l.corner) + " edge1 " + to_string(l.edge1) + " edge2 " +
         to_string(l.edge2) + " radiance " + to_string(l.radiance) + " samples <" +
         std::to_string(l.samples_u) + ", " + std::to_string(l.samples_v) + "> two_sided " +
         (l.two_sided ? "true" : "false") + " }";
}

std::string to_string(const Camera& c) {
  return "camera { location " + to_string(c.location) + " look_at " + to_string(c.look_at) +
         " up " + to_string(c.up) + " fov " + num(c.fov) + " aperture " + num(c.aperture) +
         " focal_distance " + num(c.focal_distance) + " shutter <" + num(c.shutter_open) + ", " +
         num(c.shutter_close) + "> }";
}

std::string to_string(const Settings& s) {
  return "settings { resolution <" + std::to_string(s.width) + ", " + std::to_string(s.height) +
         "> samples " + std::to_string(s.samples) + " sampler " + quoted(to_string(s.sampler)) +
         " max_depth " + std::to_string(s.max_depth) + " min_weight " + num(s.min_weight) +
         " fresnel " + quoted(to_string(s.fresnel)) + " branching " +
         quoted(to_string(s.branching)) + " termination " + quoted(to_string(s.termination)) +
         " seed " + std::to_string(s.seed) + " }";
}

std::string to_string(const Features& f) {
  std::string s;
  for (const auto& [effect, reason] : f.reasons) s += effect + ": " + reason + "\n";
  if (s.empty()) s = "(no effects beyond diffuse shading)\n";
  return s;
}

std::string to_string(const Scene& scene) {
  std::string s = to_string(scene.settings) + "\n" + to_string(scene.camera) + "\n";
  s += "background " + to_string(scene.background) + "\n";
  for (std::size_t i = 0; i < scene.materials.size(); ++i)
    s += "material #" + std::to_string(i) + " " + to_string(scene.materials[i]) + "\n";
  for (std::size_t i = 0; i < scene.meshes.size(); ++i)
    s += "mesh #" + std::to_string(i) + " " + quoted(scene.meshes[i].path) + " " +
         std::to_string(scene.meshes[i].positions.size()) + " vertices " +
         std::to_string(scene.meshes[i].indices.size() / 3) + " triangles\n";
  for (std::size_t i = 0; i < scene.shapes.size(); ++i)
    s += "shape #" + std::to_string(i) + " " + to_string(scene.shapes[i]) + "\n";
  for (const PointLight& l : scene.point_lights) s += to_string(l) + "\n";
  for (const AreaLight& l : scene.area_lights) s += to_string(l) + "\n";
  return s;
}

}  // namespace snell::ir
