// The scene IR: the plain-data contract between the compiler and the runtime.
// All geometry is in double precision and world units; the runtime converts to
// float only after moving the world so the camera sits at the origin.
// Every item carries the source place it came from, so the runtime can say
// "the light at glass.scn:12:3 ..." without knowing the language.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "runtime/ir/math.hpp"

namespace snell::ir {

// Where an IR item was written: an index into Scene::files, line and column.
struct SourceRef {
  std::uint32_t file = 0;
  std::uint32_t line = 0;  // 0: made in C++, not from a scene file
  std::uint32_t col = 0;
};

// A colour parameter: a constant or a pattern evaluated at the hit point (§8).
struct Texture {
  enum class Kind : std::uint8_t { Constant, Checker };
  Kind kind = Kind::Constant;
  Vec3 color{0.8, 0.8, 0.8};  // Constant; Checker: color1 (even cells)
  Vec3 color2{0, 0, 0};       // Checker: odd cells
  double size = 1;            // Checker: cell side
  bool operator==(const Texture&) const = default;
};

enum class MaterialKind : std::uint8_t { Diffuse, Mirror, Glossy, Dielectric, Glazed };

struct Material {
  MaterialKind kind = MaterialKind::Diffuse;
  Texture color;         // Diffuse, Mirror, Glossy, Glazed base
  double blur = 0;       // Glossy: side of the perturbation square
  double ior = 1.5;      // Dielectric, Glazed
  Vec3 absorb{0, 0, 0};  // Dielectric: Beer coefficient per channel, per scene unit
  SourceRef src;
  // Equality ignores src: the materials table is deduplicated by value.
  bool same_as(const Material& o) const {
    return kind == o.kind && color == o.color && blur == o.blur && ior == o.ior &&
           absorb == o.absorb;
  }
};

// One transform step of a `motion { }` block (§8).
struct TransformOp {
  enum class Kind : std::uint8_t { Translate, Rotate, Scale };
  Kind kind = Kind::Translate;
  Vec3 value;
};

// How an object moves during the shutter interval. At time fraction u in [0, 1]
// (0 = shutter open, 1 = shutter close) each op is applied partially: translate
// u·V, rotate u·R (degrees, x then y then z), scale (1-u) + u·S. The object's
// transform at u is motion_at(u) * world_from_object.
struct Motion {
  std::vector<TransformOp> ops;
  bool moves() const;
  Transform at(double u) const;
};

enum class ShapeKind : std::uint8_t { Sphere, Plane, Box, Triangle, Mesh };

struct Shape {
  ShapeKind kind = ShapeKind::Sphere;
  // Object-space definition, as written in the block.
  Vec3 center;                  // Sphere
  double radius = 1;            // Sphere
  Vec3 normal{0, 1, 0};         // Plane: unit length (normalised by lowering)
  double distance = 0;          // Plane: points p with dot(p, normal) = distance
  Vec3 min, max;                // Box
  Vec3 a, b, c;                 // Triangle
  std::uint32_t mesh = 0;       // Mesh: index into Scene::meshes
  std::uint32_t material = 0;   // index into Scene::materials
  Transform world_from_object;  // the object's transforms, in the order written
  Motion motion;
  SourceRef src;
};

struct Mesh {
  std::string path;                    // as resolved on disk
  std::vector<Vec3> positions;         // object space
  std::vector<std::uint32_t> indices;  // three per triangle
};

struct PointLight {
  Vec3 position;
  Vec3 intensity{1, 1, 1};  // radiant intensity per channel
  SourceRef src;
};

struct AreaLight {
  Vec3 corner;
  Vec3 edge1{1, 0, 0};
  Vec3 edge2{0, 0, 1};
  Vec3 radiance{1, 1, 1};
  std::uint32_t samples_u = 1, samples_v = 1;  // jittered grid of shadow rays
  bool two_sided = false;                      // otherwise emits only towards cross(edge1, edge2)
  SourceRef src;
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
};

enum class SamplerKind : std::uint8_t { Independent, Stratified, Sobol };
enum class FresnelMode : std::uint8_t { Exact, Schlick };
// How a dielectric hit continues the ray tree: trace both the reflected and the
// refracted ray ("split", the lecture's tree), or one of them chosen with
// probability R and 1 − R, weighted so the estimate stays unbiased ("stochastic").
enum class Branching : std::uint8_t { Split, Stochastic };
// What happens to a branch whose weight falls below min_weight: dropped
// ("cutoff", biased dark) or continued with probability weight/min_weight and
// reweighted ("roulette", Russian roulette: unbiased, noisier).
enum class Termination : std::uint8_t { Cutoff, Roulette };

struct Settings {
  std::uint32_t width = 640, height = 480;
  std::uint32_t samples = 1;  // camera rays per pixel
  SamplerKind sampler = SamplerKind::Stratified;
  std::uint32_t max_depth = 8;
  double min_weight = 0.001;
  FresnelMode fresnel = FresnelMode::Exact;
  Branching branching = Branching::Split;
  Termination termination = Termination::Cutoff;
  std::uint64_t seed = 0;
  SourceRef src;
};

struct Scene {
  std::vector<std::string> files;  // SourceRef::file indexes this
  Settings settings;
  Camera camera;
  Vec3 background{0, 0, 0};
  std::vector<Material> materials;
  std::vector<Shape> shapes;
  std::vector<Mesh> meshes;
  std::vector<PointLight> point_lights;
  std::vector<AreaLight> area_lights;
};

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
  bool glazed = false;
  bool textures = false;                                     // some colour is a pattern
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
std::string to_string(const Shape& s);
std::string to_string(const PointLight& l);
std::string to_string(const AreaLight& l);
std::string to_string(const Camera& c);
std::string to_string(const Settings& s);
std::string to_string(const Features& f);
std::string to_string(SamplerKind k);
std::string to_string(FresnelMode m);
std::string to_string(Branching b);
std::string to_string(Termination t);
std::string to_string(MaterialKind k);
std::string to_string(ShapeKind k);
// A stable text dump of the whole scene (`snell render --dump-ir`).
std::string to_string(const Scene& scene);

}  // namespace snell::ir
