// §17 images: the mappings from a pattern point to (u, v), and the render's
// texture system (OpenImageIO's TextureSystem in the image module, reached through
// the function pointers of texture_io.cpp's C interface: OIIO loads only when a
// scene has an image).
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "runtime/ir/ir.hpp"
#include "runtime/vec.hpp"

namespace snell::rt {

// (u, v) of an image mapping; v = 0 is the image's bottom row. Not wrapped: the
// lookup repeats the image or is black outside [0, 1]².
struct ImageUV {
  double u = 0, v = 0;
};
inline constexpr double kImagePi = 3.14159265358979323846;
inline double around_y(ir::Vec3 q) {  // atan2(x, z) / 360°, shifted into [0, 1]
  return 0.5 + std::atan2(q.x, q.z) / (2 * kImagePi);
}
inline ImageUV image_uv(ir::ImageMapping m, ir::Vec3 q) {
  switch (m) {
    case ir::ImageMapping::Planar:
      return {q.x, q.y};
    case ir::ImageMapping::Cylindrical:
      return {around_y(q), q.y};
    case ir::ImageMapping::Spherical:
    case ir::ImageMapping::Uv:  // without a surface (a background): the direction's
    case ir::ImageMapping::Latlong: {
      double r = std::sqrt(q.x * q.x + q.y * q.y + q.z * q.z);
      double s = r > 0 ? std::fmax(-1.0, std::fmin(1.0, q.y / r)) : 0;
      return {around_y(q), 0.5 + std::asin(s) / kImagePi};
    }
  }
  return {};
}
// Whether u goes around y (it jumps from 1 to 0 behind the pattern's -z axis; "uv"
// around the axis of the shapes that have one).
inline bool wraps_around(ir::ImageMapping m) {
  return m != ir::ImageMapping::Planar;
}

// The §17 texture cache bound (OIIO's max_memory_MB): images larger than this are
// streamed through it in tiles.
inline constexpr int kTextureCacheMB = 256;

// The images of one render: opened once before it, shared by every thread.
class ImageTextures {
 public:
  // Opens every image of scene.images; null with `error` ("FILE:LINE:COL: cannot
  // read image ...") when one cannot be read or the image module cannot load.
  // Images tagged with a colour space are converted from it through the OCIO
  // config `ocio_config` (empty: $OCIO, else Snell's).
  // `failed`, when given: the index of the image that could not be read (else
  // untouched), and `why` the reader's reason alone.
  static std::unique_ptr<ImageTextures> open(const ir::Scene& scene, const std::string& ocio_config,
                                             std::string& error, std::size_t* failed = nullptr,
                                             std::string* why = nullptr);
  ~ImageTextures();
  ImageTextures(const ImageTextures&) = delete;
  ImageTextures& operator=(const ImageTextures&) = delete;

  // The linear RGB at (u, v) of image `image`, filtered over the footprint whose
  // (u, v) extents along two directions are (du_a, dv_a) and (du_b, dv_b);
  // zero extents are a point (bilinear) lookup. Inline: textures.hpp is used by
  // the compiler's tests too, which do not link the runtime.
  //
  // Edges: `repeat` tiles; without it the image is black outside [0, 1]² and its
  // edge texels are not blended with that black (the filter clamps). Whatever
  // `repeat` says, u wraps around the seam of the mappings that go round (§17's
  // u is an angle there), and v stops at the poles of `spherical` and `latlong`
  // (the top row is the zenith, not a neighbour of the bottom one).
  Color lookup(std::uint32_t image, double u, double v, float du_a, float dv_a, float du_b,
               float dv_b, bool repeat, ir::ImageMapping mapping) const {
    if (image >= handles_.size()) return Color(0.0f);
    if (!repeat && !(u >= 0 && u <= 1 && v >= 0 && v <= 1)) return Color(0.0f);
    const bool poles =
        mapping == ir::ImageMapping::Spherical || mapping == ir::ImageMapping::Latlong;
    const bool s_periodic = repeat || poles || mapping == ir::ImageMapping::Cylindrical;
    const bool t_periodic = repeat && !poles;
    // OIIO's t runs down from the top row. Periodic coordinates are reduced to
    // [0, 1) in double first, so a point far from the origin keeps its texel.
    double s = s_periodic ? u - std::floor(u) : u;
    double t = t_periodic ? (1 - v) - std::floor(1 - v) : 1 - v;
    const float st[6] = {float(s), float(t), du_a, -dv_a, du_b, -dv_b};
    float rgb[3];
    api_->lookup(ts_, handles_[image], (s_periodic ? 1 : 0) | (t_periodic ? 2 : 0), st, rgb);
    return {rgb[0], rgb[1], rgb[2]};
  }
  // OIIO's statistics of this render's lookups and cache (--stats).
  std::string stats() const;

  // The module's functions (texture_io.cpp), resolved once by name.
  struct Api {
    void* (*create)(int) = nullptr;
    void (*destroy)(void*) = nullptr;
    // (module, path, OCIO config, error, note): a handle, or null with error;
    // `note` what a readable image's reading says of it.
    void* (*open)(void*, const std::string&, const std::string&, std::string&,
                  std::string&) = nullptr;
    void (*lookup)(void*, void*, int, const float*, float*) = nullptr;
    void (*stats)(void*, std::string&) = nullptr;
    std::string error;
  };

 private:
  ImageTextures() = default;
  const Api* api_ = nullptr;
  void* ts_ = nullptr;
  std::vector<void*> handles_;  // by ir::ImageTexture::image
};

}  // namespace snell::rt
