#include "compiler/lower.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <new>

#include "compiler/ir_binding.hpp"
#ifdef __linux__
#include <sys/mman.h>
#endif

namespace snell::compile {

using lang::DiagKind;
using lang::Span;

namespace {

const EvaluatedProp* get(const std::vector<EvaluatedProp>& props, PropId id) {
  return find_evaluated(props, id);
}

ir::Vec3 vec(const std::vector<EvaluatedProp>& props, PropId id) {
  return get(props, id)->value.v;
}

double num(const std::vector<EvaluatedProp>& props, PropId id) {
  return get(props, id)->value.n;
}

}  // namespace

// The transform ops of `props` (translate/rotate/scale, in the order written):
// each later op applies after the earlier ones.
ir::Transform object_transforms(const std::vector<EvaluatedProp>& props) {
  ir::Transform t;
  for (const EvaluatedProp& p : props) {
    switch (p.info->type) {
      case PropType::Translate:
        t = ir::Transform::translate(p.value.v) * t;
        break;
      case PropType::Rotate:
        t = ir::Transform::rotate_xyz(p.value.v) * t;
        break;
      case PropType::Scale:
        t = ir::Transform::scale(p.value.v) * t;
        break;
      default:
        break;
    }
  }
  return t;
}

ir::Motion object_motion(const EvaluatedProp* motion) {
  ir::Motion m;
  if (!motion) return m;
  for (const EvaluatedProp& op : motion->nested) {
    if (op.info->type == PropType::Vec3) {  // §19 pivot, wherever it is written
      m.has_pivot = true;
      m.pivot = op.value.v;
      continue;
    }
    ir::TransformOp t;
    t.kind = op.info->type == PropType::Translate ? ir::TransformOp::Kind::Translate
             : op.info->type == PropType::Rotate  ? ir::TransformOp::Kind::Rotate
                                                  : ir::TransformOp::Kind::Scale;
    t.value = op.value.v;
    m.ops.push_back(t);
  }
  return m;
}

const EvaluatedProp* find_evaluated(const std::vector<EvaluatedProp>& props, PropId id) {
  for (const EvaluatedProp& p : props)
    if (p.info->id == static_cast<std::int32_t>(id)) return &p;
  return nullptr;
}

SceneBuilder::SceneBuilder(const lang::SourceManager& sources, lang::DiagnosticEngine& diags)
    : sources_(sources), diags_(diags) {}

ir::SourceRef SceneBuilder::ref(Span span) const {
  if (span.file >= sources_.size()) return {};
  for (const RefCache& c : ref_cache_)
    if (c.span.file == span.file && c.span.begin == span.begin) return c.ref;
  lang::LineCol lc = sources_.file(span.file).line_col(span.begin);
  RefCache& c = ref_cache_[ref_next_++ & 1];
  c.span = span;
  c.ref = {span.file, lc.line, lc.col};
  return c.ref;
}

bool SceneBuilder::first_of_kind(std::string_view kind, Span span) {
  auto [it, inserted] = singletons_.try_emplace(std::string(kind), span);
  if (inserted) return true;
  diags_
      .report(DiagKind::DuplicateSceneItem, span,
              "a scene has at most one '" + std::string(kind) + "'")
      .note(it->second, "the first one is here");
  return false;
}

namespace {
// FNV-1a over every number of a kind struct, textures included (fields.hpp).
struct Hasher {
  std::uint64_t h = 0xcbf29ce484222325ull;
  void mix(std::uint64_t x) { h = (h ^ x) * 0x100000001b3ull; }
  void operator()(double d) {
    if (d == 0) d = 0;  // -0 and +0 compare equal, so they must hash equal
    std::uint64_t x;
    std::memcpy(&x, &d, sizeof x);
    mix(x);
  }
  void operator()(ir::Vec3 v) { (*this)(v.x), (*this)(v.y), (*this)(v.z); }
  template <class E>
  requires std::is_enum_v<E>
  void operator()(E e) { mix(std::uint64_t(e)); }
  void operator()(const ir::Texture& t) {
    mix(t.pattern.index() << 7);
    std::visit([&](const auto& p) { fields(p); }, t.pattern);
    for (const ir::ColorStop& c : t.color_map) (*this)(c.at), (*this)(c.color);
    if (const auto* f = std::get_if<ir::FunctionPattern>(&t.pattern)) {
      mix(f->program.code.size());
      for (double c : f->program.constants) (*this)(c);
    }
    (*this)(t.turbulence);
    mix(t.octaves), mix(std::uint64_t(t.space));
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 4; ++c) (*this)(t.world_from_pattern.m(r, c));
  }
  template <class T>
  void fields(const T& kind) {
    ir::for_each_field(kind, [&](const char*, const auto& v) { (*this)(v); });
  }
};
}  // namespace

