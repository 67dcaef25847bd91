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

// The scene's images opened, as the render opens them.
std::unique_ptr<ImageTextures> opened(const ir::Scene& s) {
  std::string err;
  auto tex = rt::ImageTextures::open(s, "", err);
  INFO(err);
  REQUIRE(tex);
  return tex;
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
  auto tex = opened(s);
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
  auto tex = opened(s);
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

TEST_CASE("edges: repeat false clamps its filter, and the poles do not wrap", "[images]") {
  // Between the last texel centre and the edge a bilinear lookup is the edge texel
  // itself: without repeat it was blended with the black outside (0.6 of the
  // texel at u = 0.95 of a 2-texel image); at a pole of the spherical mappings
  // the top row was blended with the bottom one (red and blue made purple).
  Images im;
  ir::Scene s = scene_with(im);
  auto tex = opened(s);
  const double in = 0.2 / kW;  // past the edge texels' centres, inside the image
  ir::Texture planar = image_texture(1, ir::ImageMapping::Planar, false);
  check_texel(at(*tex, planar, {1 - in, v_of(1), 0}), 1, kW - 1, 1);
  check_texel(at(*tex, planar, {in, v_of(0), 0}), 1, 0, 0);
  check_texel(at(*tex, planar, {u_of(2), 1 - in / 2, 0}), 1, 2, 0);   // top row
  check_texel(at(*tex, planar, {u_of(1), in / 2, 0}), 1, 1, kH - 1);  // bottom row
  for (bool repeat : {true, false})
    for (ir::ImageMapping m : {ir::ImageMapping::Spherical, ir::ImageMapping::Latlong}) {
      INFO("repeat " << repeat << " mapping " << int(m));
      ir::Texture t = image_texture(1, m, repeat);
      check_texel(at(*tex, t, direction(u_of(1), 1 - 1e-4)), 1, 1, 0);   // the zenith
      check_texel(at(*tex, t, direction(u_of(3), 1e-4)), 1, 3, kH - 1);  // the nadir
      check_texel(at(*tex, t, direction(u_of(0), v_of(0))), 1, 0, 0);    // u still wraps
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

TEST_CASE("an image's colour space tag decides how it becomes linear", "[images]") {
  // The same texels as Images, tagged (oiio:ColorSpace): OIIO's name for a PNG
  // gAMA chunk, colour spaces of the studio test config (tests/ocio/studio.ocio),
  // and one it does not have.
  Images im;
  std::vector<unsigned char> b;
  std::vector<float> f;
  for (int row = 0; row < kH; ++row)
    for (int i = 0; i < kW; ++i)
      for (int c = 0; c < 3; ++c) {
        b.push_back(code(i, row, c));
        f.push_back(exr_value(i, row, c));
      }
  std::vector<std::uint16_t> w16;
  for (unsigned char c : b) w16.push_back(std::uint16_t(c * 257));  // the same fraction
  auto write = [&](const std::string& name, const std::string& space, bool floats = false,
                   bool sixteen = false) {
    std::string path = (im.dir / name).string();
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    const OIIO::TypeDesc type = floats    ? OIIO::TypeDesc::FLOAT
                                : sixteen ? OIIO::TypeDesc::UINT16
                                          : OIIO::TypeDesc::UINT8;
    OIIO::ImageSpec spec(kW, kH, 3, type);
    spec.attribute("oiio:ColorSpace", space);
    if (space == "Gamma2.2") spec.attribute("oiio:Gamma", 2.2f);
    REQUIRE(out->open(path, spec));
    const void* data = floats    ? (const void*)f.data()
                       : sixteen ? (const void*)w16.data()
                                 : b.data();
    REQUIRE(out->write_image(spec.format, data));
    REQUIRE(out->close());
    return path;
  };
  ir::Scene s = base_scene(1, 1, 1);
  // 16-bit: a gAMA chunk's power and OIIO's "Linear" mean what they say.
  s.images.push_back({write("gamma.png", "Gamma2.2", false, true), {}});
  s.images.push_back({write("ocio-gamma.png", "Gamma 2.2 Encoded", false), {}});
  // (Not an EXR: OIIO 2.4 reads every EXR as "Linear", whatever it was tagged.)
  s.images.push_back({write("x2.png", "Scaled Linear x2", false), {}});
  s.images.push_back({write("linear.png", "Linear", false, true), {}});
  // OIIO's tag for a PPM, carried into a PNG by oiiotool: §17's 8-bit sRGB.
  s.images.push_back({write("rec709.png", "Rec709", false), {}});
  // §17: 8-bit files are sRGB whatever OIIO's own names in their header say (oiiotool
  // writes an 8-bit PNG of float values with a gAMA of 1.0, "Linear").
  s.images.push_back({write("linear8.png", "Linear", false), {}});
  s.images.push_back({write("gamma8.png", "Gamma2.2", false), {}});
  std::string err;
  auto tex = rt::ImageTextures::open(s, SNELL_STUDIO_OCIO, err);
  INFO(err);
  REQUIRE(tex);
  for (int row = 0; row < kH; ++row)
    for (int i = 0; i < kW; ++i) {
      ir::Vec3 q{u_of(i), v_of(row), 0};
      Color g = at(*tex, image_texture(0, ir::ImageMapping::Planar), q);
      Color o = at(*tex, image_texture(1, ir::ImageMapping::Planar), q);
      Color x = at(*tex, image_texture(2, ir::ImageMapping::Planar), q);
      Color l = at(*tex, image_texture(3, ir::ImageMapping::Planar), q);
      Color r709 = at(*tex, image_texture(4, ir::ImageMapping::Planar), q);
      Color l8 = at(*tex, image_texture(5, ir::ImageMapping::Planar), q);
      Color g8 = at(*tex, image_texture(6, ir::ImageMapping::Planar), q);
      for (int c = 0; c < 3; ++c) {
        INFO("texel " << i << "," << row << " channel " << c);
        float v = code(i, row, c) / 255.0f;
        // Half floats: 2^-11 relative (see check_texel).
        CHECK(g[c] == Approx(std::pow(v, 2.2f)).epsilon(1e-3));
        CHECK(o[c] == Approx(std::pow(v, 2.2f)).epsilon(1e-3));
        CHECK(x[c] == Approx(2 * v).epsilon(1e-3));
        CHECK(l[c] == Approx(v).epsilon(1e-3));
        float srgb = v <= 0.04045f ? v / 12.92f : std::pow((v + 0.055f) / 1.055f, 2.4f);
        CHECK(r709[c] == Approx(srgb).epsilon(1e-3).margin(1e-6));
        CHECK(l8[c] == Approx(srgb).epsilon(1e-3).margin(1e-6));
        CHECK(g8[c] == Approx(srgb).epsilon(1e-3).margin(1e-6));
      }
    }
  // A colour space the config does not have: an error naming the file, the space
  // and the config, before the render.
  ir::Scene bad = base_scene(1, 1, 1);
  bad.images.push_back({write("odd.png", "Filmic Log Encoding", false), {}});
  err = rt::check_images(bad, SNELL_STUDIO_OCIO);
  INFO(err);
  CHECK(err.find("odd.png") != std::string::npos);
  CHECK(err.find("'Filmic Log Encoding'") != std::string::npos);
  CHECK(err.find("studio.ocio") != std::string::npos);
}

TEST_CASE("grey images give grey, with or without alpha, and alpha is never a colour", "[images]") {
  // §17: an image gives its colours; a grey file (one channel, or grey + alpha
  // as PNG and TIFF write it) is the same grey in R, G and B, and an alpha
  // channel (RGBA, or an EXR's A before its Y) never reads as a colour, nor
  // scales one (PNG's alpha is unassociated: OIIO would premultiply it). Grey +
  // alpha used to come out red = grey * alpha, green = alpha, blue = 0.
  Images im;
  auto write = [&](const std::string& name, int channels, std::vector<std::string> names,
                   int alpha) {
    std::vector<unsigned char> b;
    for (int row = 0; row < kH; ++row)
      for (int i = 0; i < kW; ++i)
        for (int c = 0; c < channels; ++c)
          b.push_back(c == alpha ? 255 - code(i, row, 0)
                                 : code(i, row, c - (c > alpha && alpha >= 0 ? 1 : 0)));
    std::string path = (im.dir / name).string();
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    OIIO::ImageSpec spec(kW, kH, channels, OIIO::TypeDesc::UINT8);
    spec.channelnames = names;
    spec.alpha_channel = alpha;
    spec.attribute("oiio:UnassociatedAlpha", 1);  // the codes as given, not divided by alpha
    REQUIRE(out->open(path, spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, b.data()));
    REQUIRE(out->close());
    return path;
  };
  ir::Scene s = base_scene(1, 1, 1);
  s.images.push_back({write("grey.png", 1, {"Y"}, -1), {}});
  s.images.push_back({write("grey-alpha.png", 2, {"Y", "A"}, 1), {}});
  s.images.push_back({write("rgba.png", 4, {"R", "G", "B", "A"}, 3), {}});
  {  // float, so linear as it is: the PNG's decoded values
    std::vector<float> f;
    for (int row = 0; row < kH; ++row)
      for (int i = 0; i < kW; ++i) f.insert(f.end(), {0.5f, png_value(i, row, 0)});
    std::string path = (im.dir / "alpha-grey.exr").string();
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    OIIO::ImageSpec spec(kW, kH, 2, OIIO::TypeDesc::FLOAT);
    spec.channelnames = {"A", "Y"};
    spec.alpha_channel = 0;
    REQUIRE(out->open(path, spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, f.data()));
    REQUIRE(out->close());
    s.images.push_back({path, {}});
  }
  auto tex = opened(s);
  for (int row = 0; row < kH; ++row)
    for (int i = 0; i < kW; ++i) {
      ir::Vec3 q{u_of(i), v_of(row), 0};
      for (std::uint32_t image : {0u, 1u, 3u}) {
        Color g = at(*tex, image_texture(image, ir::ImageMapping::Planar), q);
        for (int c = 0; c < 3; ++c) {
          INFO("image " << image << " texel " << i << "," << row << " channel " << c);
          CHECK(g[c] == Approx(png_value(i, row, 0)).epsilon(1e-3).margin(1e-4));
        }
      }
      check_texel(at(*tex, image_texture(2, ir::ImageMapping::Planar), q), 0, i, row);
    }
}

TEST_CASE("an EXR's chromaticities convert its primaries to Rec.709", "[images]") {
  // The texels of Images' EXR, written once with ACEScg primaries (AP1, ACES
  // white) and once with Rec.709's: the first is looked up as M · rgb with M the
  // Bradford-adapted AP1-to-Rec.709 matrix (its published four decimals), the
  // second unchanged.
  Images im;
  std::vector<float> f;
  for (int row = 0; row < kH; ++row)
    for (int i = 0; i < kW; ++i)
      for (int c = 0; c < 3; ++c) f.push_back(exr_value(i, row, c));
  auto write = [&](const std::string& name, const float* xy) {
    std::string path = (im.dir / name).string();
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    OIIO::ImageSpec spec(kW, kH, 3, OIIO::TypeDesc::FLOAT);
    spec.attribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), xy);
    REQUIRE(out->open(path, spec));
    REQUIRE(out->write_image(spec.format, f.data()));
    REQUIRE(out->close());
    // OIIO must round-trip the attribute, or this test tests nothing.
    auto in = OIIO::ImageInput::open(path);
    REQUIRE(in);
    float back[8];
    REQUIRE(
        in->spec().getattribute("chromaticities", OIIO::TypeDesc(OIIO::TypeDesc::FLOAT, 8), back));
    CHECK(back[0] == xy[0]);
    return path;
  };
  const float ap1[8] = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  const float rec709[8] = {0.64f, 0.33f, 0.30f, 0.60f, 0.15f, 0.06f, 0.3127f, 0.3290f};
  ir::Scene s = base_scene(1, 1, 1);
  s.images.push_back({write("acescg.exr", ap1), {}});
  s.images.push_back({write("rec709.exr", rec709), {}});
  auto tex = opened(s);
  const float m[9] = {1.7051f,  -0.6218f, -0.0833f, -0.1303f, 1.1408f,
                      -0.0105f, -0.0240f, -0.1290f, 1.1530f};
  for (int row = 0; row < kH; ++row)
    for (int i = 0; i < kW; ++i) {
      ir::Vec3 q{u_of(i), v_of(row), 0};
      Color a = at(*tex, image_texture(0, ir::ImageMapping::Planar), q);
      Color r = at(*tex, image_texture(1, ir::ImageMapping::Planar), q);
      for (int c = 0; c < 3; ++c) {
        INFO("texel " << i << "," << row << " channel " << c);
        float want = 0;
        for (int k = 0; k < 3; ++k) want += m[3 * c + k] * exr_value(i, row, k);
        // The published matrix's rounding (1.5e-4 an entry) times values <= 2.5.
        CHECK(a[c] == Approx(want).margin(1e-3));
        CHECK(r[c] == Approx(exr_value(i, row, c)).epsilon(1e-6).margin(1e-6));
      }
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
  // A small file claiming a huge image (a PNG of 60000 x 60000 with one row of
  // data): refused from its header, before a float copy of it is attempted
  // (such a "PNG bomb" of 2.7 MB crashed check and render).
  std::string bomb = (im.dir / "bomb.png").string();
  {
    std::ofstream out(bomb, std::ios::binary);
    const unsigned char header[] = {
        0x89, 'P', 'N',  'G',  '\r', '\n', 0x1a, '\n',                    // signature
        0,    0,   0,    13,   'I',  'H',  'D',  'R',  0, 0, 0xea, 0x60,  // width 60000
        0,    0,   0xea, 0x60, 8,    2,    0,    0,    0,                 // height, RGB8
    };
    out.write(reinterpret_cast<const char*>(header), sizeof header);
    const unsigned char crc[4] = {0x0f, 0xb0, 0xe2, 0x15};  // of "IHDR" and its data
    out.write(reinterpret_cast<const char*>(crc), 4);
    // One row's worth of data (a deflated 16 zero bytes) and the end.
    const unsigned char rest[] = {
        0x00, 0x00, 0x00, 0x0b, 0x49, 0x44, 0x41, 0x54, 0x78, 0x9c, 0x63, 0x60,
        0x40, 0x05, 0x00, 0x00, 0x10, 0x00, 0x01, 0x39, 0xbd, 0x8f, 0x65, 0x00,
        0x00, 0x00, 0x00, 0x49, 0x45, 0x4e, 0x44, 0xae, 0x42, 0x60, 0x82,
    };
    out.write(reinterpret_cast<const char*>(rest), sizeof rest);
  }
  ir::Scene b = base_scene(1, 1, 1);
  b.images.push_back({bomb, {}});
  err = rt::check_images(b);
  INFO(err);
  CHECK(err.find("bomb.png") != std::string::npos);
  CHECK(err.find("60000x60000") != std::string::npos);
}

TEST_CASE("a damaged float EXR is refused before the render, and every bad image is named",
          "[images]") {
  // The texture system reads a float EXR itself, tile by tile as lookups need
  // them: a file cut short had a readable header, and its failed lookups were
  // black, exit 0.
  Images im;
  std::string cut = (im.dir / "cut.exr").string();
  {
    std::vector<float> f(64 * 64 * 3, 0.5f);
    auto out = OIIO::ImageOutput::create(cut);
    REQUIRE(out);
    OIIO::ImageSpec spec(64, 64, 3, OIIO::TypeDesc::FLOAT);
    spec.attribute("compression", "none");
    REQUIRE(out->open(cut, spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, f.data()));
    REQUIRE(out->close());
  }
  fs::resize_file(cut, fs::file_size(cut) * 6 / 10);
  std::string text = (im.dir / "text.png").string();
  { std::ofstream(text) << "this is text\n"; }
  ir::Scene s = scene_with(im);  // images 0 and 1 are good
  s.images.push_back({cut, {}});
  s.images.push_back({text, {}});
  std::string err = rt::check_images(s);
  INFO(err);
  CHECK(err.find("cut.exr") != std::string::npos);
  err.clear();
  auto bad = rt::unreadable_images(s.images, "", err);
  CHECK(err.empty());
  REQUIRE(bad.size() == 2);
  CHECK(bad[0].first == 2);
  CHECK(bad[1].first == 3);
}

namespace {

// One pixel of a diffuse surface textured by image `image` with mapping "uv", seen
// straight on from `eye` (1e-3° wide) and lit from the eye by a point light of
// intensity π d²: the pixel is the albedo, the texel at the point's (u, v).
Color lit_texel(const Images& im, std::uint32_t image, ir::Shape shape, ir::Vec3 eye,
                ir::Vec3 target, std::vector<ir::MeshData> meshes = {}) {
  ir::Scene s = scene_with(im);
  s.meshes = std::move(meshes);
  ir::Material m = ir::Diffuse{image_texture(image, ir::ImageMapping::Uv)};
  shape.material = add_material(s, m);
  s.shapes.push_back(shape);
  double d = ir::length(target - eye);
  s.point_lights.push_back(ir::PointLight{eye, ir::Vec3(rt::kImagePi * d * d), {}});
  ir::Vec3 dir = ir::normalize(target - eye);
  look(s, eye, target, 1e-3, std::fabs(dir.y) > 0.9 ? ir::Vec3{1, 0, 0} : ir::Vec3{0, 1, 0});
  rt::RenderResult r = rt::render(s, {});
  const float* px = r.image.at(0, 0);
  return {px[0], px[1], px[2]};
}

}  // namespace

// The margin: cos θ of a ray 1e-5 rad off the axis and the light's 1/d² are 1 to
// ~1e-10; the texel margin is check_texel's.
TEST_CASE("uv mapping: mesh vt, the sphere and the cylinder at texel centres", "[images]") {
  Images im;
  // A 2 x 1 quad whose vt runs u the other way: u = 1 - x / 2, v = y.
  ir::MeshData quad;
  quad.path = "quad";
  quad.positions = {{0, 0, 0}, {2, 0, 0}, {2, 1, 0}, {0, 1, 0}};
  quad.indices = {0, 1, 2, 0, 2, 3};
  quad.texcoords = {{1, 0, 0}, {0, 0, 0}, {0, 1, 0}, {1, 1, 0}};
  quad.texcoord_indices = quad.indices;
  for (std::uint32_t image = 0; image < 2; ++image)
    for (int row = 0; row < kH; ++row)
      for (int i = 0; i < kW; ++i) {
        double u = u_of(i), v = v_of(row);
        INFO("texel " << i << "," << row);
        ir::Vec3 q{2 * (1 - u), v, 0};
        check_texel(
            lit_texel(im, image, shape_of(ir::Mesh{0}, 0), q + ir::Vec3{0, 0, -5}, q, {quad}),
            image, i, row);
        // The sphere: the spherical mapping about its centre.
        ir::Vec3 n = direction(u, v);
        check_texel(lit_texel(im, image, sphere({1, 2, 3}, 1, 0), ir::Vec3{1, 2, 3} + n * 5,
                              ir::Vec3{1, 2, 3} + n),
                    image, i, row);
        // The cylinder's side: u around the axis in its frame (x, -z for the y
        // axis), v up the axis from base to cap.
        double phi = (u - 0.5) * 2 * rt::kImagePi;
        ir::Vec3 out{std::cos(phi), 0, -std::sin(phi)};
        ir::Vec3 p = out + ir::Vec3{0, 2 * v, 0};
        check_texel(lit_texel(im, image, shape_of(ir::Cylinder{{0, 0, 0}, {0, 2, 0}, 1}, 0),
                              p + out * 4, p),
                    image, i, row);
      }
}

TEST_CASE("uv mapping: each kind's parameters at known points", "[images]") {
  ir::Scene s = base_scene(1, 1, 1);
  auto uv = [&](ir::Shape shape, ir::Vec3 w, std::uint32_t tri = 0) {
    s.shapes = {shape};
    rt::SurfaceFrame f = rt::surface_frame(s, s.shapes[0], ir::kNoPart, ir::kNoPart, tri, 0);
    return rt::surface_uv(f, w);
  };
  auto near = [](rt::ImageUV a, double u, double v) {
    INFO("(" << a.u << ", " << a.v << ") want (" << u << ", " << v << ")");
    CHECK(a.u == Approx(u).margin(1e-12));
    CHECK(a.v == Approx(v).margin(1e-12));
  };
  // Box faces: the face's two other coordinates as fractions of the box.
  ir::Shape b = box({0, 0, 0}, {2, 4, 8}, 0);
  near(uv(b, {2, 1, 2}), 0.25, 0.25);    // +x face: (z, y)
  near(uv(b, {0.5, 0, 6}), 0.25, 0.75);  // -y face: (x, z)
  near(uv(b, {1.5, 3, 8}), 0.75, 0.75);  // +z face: (x, y)
  // Disc and cone caps: the square around them, in the axis frame (x, -z for y).
  near(uv(shape_of(ir::Disc{{0, 0, 0}, {0, 1, 0}, 2, 0}, 0), {1, 0, 0}), 0.75, 0.5);
  near(uv(shape_of(ir::Disc{{0, 0, 0}, {0, 1, 0}, 2, 0}, 0), {0, 0, -1}), 0.5, 0.75);
  near(uv(shape_of(ir::Cone{{0, 0, 0}, 2, {0, 4, 0}, 0}, 0), {-1, 0, 0}), 0.25, 0.5);
  // The cone's side: halfway up, radius 1.
  near(uv(shape_of(ir::Cone{{0, 0, 0}, 2, {0, 4, 0}, 0}, 0), {1, 2, 0}), 0.5, 0.5);
  // Torus: u as the spherical formula's, v around the tube from its inner equator.
  ir::Shape t = shape_of(ir::Torus{2, 0.5}, 0);
  near(uv(t, {0, 0, 2.5}), 0.5, 0.5);    // outer equator, +z
  near(uv(t, {2, 0.5, 0}), 0.75, 0.75);  // top of the tube, +x
  // Plane: its two axes; triangle: the barycentrics of b and c.
  near(uv(plane({0, 1, 0}, 0, 0), {3, 0, -5}), 3, 5);
  near(uv(triangle({0, 0, 0}, {1, 0, 0}, {0, 1, 0}, 0), {0.25, 0.5, 0}), 0.25, 0.5);
  // Transforms: the leaf's object space (a sphere moved and turned keeps its map).
  ir::Shape sp = sphere({0, 0, 0}, 1, 0);
  sp.set_world_from_object(ir::Transform::translate({5, 0, 0}) * ir::Transform::rotate_y(90));
  near(uv(sp, {5, 0, 1} /* object -x */), 0.25, 0.5);
}

TEST_CASE("a file replaced by one of the same size and time is decoded again", "[images]") {
  // 8-bit files are decoded to linear once and the decoding kept in a cache file;
  // its key had only the path, size and time, so a same-size file copied in with
  // its time kept (cp -p, rsync -t) rendered the old picture.
  Images im;
  std::string ppm = (im.dir / "swap.ppm").string();
  auto write = [&](unsigned char r, unsigned char b) {
    std::ofstream out(ppm, std::ios::binary);
    out << "P6\n1 1\n255\n" << char(r) << char(0) << char(b);
  };
  write(255, 0);
  const auto when = fs::last_write_time(ppm);
  ir::Scene s = base_scene(1, 1, 1);
  s.images.push_back({ppm, {}});
  auto first = opened(s);
  Color red = at(*first, image_texture(0, ir::ImageMapping::Planar), {0.5, 0.5, 0});
  CHECK(red.x == Approx(1).margin(1e-3));
  CHECK(red.z == Approx(0).margin(1e-3));
  write(0, 255);
  fs::last_write_time(ppm, when);
  auto second = opened(s);
  Color blue = at(*second, image_texture(0, ir::ImageMapping::Planar), {0.5, 0.5, 0});
  CHECK(blue.x == Approx(0).margin(1e-3));
  CHECK(blue.z == Approx(1).margin(1e-3));
}

TEST_CASE("NaN and infinite texels are mended to their finite neighbours' mean, and said",
          "[images]") {
  // A float EXR is otherwise read by the texture system as it is: one NaN texel
  // made every lookup whose filter touched it NaN, so those samples were dropped
  // (a whole image of them black). A PNG has no such values: no note.
  Images im;
  const std::string bad = (im.dir / "nan.exr").string();
  std::vector<float> f;
  for (int row = 0; row < kH; ++row)
    for (int i = 0; i < kW; ++i)
      for (int c = 0; c < 3; ++c) f.push_back(exr_value(i, row, c));
  auto texel = [&](int i, int row, int c) -> float& { return f[3 * (row * kW + i) + c]; };
  texel(1, 1, 0) = NAN;
  texel(2, 1, 2) = INFINITY;
  {
    auto out = OIIO::ImageOutput::create(bad);
    REQUIRE(out);
    OIIO::ImageSpec spec(kW, kH, 3, OIIO::TypeDesc::FLOAT);
    REQUIRE(out->open(bad, spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, f.data()));
    REQUIRE(out->close());
  }
  ir::Scene s = scene_with(im);
  s.images.push_back({bad, {}});
  std::string err;
  std::vector<std::pair<std::size_t, std::string>> notes;
  CHECK(rt::unreadable_images(s.images, "", err, &notes).empty());
  CHECK(err.empty());
  REQUIRE(notes.size() == 1);
  CHECK(notes[0].first == 2);
  CHECK(notes[0].second.find("2 pixels of it hold NaN or infinite values") != std::string::npos);
  // The mended texel is the mean of the finite values of its 3x3 box (the texel
  // itself excluded), in that channel; the others are as written.
  auto mean3 = [&](int i0, int row0, int c) {
    double sum = 0;
    int n = 0;
    for (int row = std::max(0, row0 - 1); row <= std::min(kH - 1, row0 + 1); ++row)
      for (int i = std::max(0, i0 - 1); i <= std::min(kW - 1, i0 + 1); ++i)
        if (std::isfinite(texel(i, row, c))) sum += texel(i, row, c), ++n;
    return float(sum / n);
  };
  auto tex = opened(s);
  const ir::Texture t = image_texture(2, ir::ImageMapping::Planar);
  for (int row = 0; row < kH; ++row)
    for (int i = 0; i < kW; ++i) {
      Color got = at(*tex, t, {u_of(i), v_of(row), 0});
      for (int c = 0; c < 3; ++c) {
        const float want = std::isfinite(texel(i, row, c)) ? texel(i, row, c) : mean3(i, row, c);
        INFO("texel " << i << "," << row << " channel " << c);
        CHECK(got[c] == Approx(want).epsilon(1e-5).margin(1e-4));
      }
    }
}
