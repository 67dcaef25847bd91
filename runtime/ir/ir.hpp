// The scene IR: the plain-data contract between the compiler and the runtime.
// All geometry is in double precision and world units; the runtime converts to
// float only after moving the world so the camera sits at the origin.
// Every item carries the source place it came from, so the runtime can say
// "the light at glass.scn:12:3 ..." without knowing the language.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/ir/enums.hpp"
#include "runtime/ir/materials.hpp"
#include "runtime/ir/math.hpp"
#include "runtime/ir/shapes.hpp"
#include "runtime/ir/source_ref.hpp"

namespace snell::ir {

struct PointLight {
  Vec3 position;
  Vec3 intensity{1, 1, 1};  // radiant intensity per channel
  SourceRef src;
  // The properties that are one field each (compiler/properties.def binds their
  // defaults by name).
  static constexpr auto fields() { return std::tuple{field("intensity", &PointLight::intensity)}; }
};

struct AreaLight {
  Vec3 corner;
  Vec3 edge1{1, 0, 0};
  Vec3 edge2{0, 0, 1};
  Vec3 radiance{1, 1, 1};
  std::uint32_t samples_u = 1, samples_v = 1;  // jittered grid of shadow rays
  bool two_sided = false;                      // otherwise emits only towards cross(edge1, edge2)
  SourceRef src;
  // samples is two fields (samples_u, samples_v).
  static constexpr auto fields() { return std::tuple{field("two_sided", &AreaLight::two_sided)}; }
};

struct Camera {
  Vec3 location{0, 0, 0};
  Vec3 look_at{0, 0, 1};
  Vec3 up{0, 1, 0};
  double fov = 60;            // horizontal, degrees
  double aperture = 0;        // lens diameter; 0 = pinhole
  double focal_distance = 1;  // lowering fills in |look_at - location| when unset
  double shutter_open = 0, shutter_close = 0;
  SourceRef src;
  // shutter is two fields; focal_distance has no default (lowering fills it in).
  static constexpr auto fields() {
    return std::tuple{field("location", &Camera::location), field("look_at", &Camera::look_at),
                      field("up", &Camera::up), field("fov", &Camera::fov),
                      field("aperture", &Camera::aperture)};
  }
};

// Settings enums (kinds.def, enums.hpp). Branching: how a dielectric hit continues
// the ray tree: trace both the reflected and the refracted ray ("split", the
// lecture's tree), or one of them chosen with probability R and 1 − R, weighted so
// the estimate stays unbiased ("stochastic"). Termination: what happens to a
// branch whose weight falls below min_weight: dropped ("cutoff", biased dark) or
// continued with probability weight/min_weight and reweighted ("roulette",
// Russian roulette: unbiased, noisier).

struct Settings {
  std::uint32_t width = 640, height = 480;
  std::uint32_t samples = 1;  // camera rays per pixel
  SamplerKind sampler = SamplerKind::Stratified;
  std::uint32_t max_depth = 8;
  double min_weight = 0.001;
  FresnelMode fresnel = FresnelMode::Exact;
  Branching branching = Branching::Split;
  Termination termination = Termination::Cutoff;
  LightSampling light_sampling = LightSampling::Area;
  GlossySampling glossy_sampling = GlossySampling::Mis;
  std::uint64_t seed = 0;
  IntegratorKind integrator = IntegratorKind::Whitted;
  SourceRef src;
  // The settings properties that are one field each (resolution is two: width
  // and height); compiler/properties.def binds them by name.
  static constexpr auto fields() {
    return std::tuple{field("samples", &Settings::samples),
                      field("sampler", &Settings::sampler),
                      field("max_depth", &Settings::max_depth),
                      field("min_weight", &Settings::min_weight),
                      field("fresnel", &Settings::fresnel),
                      field("branching", &Settings::branching),
                      field("termination", &Settings::termination),
                      field("light_sampling", &Settings::light_sampling),
                      field("glossy_sampling", &Settings::glossy_sampling),
                      field("seed", &Settings::seed),
                      field("integrator", &Settings::integrator)};
  }
};

// §17: an image file a scene's `image` patterns read (the compiler has checked it
// exists; the runtime's texture system opens it, runtime/shading/image_texture.hpp).
struct ImageFile {
  std::string path;
  SourceRef src;  // the `file` property that named it first
};

struct Scene {
  std::vector<std::string> files;  // SourceRef::file indexes this
  Settings settings;
  Camera camera;
  // §17: a colour or a pattern (an image) evaluated at the escaping ray's unit
  // direction; never lights diffuse surfaces.
  Texture background{Vec3{0, 0, 0}};
  SourceRef background_src;  // the `background` statement, when there is one
  std::vector<Material> materials;
  std::vector<Shape> shapes;
  // §12-§13: what CSG objects and instances are made of. A part's world_from_object
  // places it in its CSG object's or prototype's space.
  std::vector<Shape> parts;
  std::vector<CsgNode> csg_nodes;
  std::vector<Prototype> prototypes;
  std::vector<MeshData> meshes;
  std::vector<ImageFile> images;  // §17, indexed by ImageTexture::image
  std::vector<PointLight> point_lights;
  std::vector<AreaLight> area_lights;
};

// Whether `pred(part)` holds for a leaf of the CSG tree at `root`, the leaves in
// the order written (Scene::parts[part]); stops at the first that does. Children
// come before their parents (validate), so only such links are followed: the walk
// ends on any tree. A stack of its own, as trees may be deep.
template <class P>
bool any_csg_leaf(const Scene& scene, std::uint32_t root, P&& pred) {
  std::vector<std::uint32_t> todo{root};
  while (!todo.empty()) {
    std::uint32_t i = todo.back();
    todo.pop_back();
    if (i >= scene.csg_nodes.size()) continue;
    const CsgNode& n = scene.csg_nodes[i];
    if (n.leaf()) {
      if (n.part < scene.parts.size() && pred(n.part)) return true;
      continue;
    }
    for (auto it = n.children.rbegin(); it != n.children.rend(); ++it)
      if (*it < i) todo.push_back(*it);
  }
  return false;
}

// The materials of the surfaces `shape` shows, in the order written: its own; a
// CSG object's leaves'; an instance's parts' (a part without one takes the
// instance's, `inherited` here). Not the material a CSG block or instance carries
// only for its children to inherit.
template <class F>
void surface_materials(const Scene& scene, const Shape& shape, F&& f,
                       std::uint32_t inherited = kInheritMaterial) {
  const std::uint32_t own = shape.material == kInheritMaterial ? inherited : shape.material;
  if (const Csg* c = shape.as<Csg>()) {
    any_csg_leaf(scene, c->node, [&](std::uint32_t part) {
      std::uint32_t m = scene.parts[part].material;
      f(m == kInheritMaterial ? own : m);
      return false;
    });
  } else if (const Instance* in = shape.as<Instance>()) {
    if (in->prototype < scene.prototypes.size())
      for (std::uint32_t p : scene.prototypes[in->prototype].parts)
        if (p < scene.parts.size()) surface_materials(scene, scene.parts[p], f, own);
  } else {
    f(own);
  }
}

// Whether anything of `s` moves: its own motion, or (§12) a leaf of its CSG tree,
// which may move inside the CSG object.
bool moves(const Shape& s, const Scene& scene);

// The effects a scene uses (architecture: "simulate only the effects a scene calls
// for"), computed from the IR alone, each with the reason it is on.
struct Features {
  bool motion_blur = false;     // shutter open AND some object moves
  bool depth_of_field = false;  // aperture > 0
  bool point_lights = false;
  bool area_lights = false;
  bool mirror = false;
  bool glossy = false;
  bool dielectric = false;
  bool absorption = false;  // some dielectric absorbs (absorb > 0)
  bool interiors = false;   // some dielectric has a priority (§14): rays track media
  bool glazed = false;
  bool highlights = false;  // some diffuse or glazed has specular > 0 (§16)
  bool textures = false;    // some colour is a pattern
  bool bumps = false;       // some material has a bump (§16): shading normals from patterns
  bool finish = false;      // highlights or bumps: §16's kernel axis
  std::vector<std::pair<std::string, std::string>> reasons;  // (effect, why)

