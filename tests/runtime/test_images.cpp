// §17 images through OIIO's texture system: lookups of generated images (an 8-bit
// sRGB PNG and a float EXR with known texels) at exact texel centres through each
// mapping, repeat, latlong backgrounds, and filtering of a checker floor.
#include <OpenImageIO/imageio.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "runtime/render.hpp"
#include "runtime/shading/textures.hpp"
#include "scene_util.hpp"

using namespace snell;
using namespace snell::test;
namespace fs = std::filesystem;
using rt::Color;
using rt::ImageTextures;

namespace {

constexpr int kW = 4, kH = 2;  // texels; row 0 is the image's top row

// The 8-bit code of channel c of texel (i, row): all different.
unsigned char code(int i, int row, int c) {
  return static_cast<unsigned char>(20 + 60 * i + 30 * row + 7 * c);
}
float srgb_decode(float c) {
  return c <= 0.04045f ? c / 12.92f : std::pow((c + 0.055f) / 1.055f, 2.4f);
}
// Texel (i, row)'s linear value in each image.
float png_value(int i, int row, int c) {
  return srgb_decode(code(i, row, c) / 255.0f);
}
float exr_value(int i, int row, int c) {
  return 0.25f * float(i) + 2.0f * float(row) + 0.125f * float(c);  // > 1 is fine: linear
}

struct Images {
  fs::path dir;
  std::string png, exr;
  Images() {
    dir = fs::temp_directory_path() / ("snell_images_" + std::to_string(::getpid()));
    fs::create_directories(dir);
    png = (dir / "texels.png").string();
    exr = (dir / "texels.exr").string();
    std::vector<unsigned char> b;
    std::vector<float> f;
    for (int row = 0; row < kH; ++row)
      for (int i = 0; i < kW; ++i)
        for (int c = 0; c < 3; ++c) {
          b.push_back(code(i, row, c));
          f.push_back(exr_value(i, row, c));
        }
    auto write = [](const std::string& path, OIIO::TypeDesc type, const void* data) {
      auto out = OIIO::ImageOutput::create(path);
      REQUIRE(out);
      OIIO::ImageSpec spec(kW, kH, 3, type);
      REQUIRE(out->open(path, spec));
      REQUIRE(out->write_image(type, data));
      REQUIRE(out->close());
    };
    write(png, OIIO::TypeDesc::UINT8, b.data());
    write(exr, OIIO::TypeDesc::FLOAT, f.data());
  }
  ~Images() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
};

ir::Scene scene_with(const Images& im) {
  ir::Scene s = base_scene(1, 1, 1);
  s.images.push_back({im.png, {}});
  s.images.push_back({im.exr, {}});
  return s;
}

ir::Texture image_texture(std::uint32_t image, ir::ImageMapping m, bool repeat = true) {
  ir::Texture t;
  t.pattern = ir::ImageTexture{image, m, repeat};
  return t;
}

// The colour at point q (a point lookup: no footprint, no normal, no inward move).
Color at(const ImageTextures& tex, const ir::Texture& t, ir::Vec3 q) {
  rt::TexturePoint tp;
  tp.p = rt::Vec3f(float(q.x), float(q.y), float(q.z));
  tp.images = &tex;
  return rt::texture_color(t, tp);
}

// (u, v) of the centre of texel (i, row): v = 0 is the bottom row.
double u_of(int i) {
  return (i + 0.5) / kW;
}
double v_of(int row) {
  return 1 - (row + 0.5) / kH;
}
// The unit direction whose spherical (u, v) is given.
ir::Vec3 direction(double u, double v) {
  double phi = (u - 0.5) * 2 * rt::kImagePi, lat = (v - 0.5) * rt::kImagePi;
  return {std::sin(phi) * std::cos(lat), std::sin(lat), std::cos(phi) * std::cos(lat)};
}

// The PNG is decoded to half floats (texture_io.cpp): 2^-11 relative, and the
// EXR is float; a lookup at a texel centre is that texel (bilinear weights 1, 0).
// The margin 1e-4: a render's rays lie up to ~1e-5 of a texel off the centre (and
// its footprint is as wide), which mixes in ~1e-5 of a neighbour differing by <= 2.
void check_texel(Color got, int image, int i, int row) {
  for (int c = 0; c < 3; ++c) {
    float want = image == 0 ? png_value(i, row, c) : exr_value(i, row, c);
    INFO("image " << image << " texel " << i << "," << row << " channel " << c);
    CHECK(got[c] == Approx(want).epsilon(1e-3).margin(1e-4));
  }
}

}  // namespace