std::uint64_t SceneBuilder::material_hash(const ir::Material& m) {
  Hasher hs;
  hs.mix(m.model.index());
  std::visit([&](const auto& k) { hs.fields(k); }, m.model);
  if (m.bump.on()) hs(m.bump.pattern), hs(m.bump.amount);
  std::uint64_t h = hs.h;
  h = (h ^ (h >> 30)) * 0xBF58476D1CE4E5B9ull;  // SplitMix64 finaliser: spread all bits
  h = (h ^ (h >> 27)) * 0x94D049BB133111EBull;
  return h ^ (h >> 31);
}

std::uint32_t SceneBuilder::material_index(const ir::Material& m) {
  if (2 * (material_count_ + 1) > material_slots_.size()) {
    std::vector<MaterialSlot> old = std::move(material_slots_);
    material_slots_.assign(std::max<std::size_t>(64, old.size() * 2), MaterialSlot{});
    std::size_t mask = material_slots_.size() - 1;
    for (const MaterialSlot& slot : old) {
      if (slot.index == 0) continue;
      std::size_t i = slot.hash & mask;
      while (material_slots_[i].index != 0) i = (i + 1) & mask;
      material_slots_[i] = slot;
    }
  }
  std::uint64_t h = material_hash(m);
  std::size_t mask = material_slots_.size() - 1;
  std::size_t i = h & mask;
  while (material_slots_[i].index != 0) {
    const MaterialSlot& slot = material_slots_[i];
    if (slot.hash == h && scene_.materials[slot.index - 1].same_as(m)) return slot.index - 1;
    i = (i + 1) & mask;
  }
  scene_.materials.push_back(m);
  prefault(scene_.materials, materials_prefault_);
  ++material_count_;
  material_slots_[i] = {h, static_cast<std::uint32_t>(scene_.materials.size())};
  return material_slots_[i].index - 1;
}

namespace {
template <class T>
void reserve_for(std::vector<T>& v, std::size_t n) {
  std::size_t want = std::min(v.size() + n, kMaxSceneObjects);
  if (want <= v.capacity()) return;
  try {
    v.reserve(std::max(want, 2 * v.capacity()));
  } catch (const std::bad_alloc&) {
    // No address space for the hint (strict overcommit): grow as usual instead.
  }
}
}  // namespace

// Faults in the next few MiB of a vector's reserved room with one madvise
// (MADV_POPULATE_WRITE, Linux 5.14) instead of one page fault per 4 KiB as the
// vector fills: about a third less system time for a million objects. Runs
// ahead of the used part by at most one window, so resident memory grows as
// before; without the call (other systems, older kernels) nothing changes.
template <class T>
void SceneBuilder::prefault(const std::vector<T>& v, Prefault& pf) {
#if defined(__linux__) && defined(MADV_POPULATE_WRITE)
  constexpr std::size_t kWindow = std::size_t{4} << 20, kPage = 4096;
  static bool supported = true;
  if (!supported) return;
  if (v.data() != pf.base) pf = {v.data(), 0};
  std::size_t used = v.size() * sizeof(T), cap = v.capacity() * sizeof(T);
  if (used + kWindow / 2 < pf.done || cap < 2 * kWindow) return;
  auto base = reinterpret_cast<std::uintptr_t>(v.data());
  std::uintptr_t from = (base + std::max(used, pf.done) + kPage - 1) & ~(kPage - 1);
  std::uintptr_t to = std::min(base + used + kWindow, base + cap) & ~(kPage - 1);
  if (to > from && madvise(reinterpret_cast<void*>(from), to - from, MADV_POPULATE_WRITE) != 0)
    supported = false;
  pf.done = to - base;
#else
  (void)v, (void)pf;
#endif
}

