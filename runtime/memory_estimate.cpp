#include "runtime/memory_estimate.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cmath>

#include "runtime/geometry/motion.hpp"
#include "runtime/image_format.hpp"
#include "runtime/shading/image_texture.hpp"  // kTextureCacheMB

namespace snell::rt {

namespace {

// Measured on this machine (peak RSS of `snell render` at 1×1 pixel minus that of
// `snell check`, Debian 12's Embree 3): 1 M spheres add 312 MB (48 bytes each in
// the sphere set, the rest Embree's BVH), a 1 M-triangle mesh 292 MB, one sphere
// 143 MB of libraries, threads and the image module. Other shapes keep both
// matrices per object (local_set.hpp) and were measured at 573 MB a million
// before the sphere set shrank. The constants round those up.
constexpr std::uint64_t kFixed = 160'000'000;
constexpr std::uint64_t kPerSphere = 256;
constexpr std::uint64_t kPerShape = 512;
// An instance is an Embree instance geometry of its own besides the shape: 1.5 KB
// each measured (300 k flattened instances of nested values: 460 MB).
constexpr std::uint64_t kPerInstance = 1536;
constexpr std::uint64_t kPerTriangle = 192;
// A moving box, triangle or mesh is one Embree geometry with a vertex buffer per
// time step (up to 129: embree_scene.cpp add_moving_triangles) and a BVH over the
// steps: 170 KB for a box turning 90° (12 triangles, 129 steps) measured, 12
// bytes a vertex and ~75 a triangle per step. 8000 such boxes took 1.67 GB where
// 4 MB were counted.
constexpr std::uint64_t kPerMovingTriangleStep = 3 * 12 + 80;

std::uint64_t moving_triangles(const ir::Scene& scene) {
  if (!(scene.camera.shutter_close > scene.camera.shutter_open)) return 0;  // traced still
  std::uint64_t bytes = 0;
  std::vector<ir::Vec3> corners;
  for (const ir::Shape& s : scene.shapes) {
    if (!s.motion().moves()) continue;
    std::uint64_t tris = 0;
    corners.clear();
    if (const ir::Box* b = s.as<ir::Box>()) {
      for (int i = 0; i < 8; ++i)
        corners.push_back({i & 1 ? b->max.x : b->min.x, i & 2 ? b->max.y : b->min.y,
                           i & 4 ? b->max.z : b->min.z});
      tris = 12;
    } else if (const ir::Triangle* t = s.as<ir::Triangle>()) {
      corners = {t->a, t->b, t->c};
      tris = 1;
    } else if (const ir::Mesh* m = s.as<ir::Mesh>(); m && m->mesh < scene.meshes.size()) {
      const ir::MeshData& d = scene.meshes[m->mesh];
      const std::size_t stride = std::max<std::size_t>(1, d.positions.size() / 64);
      for (std::size_t i = 0; i < d.positions.size(); i += stride)
        corners.push_back(d.positions[i]);
      tris = d.indices.size() / 3;
    } else {
      continue;
    }
    const unsigned segs = geom::motion_segments(s, corners, scene.camera.location);
    bytes += std::uint64_t(segs + 1) * tris * kPerMovingTriangleStep;
  }
  return bytes;
}

}  // namespace

MemoryEstimate estimate_memory(const ir::Scene& scene, std::uint64_t width, std::uint64_t height,
                               const std::vector<std::string>& outputs) {
  MemoryEstimate e;
  const std::uint64_t pixels = width * height;
  e.film = pixels * 3 * sizeof(float);
  std::uint64_t triangles = 0;
  for (const ir::MeshData& m : scene.meshes) triangles += m.indices.size() / 3;
  // A box is 12 triangles of the triangle geometry, a triangle one, besides its
  // shape (300 k boxes took 866 MB where 314 MB were counted).
  for (const ir::Shape& s : scene.shapes)
    triangles += s.as<ir::Box>() ? 12 : s.as<ir::Triangle>() ? 1 : 0;
  std::uint64_t spheres =
      std::uint64_t(std::count_if(scene.shapes.begin(), scene.shapes.end(), [](const ir::Shape& s) {
        return s.as<ir::Sphere>() && !s.motion().moves();
      }));
  // A motion nested in others' (§12, §13) holds a frame (two matrices) and its
  // steps per block, per object, beyond what kPerShape rounds up.
  std::uint64_t nested = 0;
  auto count_nested = [&](const ir::Shape& s) {
    for (const ir::MotionBlock& b : s.motion().nested)
      nested += sizeof(ir::MotionBlock) + b.ops.size() * sizeof(ir::TransformOp);
  };
  for (const ir::Shape& s : scene.shapes) count_nested(s);
  for (const ir::Shape& s : scene.parts) count_nested(s);
  const std::uint64_t instances =
      std::uint64_t(std::count_if(scene.shapes.begin(), scene.shapes.end(),
                                  [](const ir::Shape& s) { return s.as<ir::Instance>(); }));
  e.geometry = kFixed + spheres * kPerSphere +
               (scene.shapes.size() + scene.parts.size() - spheres - instances) * kPerShape +
               instances * kPerInstance + triangles * kPerTriangle + nested +
               moving_triangles(scene);
  if (!scene.images.empty()) e.textures = std::uint64_t(kTextureCacheMB) << 20;
  // Encoded whole before it is written (atomic_file.hpp): at most its raw size
  // (zip and PNG's deflate seldom grow data, and then by a fraction of a percent).
  for (const std::string& out : outputs) {
    std::uint64_t raw = pixels * (lower_extension(out) == ".exr" ? 12 : 3);
    e.encode = std::max(e.encode, raw + raw / 100);
  }
  return e;
}

std::string MemoryEstimate::to_string() const {
  std::string s = format_bytes(total()) + " (film " + format_bytes(film) + ", geometry " +
                  format_bytes(geometry);
  if (textures) s += ", textures " + format_bytes(textures);
  if (encode) s += ", encoding " + format_bytes(encode);
  return s + ")";
}

std::uint64_t physical_memory() {
  long pages = ::sysconf(_SC_PHYS_PAGES), size = ::sysconf(_SC_PAGESIZE);
  return pages > 0 && size > 0 ? std::uint64_t(pages) * std::uint64_t(size) : 0;
}

std::string format_bytes(std::uint64_t bytes) {
  const char* unit[] = {"bytes", "KB", "MB", "GB", "TB"};
  double v = double(bytes);
  int u = 0;
  while (v >= 1000 && u < 4) v /= 1000, ++u;
  if (u == 0) return fmt::format("{} bytes", bytes);
  return fmt::format("{:.{}f} {}", v, v < 10 ? 1 : 0, unit[u]);
}

bool parse_bytes(const std::string& text, std::uint64_t& bytes) {
  std::size_t end = 0;
  double v = 0;
  try {
    v = std::stod(text, &end);
  } catch (const std::exception&) {
    return false;
  }
  std::string suffix = text.substr(end);
  for (char& c : suffix) c = char(std::toupper(static_cast<unsigned char>(c)));
  if (!suffix.empty() && suffix.back() == 'B' && suffix.size() > 1) suffix.pop_back();
  double scale = suffix.empty() || suffix == "B" ? 1
                 : suffix == "K"                 ? 1e3
                 : suffix == "M"                 ? 1e6
                 : suffix == "G"                 ? 1e9
                 : suffix == "T"                 ? 1e12
                                                 : 0;
  if (!(scale > 0) || !(v > 0) || !std::isfinite(v * scale) || v * scale > 1.8e19) return false;
  bytes = std::uint64_t(v * scale);
  return true;
}

}  // namespace snell::rt