  static Features all();  // every effect on: the general kernel
};

Features analyze_features(const Scene& scene);

// What the runtime can trace: it works in float around the camera; Embree drops
// geometry and rejects rays beyond 1.8e18 (FLT_LARGE), and its triangle test
// overflows float (t = inf) on triangles ~1e13 across (edge³ > 3.4e38). Every
// object's bounds, light and lens point must lie within kMaxCameraDistance of the
// camera (planes: the plane's nearest point); radiometric values (colours,
// intensity, radiance, background) are at most kMaxRadiometric.
inline constexpr double kMaxCameraDistance = 1e12;
inline constexpr double kMaxRadiometric = 1e30;

// One thing the runtime cannot take, and the item that has it (line 0: no source).
struct Problem {
  SourceRef src;
  std::string what;
};
std::string to_string(const Problem& p, const Scene& scene);  // "file:line:col: error: ..."

// Structural checks the runtime relies on (indices in range, finite numbers,
// positive sizes, the ranges above). Empty when valid.
std::vector<Problem> validate(const Scene& scene);

std::string to_string(const SourceRef& ref, const Scene& scene);
std::string to_string(const Texture& t);
std::string to_string(const Material& m);
std::string to_string(const MotionBlock& b);
std::string to_string(const Motion& m);
std::string to_string(const Shape& s);
std::string to_string(const MeshData& m);
std::string to_string(const ImageFile& f);
std::string to_string(const CsgNode& n);
std::string to_string(const Prototype& p);
std::string to_string(const PointLight& l);
std::string to_string(const AreaLight& l);
std::string to_string(const Camera& c);
std::string to_string(const Settings& s);
std::string to_string(const Features& f);
// A stable text dump of the whole scene (`snell render --dump-ir`).
std::string to_string(const Scene& scene);

}  // namespace snell::ir