void SceneBuilder::expect_objects(std::size_t n) {
  reserve_for(scene_.shapes, n);
  // Each object may bring a new material (distinct colours); one that reuses a
  // material leaves this room untouched.
  reserve_for(scene_.materials, n);
}

void SceneBuilder::set_background(const Value& color, Span span) {
  if (!first_of_kind("background", span)) return;
  assign(scene_.background, color);
  scene_.background_src = ref(span);
}

void SceneBuilder::add_item(const BlockInfo& block, Span kw,
                            const std::vector<EvaluatedProp>& props) {
  if (block.shape_kind >= 0) {
    add_object(block, kw, props);
    return;
  }
  // The few singleton and light items (shapes are kinds, found above).
  std::string_view n = block.name;
  if (n == "settings") {
    if (!first_of_kind(n, kw)) return;
    scene_.settings.src = ref(kw);
    apply_settings(props);
  } else if (n == "camera") {
    if (!first_of_kind(n, kw)) return;
    scene_.camera.src = ref(kw);
    apply_camera(props);
  } else if (n == "point_light") {
    ir::PointLight l;
    l.position = vec(props, PropId::point_light_position);
    l.intensity = vec(props, PropId::point_light_intensity);
    l.src = ref(kw);
    scene_.point_lights.push_back(l);
  } else if (n == "area_light") {
    ir::AreaLight l;
    l.corner = vec(props, PropId::area_light_corner);
    l.edge1 = vec(props, PropId::area_light_edge1);
    l.edge2 = vec(props, PropId::area_light_edge2);
    l.radiance = vec(props, PropId::area_light_radiance);
    ir::Vec3 s = vec(props, PropId::area_light_samples);
    l.samples_u = static_cast<std::uint32_t>(s.x);
    l.samples_v = static_cast<std::uint32_t>(s.y);
    l.two_sided = get(props, PropId::area_light_two_sided)->value.truth();
    l.src = ref(kw);
    // Each fault is reported (§10: independent errors), then the light is left out.
    bool ok = check_light_area(props);
    ok = check_light_samples(props) && ok;
    if (ok) scene_.area_lights.push_back(l);
  }
}

void SceneBuilder::apply_settings(const std::vector<EvaluatedProp>& props) {
  for (const EvaluatedProp& p : props) override_setting(*p.info, p.value);
}

void SceneBuilder::override_setting(const PropInfo& prop, const Value& v) {
  ir::Settings& s = scene_.settings;
  if (prop.id == static_cast<std::int32_t>(PropId::settings_resolution)) {
    s.width = static_cast<std::uint32_t>(v.v.x);
    s.height = static_cast<std::uint32_t>(v.v.y);
    return;
  }
  // Every other setting is the ir::Settings field of its name (properties.def).
  ir::for_each_field(s, [&](const char* field, auto& f) {
    if (prop.name == field) assign(f, v);
  });
}

void SceneBuilder::apply_camera(const std::vector<EvaluatedProp>& props) {
  ir::Camera& c = scene_.camera;
  c.location = vec(props, PropId::camera_location);
  c.look_at = vec(props, PropId::camera_look_at);
  c.up = vec(props, PropId::camera_up);
  c.fov = num(props, PropId::camera_fov);
  c.aperture = num(props, PropId::camera_aperture);
  ir::Vec3 shutter = vec(props, PropId::camera_shutter);
  c.shutter_open = shutter.x;
  c.shutter_close = shutter.y;
  if (const EvaluatedProp* fd = get(props, PropId::camera_focal_distance)) {
    c.focal_distance = fd->value.n;
    focal_distance_set_ = true;
  }
  if (!check_camera_view(props)) {
    // Reported: a view that ir::validate takes, so it is not said twice (the scene
    // has an error and is not rendered).
    c.location = {0, 0, 0}, c.look_at = {0, 0, 1}, c.up = {0, 1, 0};
  }
}

bool SceneBuilder::check_camera_view(const std::vector<EvaluatedProp>& props, bool with_up) {
  const ir::Vec3 location = vec(props, PropId::camera_location),
                 look_at = vec(props, PropId::camera_look_at), up = vec(props, PropId::camera_up);
  const ir::Vec3 fwd = look_at - location;
  const EvaluatedProp* at = get(props, PropId::camera_look_at);
  if (ir::length(fwd) == 0) {
    diags_.report(DiagKind::InvalidValue, at->value_span,
                  "the camera's 'look_at' equals its 'location': no view direction");
    return false;
  }
  if (with_up && ir::length(ir::cross(fwd, up)) == 0) {
    diags_
        .report(DiagKind::InvalidValue, get(props, PropId::camera_up)->value_span,
                "the camera's 'up' is parallel to its view direction")
        .note(at->value_span, "view direction is " + ir::to_string(ir::normalize(fwd)));
    return false;
  }
  return true;
}