TEST_CASE("image lookups at texel centres through each mapping", "[images]") {
  Images im;
  ir::Scene s = scene_with(im);
  std::string err;
  auto tex = rt::ImageTextures::open(s, err);
  REQUIRE(tex);
  for (std::uint32_t image = 0; image < 2; ++image)
    for (int row = 0; row < kH; ++row)
      for (int i = 0; i < kW; ++i) {
        double u = u_of(i), v = v_of(row);
        // planar: (u, v) = (x, y); with repeat, one image further is the same texel.
        check_texel(at(*tex, image_texture(image, ir::ImageMapping::Planar), {u, v, 7}), image, i,
                    row);
        check_texel(at(*tex, image_texture(image, ir::ImageMapping::Planar), {u - 3, v + 2, 0}),
                    image, i, row);
        ir::Vec3 d = direction(u, v) * 2.5;  // any radius
        check_texel(at(*tex, image_texture(image, ir::ImageMapping::Spherical), d), image, i, row);
        // cylindrical: u around y, v = y.
        ir::Vec3 c = direction(u, 0.5) * 3.0;
        check_texel(at(*tex, image_texture(image, ir::ImageMapping::Cylindrical), {c.x, v, c.z}),
                    image, i, row);
      }
}

TEST_CASE("repeat false is black outside [0, 1]", "[images]") {
  Images im;
  ir::Scene s = scene_with(im);
  std::string err;
  auto tex = rt::ImageTextures::open(s, err);
  REQUIRE(tex);
  ir::Texture t = image_texture(1, ir::ImageMapping::Planar, false);
  check_texel(at(*tex, t, {u_of(2), v_of(0), 0}), 1, 2, 0);  // inside: the texel
  for (ir::Vec3 q : {ir::Vec3{1.3, 0.5, 0}, ir::Vec3{-0.2, 0.5, 0}, ir::Vec3{0.5, 1.4, 0},
                     ir::Vec3{0.5, -0.3, 0}}) {
    Color c = at(*tex, t, q);
    INFO(q.x << "," << q.y);
    CHECK(c.x == 0);
    CHECK(c.y == 0);
    CHECK(c.z == 0);
  }
}

TEST_CASE("a latlong background is the image at the escaping ray's direction", "[images]") {
  Images im;
  ir::Scene s = scene_with(im);
  s.background = image_texture(1, ir::ImageMapping::Latlong);
  s.settings.width = s.settings.height = 1;
  s.settings.samples = 4;
  for (int row = 0; row < kH; ++row)
    for (int i = 0; i < kW; ++i) {
      ir::Vec3 d = direction(u_of(i), v_of(row));
      // A 1e-3° camera: its rays lie within ~1e-5 rad of d, a thousandth of a
      // texel, and the footprint is as small.
      look(s, {0, 0, 0}, d, 1e-3, std::fabs(d.y) > 0.9 ? ir::Vec3{1, 0, 0} : ir::Vec3{0, 1, 0});
      rt::RenderResult r = rt::render(s, {});
      const float* px = r.image.at(0, 0);
      check_texel(Color{px[0], px[1], px[2]}, 1, i, row);
      CHECK(r.texture_stats.find("OpenImageIO") != std::string::npos);
    }
}

TEST_CASE("an unreadable image is an error naming it", "[images]") {
  Images im;
  std::string bad = (im.dir / "not-an-image.png").string();
  { std::ofstream(bad) << "this is text\n"; }
  ir::Scene s = base_scene(1, 1, 1);
  s.images.push_back({bad, {}});
  std::string err = rt::check_images(s);
  CHECK(err.find("not-an-image.png") != std::string::npos);
  CHECK(rt::check_images(scene_with(im)).empty());
}
