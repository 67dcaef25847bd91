#include "runtime/ir/dump.hpp"

#include <charconv>
#include <cmath>
#include <filesystem>
#include <type_traits>
#include <variant>

#include "runtime/ir/ir.hpp"

namespace snell::ir {

std::string num(double v) {
  if (v == 0) return "0";  // also folds -0
  char buf[32];
  auto res = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, res.ptr);
}

namespace {

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

std::string to_string(const SourceRef& ref, const Scene& scene) {
  if (ref.line == 0) return "<built-in>";
  std::string file = ref.file < scene.files.size() ? scene.files[ref.file] : "?";
  return file + ":" + std::to_string(ref.line) + ":" + std::to_string(ref.col);
}

namespace {
// " name value" for each field, in the struct's order: numbers shortest
// round-trip, vectors <x, y, z>, textures as to_string(Texture), indices #N
// (uint32), integers (uint64) as written.
std::string field_text(double v) {
  return num(v);
}
std::string field_text(Vec3 v) {
  return to_string(v);
}
std::string field_text(const Texture& t) {
  return to_string(t);
}
std::string field_text(std::uint32_t index) {
  return "#" + std::to_string(index);
}
std::string field_text(std::uint64_t count) {  // a plain integer (a dielectric's priority)
  return std::to_string(count);
}
std::string field_text(bool b) {
  return b ? "true" : "false";
}
template <class E>
requires std::is_enum_v<E> std::string field_text(E e) {  // as the language spells it
  return "\"" + std::string(spelling(e)) + "\"";
}
template <class T>
std::string fields_text(const T& kind) {
  std::string s;
  for_each_field(kind, [&](const char* name, const auto& v) {
    s += " " + std::string(name) + " " + field_text(v);
  });
  return s;
}
template <class T>
std::string kind_text(const T& kind) {
  return std::string(KindName<T>::value) + " {" + fields_text(kind) + " }";
}
}  // namespace

std::string to_string(const Texture& t) {
  if (const Constant* c = std::get_if<Constant>(&t.pattern))
    return to_string(c->color);  // a plain colour prints as the colour
  std::string s = std::visit(
      [](const auto& p) {
        return std::string(KindName<std::decay_t<decltype(p)>>::value) + " {" + fields_text(p);
      },
      t.pattern);
  if (const FunctionPattern* f = std::get_if<FunctionPattern>(&t.pattern)) {
    std::string prog = to_string(f->program);  // one line per instruction
    for (char& c : prog)
      if (c == '\n') c = ';';
    while (!prog.empty() && (prog.back() == ';' || prog.back() == ' ')) prog.pop_back();
    s += " function { " + prog + " }";
  }
  // §15's common properties, where they differ from their defaults.
  if (!t.color_map.empty()) {
    s += " color_map {";
    for (const ColorStop& c : t.color_map)
      s += " stop <" + num(c.at) + ", " + to_string(c.color) + ">";
    s += " }";
  }
  if (t.turbulence != 0) s += " turbulence " + num(t.turbulence);
  if (t.octaves != Texture{}.octaves) s += " octaves " + std::to_string(t.octaves);
  if (!t.world_from_pattern.is_identity())
    s += " world_from_pattern " + to_string(t.world_from_pattern);
  if (t.space != PatternSpace::World) s += " space " + std::string(spelling(t.space));
  return s + " }";
}

std::string to_string(const Material& m) {
  std::string s = std::visit([](const auto& k) { return kind_text(k); }, m.model);
  if (m.bump.on()) {
    s.pop_back();  // the closing brace
    s += "bump <" + to_string(m.bump.pattern) + ", " + num(m.bump.amount) + "> }";
  }
  return s;
}

namespace {
std::string motion_text(const std::vector<TransformOp>& ops, bool has_pivot, Vec3 pivot) {
  std::string s = "{";
  for (const TransformOp& op : ops) {
    const char* k = op.kind == TransformOp::Kind::Translate ? " translate "
                    : op.kind == TransformOp::Kind::Rotate  ? " rotate "
                                                            : " scale ";
    s += k + to_string(op.value);
  }
  if (has_pivot) s += " pivot " + to_string(pivot);
  return s + " }";
}
}  // namespace

std::string to_string(const MotionBlock& b) {
  return "motion in " + to_string(b.world_from_frame) + " " +
         motion_text(b.ops, b.has_pivot, b.pivot);
}

// The world block, then the nested ones (§12, §13), outermost first, each in the
// frame it acts in.
std::string to_string(const Motion& m) {
  std::string s;
  if (!m.ops.empty() || m.nested.empty()) s = "motion " + motion_text(m.ops, m.has_pivot, m.pivot);
  for (const MotionBlock& b : m.nested) s += (s.empty() ? "" : " ") + to_string(b);
  return s;
}

std::string to_string(const Shape& sh) {
  std::string s = std::visit(
      [](const auto& g) {
        return std::string(KindName<std::decay_t<decltype(g)>>::value) + " {" + fields_text(g);
      },
      sh.geom);
  s += sh.material == kInheritMaterial ? std::string(" material inherit")
                                       : " material #" + std::to_string(sh.material);
  if (!sh.world_from_object().is_identity())
    s += " world_from_object " + to_string(sh.world_from_object());
  if (!sh.motion().empty()) s += " " + to_string(sh.motion());
  if (sh.in_object()) {
    s += " object_space { world_from_object " + to_string(sh.object_space().world_from_object);
    if (!sh.object_space().motion.empty()) s += " " + to_string(sh.object_space().motion);
    s += " }";
  }
  return s + " }";
}

std::string to_string(const MeshData& m) {
  std::string s = quoted(m.path) + " " + std::to_string(m.positions.size()) + " vertices " +
                  std::to_string(m.indices.size() / 3) + " triangles";
  if (m.smooth()) {
    std::size_t smooth = 0;
    for (std::size_t i = 0; i < m.normal_indices.size(); i += 3)
      smooth += m.normal_indices[i] != MeshData::kNoNormal;
    s += " " + std::to_string(m.normals.size()) + " normals " + std::to_string(smooth) +
         " smooth triangles";
  }
  if (!m.texcoord_indices.empty()) s += " " + std::to_string(m.texcoords.size()) + " texcoords";
  if (m.closed) return s + " closed";
  return s + (m.open_reason.empty() ? " open" : " open (" + m.open_reason + ")");
}

// The file's name only: the folder depends on where the scene was checked out.
std::string to_string(const ImageFile& f) {
  return "image_file { \"" + std::filesystem::path(f.path).filename().string() + "\" }";
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

namespace {
// A setting's value as the language writes it: enums as quoted spellings.
std::string setting_text(double v) {
  return num(v);
}
std::string setting_text(std::uint32_t v) {
  return std::to_string(v);
}
std::string setting_text(std::uint64_t v) {
  return std::to_string(v);
}
template <class E>
requires std::is_enum_v<E> std::string setting_text(E e) {
  return quoted(std::string(spelling(e)));
}
}  // namespace

std::string to_string(const Settings& s) {
  std::string out =
      "settings { resolution <" + std::to_string(s.width) + ", " + std::to_string(s.height) + ">";
  for_each_field(s, [&](const char* name, const auto& v) {
    out += " " + std::string(name) + " " + setting_text(v);
  });
  return out + " }";
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
    s += "mesh #" + std::to_string(i) + " " + to_string(scene.meshes[i]) + "\n";
  for (std::size_t i = 0; i < scene.images.size(); ++i)
    s += "image #" + std::to_string(i) + " " + to_string(scene.images[i]) + "\n";
  for (std::size_t i = 0; i < scene.shapes.size(); ++i)
    s += "shape #" + std::to_string(i) + " " + to_string(scene.shapes[i]) + "\n";
  for (std::size_t i = 0; i < scene.parts.size(); ++i)
    s += "part #" + std::to_string(i) + " " + to_string(scene.parts[i]) + "\n";
  for (std::size_t i = 0; i < scene.csg_nodes.size(); ++i)
    s += "csg #" + std::to_string(i) + " " + to_string(scene.csg_nodes[i]) + "\n";
  for (std::size_t i = 0; i < scene.prototypes.size(); ++i)
    s += "prototype #" + std::to_string(i) + " " + to_string(scene.prototypes[i]) + "\n";
  for (const PointLight& l : scene.point_lights) s += to_string(l) + "\n";
  for (const AreaLight& l : scene.area_lights) s += to_string(l) + "\n";
  return s;
}

std::string to_string(const CsgNode& n) {
  if (n.leaf()) return "leaf { part #" + std::to_string(n.part) + " }";
  std::string s = std::string(spelling(n.op)) + " {";
  for (std::uint32_t c : n.children) s += " #" + std::to_string(c);
  return s + " }";
}

std::string to_string(const Prototype& p) {
  std::string s = "{ parts";
  for (std::uint32_t c : p.parts) s += " #" + std::to_string(c);
  return s + " box " + to_string(p.lo) + " " + to_string(p.hi) + " }";
}

}  // namespace snell::ir