bool SceneBuilder::check_light_samples(const std::vector<EvaluatedProp>& props) {
  const ir::Vec3 s = vec(props, PropId::area_light_samples);
  if (std::uint64_t(s.x) * std::uint64_t(s.y) <= 65536) return true;
  diags_.report(DiagKind::InvalidValue, get(props, PropId::area_light_samples)->value_span,
                "an area light takes at most 65536 shadow samples per point");
  return false;
}

bool SceneBuilder::check_light_area(const std::vector<EvaluatedProp>& props) {
  const ir::Vec3 e1 = vec(props, PropId::area_light_edge1),
                 e2 = vec(props, PropId::area_light_edge2);
  if (ir::length(ir::cross(e1, e2)) != 0) return true;
  diags_
      .report(DiagKind::InvalidValue, get(props, PropId::area_light_edge2)->value_span,
              "'edge1' and 'edge2' of an area light must span a non-zero area")
      .note(get(props, PropId::area_light_edge1)->value_span, "edge1 is " + ir::to_string(e1));
  return false;
}

void SceneBuilder::check_item_rest(const BlockInfo& block, Span kw,
                                   const std::vector<EvaluatedProp>& props,
                                   const std::bitset<kPropCount>& failed) {
  (void)kw;
  auto judged = [&](std::initializer_list<PropId> ids) {
    for (PropId id : ids)
      if (failed.test(static_cast<std::size_t>(id))) return false;
    return true;
  };
  if (block.name == "camera" && judged({PropId::camera_location, PropId::camera_look_at})) {
    check_camera_view(props, judged({PropId::camera_up}));
  } else if (block.name == "area_light") {
    if (judged({PropId::area_light_edge1, PropId::area_light_edge2})) check_light_area(props);
    if (judged({PropId::area_light_samples})) check_light_samples(props);
  }
}

void SceneBuilder::add_object(const BlockInfo& block, Span kw,
                              const std::vector<EvaluatedProp>& props) {
  // Built in place (a Shape is ~370 bytes; a million of them copied once more
  // is measurable) and taken back out if a check below fails.
  ir::Shape& s = scene_.shapes.emplace_back();
  s.src = ref(kw);
  LowerContext cx{*this, kw, props, diags_};
  if (!lower_shape(block, cx, s.geom)) {
    scene_.shapes.pop_back();
    return;
  }
  s.material = get(props, PropId::object_material) ? material_of(props, 0) : default_material();
  s.set_world_from_object(object_transforms(props));
  if (const EvaluatedProp* m = get(props, PropId::object_motion)) s.set_motion(object_motion(m));
  prefault(scene_.shapes, shapes_prefault_);
}

std::uint32_t SceneBuilder::default_material() {
  if (default_material_ < 0) default_material_ = material_index(ir::Material{});
  return static_cast<std::uint32_t>(default_material_);
}

std::uint32_t SceneBuilder::material_of(const std::vector<EvaluatedProp>& props,
                                        std::uint32_t inherited) {
  const EvaluatedProp* mat = get(props, PropId::object_material);
  if (!mat) return inherited;
  std::uint32_t i = material_index(mat->value.mat());
  if (!scene_.materials[i].src.line) scene_.materials[i].src = ref(mat->value_span);
  return i;
}

// SceneBuilder::load_mesh is in mesh_load.cpp.

ir::Scene SceneBuilder::finish() {
  if (!focal_distance_set_)
    scene_.camera.focal_distance = ir::length(scene_.camera.look_at - scene_.camera.location);
  if (!(scene_.camera.focal_distance > 0)) scene_.camera.focal_distance = 1;
  scene_.files.clear();
  for (std::size_t i = 0; i < sources_.size(); ++i)
    scene_.files.push_back(sources_.file(static_cast<lang::FileId>(i)).path());
  return std::move(scene_);
}

}  // namespace snell::compile
