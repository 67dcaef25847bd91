// §18 end to end: frames (clock, frame, output names), crops (bit-identical to the
// full render, at their place in the EXR's display window), sample ranges, and
// snell merge (crops bit for bit, sample ranges within 1e-6 relative, crops that
// share pixels but not samples, and every refusal writing nothing). The
// every-effect scene is examples/showcase.scn (thin lens, motion blur, an area
// light, glossy metal, glass with absorption, glazes, a checker), rendered small.
#include <OpenImageIO/imageio.h>

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "tests/e2e/e2e_util.hpp"

namespace fs = std::filesystem;
using snell::e2e::kShowcase;
using snell::e2e::kSnell;
using snell::e2e::kSrc;
using snell::e2e::run;
using snell::e2e::slurp;

namespace {

// Each test's own folder.
struct SplitScratch : snell::e2e::Scratch {
  SplitScratch() : snell::e2e::Scratch("snell_split_") {}
};

struct Exr {
  OIIO::ImageSpec spec;
  std::vector<float> rgb;                // the data window, 3 floats a pixel
  const float* at(int x, int y) const {  // full-image coordinates
    return &rgb[3 * (std::size_t(y - spec.y) * spec.width + (x - spec.x))];
  }
  std::string attr(const char* name) const { return spec.get_string_attribute(name); }
};

Exr read_exr(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  REQUIRE(in);
  Exr e;
  e.spec = in->spec();
  REQUIRE(e.spec.nchannels == 3);
  e.rgb.resize(std::size_t(e.spec.width) * e.spec.height * 3);
  REQUIRE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, e.rgb.data()));
  return e;
}

// The small every-effect render, with `sampler`.
std::string showcase(const std::string& sampler, int spp) {
  return "render " + kShowcase + " --quiet --res 48x27 --spp " + std::to_string(spp) +
         " --set sampler=" + sampler;
}

// How a merge agrees with the one-run render: the worst relative difference of
// a channel, and how many channels of one piece alone differ from the render
// (so a test can show that its comparison could fail).
struct Agreement {
  double worst = 0;
  std::size_t piece_differs = 0;
};
Agreement agreement(const Exr& full, const Exr& merged, const Exr& piece) {
  Agreement a;
  for (std::size_t i = 0; i < full.rgb.size(); ++i) {
    double f = full.rgb[i], m = merged.rgb[i];
    double scale = std::max(std::fabs(f), std::fabs(m));
    if (scale > 0) a.worst = std::max(a.worst, std::fabs(f - m) / scale);
    a.piece_differs += piece.rgb[i] != full.rgb[i];
  }
  return a;
}

// How many pixels of `scene` rendered with --crop `crop` differ from `full`'s.
std::size_t crop_differs(const std::string& scene, const char* crop, const Exr& full,
                         const Scratch& tmp) {
  REQUIRE(run(scene + " --crop " + crop + " -o " + (tmp / "crop.exr")) == 0);
  Exr c = read_exr(tmp / "crop.exr");
  std::size_t differ = 0;
  for (int y = c.spec.y; y < c.spec.y + c.spec.height; ++y)
    for (int x = c.spec.x; x < c.spec.x + c.spec.width; ++x)
      differ += std::memcmp(c.at(x, y), full.at(x, y), 3 * sizeof(float)) != 0;
  return differ;
}

}  // namespace

TEST_CASE("a crop holds the full render's pixels, bit for bit, at their place", "[e2e][split]") {
  SplitScratch tmp;
  for (const char* sampler : {"independent", "stratified", "sobol"}) {
    INFO("sampler " << sampler);
    REQUIRE(run(showcase(sampler, 6) + " -o " + (tmp / "full.exr")) == 0);
    // Not on the 16-pixel tile grid: a crop's tiles start at its own corner.
    REQUIRE(run(showcase(sampler, 6) + " --crop 5,3,37,22 -o " + (tmp / "crop.exr") + " -o " +
                (tmp / "crop.png")) == 0);
    Exr full = read_exr(tmp / "full.exr"), crop = read_exr(tmp / "crop.exr");
    CHECK(crop.spec.x == 5);
    CHECK(crop.spec.y == 3);
    CHECK(crop.spec.width == 32);
    CHECK(crop.spec.height == 19);
    CHECK(crop.spec.full_x == 0);
    CHECK(crop.spec.full_y == 0);
    CHECK(crop.spec.full_width == 48);
    CHECK(crop.spec.full_height == 27);
    CHECK(crop.attr("snell:crop") == "5,3,37,22");
    CHECK(crop.attr("snell:sample_range") == "0..6");
    CHECK(crop.attr("snell:scene_hash") == full.attr("snell:scene_hash"));
    CHECK(crop.attr("snell:scene_hash").size() == 16);
    std::size_t differ = 0;
    for (int y = 3; y < 22; ++y)
      for (int x = 5; x < 37; ++x)
        differ += std::memcmp(crop.at(x, y), full.at(x, y), 3 * sizeof(float)) != 0;
    CHECK(differ == 0);
    // The PNG of a crop is the cropped pixels alone.
    auto png = OIIO::ImageInput::open(tmp / "crop.png");
    REQUIRE(png);
    CHECK(png->spec().width == 32);
    CHECK(png->spec().height == 19);
  }
}

TEST_CASE("coincident surfaces: a crop still holds the full render's pixels", "[e2e][split]") {
  // Each sphere is written twice, red then blue, alone and as a union's children:
  // every hit has two equal distances. The first written wins everywhere; it was
  // whichever the traversal met first, which depends on the packet a ray rides in,
  // so crops off the 4-pixel packet grid differed from the full render in up to
  // 191 of 4032 pixels (red against blue), and the unions were striped.
  SplitScratch tmp;
  {
    std::ofstream f(tmp / "twice.scn");
    f << "settings { resolution <120, 90> samples 1 }\n"
         "camera { location <0, 8, -14> look_at <0, 0, 0> fov 60 }\n"
         "point_light { position <0, 10, -5> intensity 300 }\n"
         "for i in 0 .. 40 { for j in 0 .. 20 {\n"
         "  let x = i * 0.5 - 10; let z = j * 0.5 - 3;\n"
         "  if j % 2 == 0 {\n"
         "    sphere { center <x, 0.2, z> radius 0.2 material diffuse <1, 0, 0> }\n"
         "    sphere { center <x, 0.2, z> radius 0.2 material diffuse <0, 0, 1> }\n"
         "  } else {\n"
         "    union { sphere { center <x, 0.2, z> radius 0.2 material diffuse <1, 0, 0> }\n"
         "            sphere { center <x, 0.2, z> radius 0.2 material diffuse <0, 0, 1> } }\n"
         "  }\n"
         "} }\n";
  }
  const std::string scene = "render " + (tmp / "twice.scn") + " --quiet --threads 1";
  REQUIRE(run(scene + " -o " + (tmp / "full.exr")) == 0);
  Exr full = read_exr(tmp / "full.exr");
  std::size_t red = 0, blue = 0;
  for (std::size_t i = 0; i < full.rgb.size(); i += 3) {
    red += full.rgb[i] > 0;
    blue += full.rgb[i + 2] > 0;
  }
  CHECK(red > 2000);
  CHECK(blue == 0);
  for (const char* crop : {"5,5,77,61", "1,1,119,89", "3,7,50,50"}) {
    INFO("crop " << crop);
    CHECK(crop_differs(scene, crop, full, tmp) == 0);
  }
}

TEST_CASE("moving instances: a crop still holds the full render's pixels", "[e2e][split]") {
  // Embree carries a ray into a moving instance's space by its own interpolation,
  // whose last bits depend on the packet the ray rides in; a crop off the packet
  // grid differed from the full render where mirrors saw each other (a pixel in a
  // few thousand, ~1e-5 relative). The hit is now found again in Snell's own
  // transform: CSG (torus, box, sphere) and triangles (boxes).
  SplitScratch tmp;
  {
    std::ofstream f(tmp / "wheels.scn");
    f << "settings { resolution <96, 72> samples 4 }\n"
         "camera { location <0, 5, -6> look_at <0, 0, 0> fov 60 shutter <0, 1> }\n"
         "point_light { position <2, 6, -3> intensity 60 }\n"
         "plane { normal <0, 1, 0> distance -0.5 material diffuse 0.6 }\n"
         "let wheel = union { torus { major 0.5 minor 0.12 }\n"
         "  box { min <-0.5, -0.06, -0.06> max <0.5, 0.06, 0.06> } };\n"
         "let block = union { box { min -0.3 max 0.3 } sphere { radius 0.2 center <0, 0.4, 0> } "
         "};\n"
         "for i in 0 .. 3 { for j in 0 .. 3 {\n"
         "  let p = <i * 1.3 - 1.3, 0.3, j * 1.3 - 1.3>;\n"
         "  if (i + j) % 2 == 0 {\n"
         "    object { wheel material mirror 0.8 rotate <90, 30 * i, 0> translate p\n"
         "      motion { rotate <0, 0, 90 + 20 * j> pivot p translate <0.2, 0, 0.1> } }\n"
         "  } else {\n"
         "    object { block material mirror 0.8 rotate <0, 30 * i, 0> translate p\n"
         "      motion { rotate <0, 90 + 20 * j, 0> pivot p translate <0.2, 0, 0.1> } }\n"
         "  }\n"
         "} }\n";
  }
  const std::string scene = "render " + (tmp / "wheels.scn") + " --quiet --threads 1";
  REQUIRE(run(scene + " -o " + (tmp / "full.exr")) == 0);
  Exr full = read_exr(tmp / "full.exr");
  std::size_t lit = 0;
  for (float v : full.rgb) lit += v > 0;
  CHECK(lit > full.rgb.size() / 2);
  for (const char* crop : {"5,5,77,61", "1,1,95,71", "33,0,34,72", "50,0,51,72"}) {
    INFO("crop " << crop);
    CHECK(crop_differs(scene, crop, full, tmp) == 0);
  }
}

TEST_CASE("sample ranges merge to the one-run image within 1e-6 relative", "[e2e][split]") {
  SplitScratch tmp;
  for (const char* sampler : {"independent", "stratified", "sobol"}) {
    INFO("sampler " << sampler);
    REQUIRE(run(showcase(sampler, 7) + " -o " + (tmp / "full.exr")) == 0);
    // Uneven ranges of 7 samples (stratification is over the whole 7).
    REQUIRE(run(showcase(sampler, 7) + " --sample-range 0..1 -o " + (tmp / "a.exr")) == 0);
    REQUIRE(run(showcase(sampler, 7) + " --sample-range 1..5 -o " + (tmp / "b.exr")) == 0);
    REQUIRE(run(showcase(sampler, 7) + " --sample-range 5..7 -o " + (tmp / "c.exr")) == 0);
    CHECK(read_exr(tmp / "b.exr").attr("snell:piece_samples") == "4");
    REQUIRE(run("merge --quiet " + (tmp / "m.exr") + " " + (tmp / "c.exr") + " " + (tmp / "a.exr") +
                " " + (tmp / "b.exr")) == 0);
    Exr full = read_exr(tmp / "full.exr"), merged = read_exr(tmp / "m.exr"),
        a = read_exr(tmp / "a.exr");
    REQUIRE(merged.rgb.size() == full.rgb.size());
    const Agreement ag = agreement(full, merged, a);
    // Three float32 roundings (the piece's mean, the merge's sum, its result) of
    // sums of non-negative terms: at most ~3 · 2^-24 ≈ 1.8e-7 relative.
    CHECK(ag.worst <= 1e-6);
    // And the test can fail: one sample alone is not the image.
    CHECK(ag.piece_differs > full.rgb.size() / 2);
    CHECK(merged.attr("snell:sample_range") == "0..7");
  }
}

TEST_CASE("crops and sample-split crops merge into the full render", "[e2e][split]") {
  SplitScratch tmp;
  const std::string r = showcase("stratified", 4);
  REQUIRE(run(r + " -o " + (tmp / "full.exr")) == 0);
  REQUIRE(run(r + " --crop 0,0,20,27 -o " + (tmp / "left.exr")) == 0);
  REQUIRE(run(r + " --crop 20,0,48,11 -o " + (tmp / "top.exr")) == 0);
  REQUIRE(run(r + " --crop 20,11,48,27 --sample-range 0..3 -o " + (tmp / "br0.exr")) == 0);
  REQUIRE(run(r + " --crop 20,11,48,27 --sample-range 3..4 -o " + (tmp / "br1.exr")) == 0);
  REQUIRE(run("merge --quiet " + (tmp / "m.exr") + " " + (tmp / "top.exr") + " " +
              (tmp / "br1.exr") + " " + (tmp / "left.exr") + " " + (tmp / "br0.exr")) == 0);
  REQUIRE(run("merge --quiet " + (tmp / "m.png") + " " + (tmp / "top.exr") + " " +
              (tmp / "br1.exr") + " " + (tmp / "left.exr") + " " + (tmp / "br0.exr")) == 0);
  Exr full = read_exr(tmp / "full.exr"), m = read_exr(tmp / "m.exr");
  REQUIRE(m.spec.width == 48);
  REQUIRE(m.spec.height == 27);
  std::size_t crop_differs = 0;
  double worst = 0;
  for (int y = 0; y < 27; ++y)
    for (int x = 0; x < 48; ++x) {
      if (x < 20 || y < 11) {
        crop_differs += std::memcmp(m.at(x, y), full.at(x, y), 3 * sizeof(float)) != 0;
      } else {
        for (int k = 0; k < 3; ++k) {
          double f = full.at(x, y)[k], g = m.at(x, y)[k];
          if (f != 0 || g != 0)
            worst = std::max(worst, std::fabs(f - g) / std::max(std::fabs(f), std::fabs(g)));
        }
      }
    }
  CHECK(crop_differs == 0);
  CHECK(worst <= 1e-6);
  // The PNG goes through the same display transform as render's: identical bytes
  // to a PNG of the one-run render wherever the crops are bit-identical.
  REQUIRE(run(r + " -o " + (tmp / "full.png")) == 0);
  auto p1 = OIIO::ImageInput::open(tmp / "m.png"), p2 = OIIO::ImageInput::open(tmp / "full.png");
  REQUIRE(p1);
  REQUIRE(p2);
  std::vector<unsigned char> b1(48 * 27 * 3), b2(48 * 27 * 3);
  REQUIRE(p1->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, b1.data()));
  REQUIRE(p2->read_image(0, 0, 0, 3, OIIO::TypeDesc::UINT8, b2.data()));
  std::size_t png_differs = 0;
  for (int y = 0; y < 27; ++y)
    for (int x = 0; x < 48; ++x)
      if (x < 20 || y < 11)
        for (int k = 0; k < 3; ++k)
          png_differs += b1[(y * 48 + x) * 3 + k] != b2[(y * 48 + x) * 3 + k];
  CHECK(png_differs == 0);
}

// A farm that ran a first pass over the whole image and then split the rest of
// the samples by tiles: crops share pixels, never a (pixel, sample).
TEST_CASE("a full pass and passes split by crops merge to the one-run image", "[e2e][split]") {
  SplitScratch tmp;
  for (const char* sampler : {"independent", "stratified", "sobol"}) {
    INFO("sampler " << sampler);
    const std::string r = showcase(sampler, 4);
    REQUIRE(run(r + " -o " + (tmp / "full.exr")) == 0);
    REQUIRE(run(r + " --sample-range 0..2 -o " + (tmp / "g1.exr")) == 0);
    REQUIRE(run(r + " --crop 0,0,20,27 --sample-range 2..4 -o " + (tmp / "g2.exr")) == 0);
    // The right part split again, by rows and by samples, off the tile grid.
    REQUIRE(run(r + " --crop 20,0,48,13 --sample-range 2..4 -o " + (tmp / "g3.exr")) == 0);
    REQUIRE(run(r + " --crop 20,13,48,27 --sample-range 2..3 -o " + (tmp / "g4.exr")) == 0);
    REQUIRE(run(r + " --crop 20,13,48,27 --sample-range 3..4 -o " + (tmp / "g5.exr")) == 0);
    const std::string pieces = " " + (tmp / "g1.exr") + " " + (tmp / "g2.exr") + " " +
                               (tmp / "g3.exr") + " " + (tmp / "g4.exr") + " " + (tmp / "g5.exr");
    REQUIRE(run("merge --quiet " + (tmp / "m.exr") + pieces) == 0);
    // The order the pieces are named in changes no bit.
    REQUIRE(run("merge --quiet " + (tmp / "r.exr") + " " + (tmp / "g5.exr") + " " +
                (tmp / "g3.exr") + " " + (tmp / "g1.exr") + " " + (tmp / "g4.exr") + " " +
                (tmp / "g2.exr")) == 0);
    Exr full = read_exr(tmp / "full.exr"), m = read_exr(tmp / "m.exr"),
        reordered = read_exr(tmp / "r.exr"), g1 = read_exr(tmp / "g1.exr");
    REQUIRE(m.spec.width == 48);
    REQUIRE(m.spec.height == 27);
    REQUIRE(m.rgb.size() == full.rgb.size());
    const Agreement ag = agreement(full, m, g1);
    // The same three float32 roundings as a merge of sample ranges alone.
    CHECK(ag.worst <= 1e-6);
    // And the test can fail: the first pass alone is not the image.
    CHECK(ag.piece_differs > full.rgb.size() / 2);
    CHECK(std::memcmp(m.rgb.data(), reordered.rgb.data(), m.rgb.size() * sizeof(float)) == 0);
    CHECK(m.attr("snell:crop") == "0,0,48,27");
    CHECK(m.attr("snell:sample_range") == "0..4");
  }
}

TEST_CASE("merge refuses pieces that do not make one image, and writes nothing", "[e2e][split]") {
  SplitScratch tmp;
  std::ofstream(tmp / "s.scn") << "settings { resolution <12, 8> samples 4 }\n"
                                  "point_light { position <0, 5, -5> intensity 30 }\n"
                                  "sphere { center <0, 0, 0> radius 1 }\n";
  std::ofstream(tmp / "t.scn") << "settings { resolution <12, 8> samples 4 }\n"
                                  "point_light { position <0, 5, -5> intensity 30 }\n"
                                  "sphere { center <0, 0, 0> radius 1.5 }\n";
  const std::string s = "render " + (tmp / "s.scn") + " --quiet";
  REQUIRE(run(s + " --crop 0,0,6,8 -o " + (tmp / "left.exr")) == 0);
  REQUIRE(run(s + " --crop 6,0,12,8 -o " + (tmp / "right.exr")) == 0);
  REQUIRE(run(s + " --crop 5,0,12,8 -o " + (tmp / "wide_right.exr")) == 0);
  REQUIRE(run(s + " --crop 6,0,12,7 -o " + (tmp / "short_right.exr")) == 0);
  REQUIRE(run(s + " --crop 6,0,12,8 --seed 3 -o " + (tmp / "right_seed3.exr")) == 0);
  REQUIRE(run("render " + (tmp / "t.scn") + " --quiet --crop 6,0,12,8 -o " +
              (tmp / "right_t.exr")) == 0);
  REQUIRE(run(s + " --sample-range 0..2 -o " + (tmp / "s02.exr")) == 0);
  REQUIRE(run(s + " --sample-range 1..4 -o " + (tmp / "s14.exr")) == 0);
  REQUIRE(run(s + " --sample-range 3..4 -o " + (tmp / "s34.exr")) == 0);
  REQUIRE(run(s + " --crop 0,0,6,8 --sample-range 2..4 -o " + (tmp / "left24.exr")) == 0);
  REQUIRE(run(s + " --crop 6,0,12,8 --sample-range 2..4 -o " + (tmp / "right24.exr")) == 0);
  REQUIRE(run(s + " --crop 6,0,12,8 --sample-range 1..4 -o " + (tmp / "right14.exr")) == 0);
  REQUIRE(run(s + " --crop 6,0,12,7 --sample-range 2..4 -o " + (tmp / "short_right24.exr")) == 0);
  REQUIRE(run(s + " -o " + (tmp / "whole.png")) == 0);
  // The good sets merge, so each refusal below is the fault it names.
  REQUIRE(run("merge --quiet " + (tmp / "ok.exr") + " " + (tmp / "left.exr") + " " +
              (tmp / "right.exr")) == 0);
  REQUIRE(run("merge --quiet " + (tmp / "ok.exr") + " " + (tmp / "s02.exr") + " " +
              (tmp / "left24.exr") + " " + (tmp / "right24.exr")) == 0);
  std::ofstream(tmp / "keep.exr") << "previous contents";
  struct Case {
    const char* what;
    std::vector<std::string> pieces;
    const char* says;
  };
  const std::vector<Case> cases = {
      {"a different scene", {"left.exr", "right_t.exr"}, "different scenes"},
      {"different settings", {"left.exr", "right_seed3.exr"}, "different settings"},
      {"overlapping crops", {"left.exr", "wide_right.exr"}, "overlap"},
      {"a piece given twice", {"left.exr", "right.exr", "right.exr"}, "both hold samples"},
      {"pixels not covered", {"left.exr", "short_right.exr"}, "do not cover"},
      {"overlapping sample ranges", {"s02.exr", "s14.exr"}, "both hold samples 1..2"},
      {"samples not covered", {"s02.exr", "s34.exr"}, "no piece holds samples 2..3"},
      {"one crop alone", {"left.exr"}, "do not cover"},
      {"a pass and a crop sharing samples",
       {"s02.exr", "left24.exr", "right14.exr"},
       "overlap: both hold samples 1..2 of pixels 6,0,12,8"},
      {"a pass and a crop leaving samples out",
       {"s02.exr", "left24.exr"},
       "no piece holds samples 2..4 of pixels 6,0,12,8"},
      {"a pass and crops leaving a row's samples out",
       {"s02.exr", "left24.exr", "short_right24.exr"},
       "no piece holds samples 2..4 of pixels 6,7,12,8"},
  };
  for (const Case& c : cases) {
    INFO(c.what);
    std::string args = "merge " + (tmp / "keep.exr");
    for (const std::string& p : c.pieces) args += " " + (tmp / p);
    CHECK(run(args, tmp / "log.txt") == 1);
    std::string log = slurp(tmp / "log.txt");
    INFO(log);
    CHECK(log.find(c.says) != std::string::npos);
    CHECK(log.find("nothing written") != std::string::npos);
    CHECK(slurp(tmp / "keep.exr") == "previous contents");
    std::string args_new = "merge " + (tmp / "new.exr");
    for (const std::string& p : c.pieces) args_new += " " + (tmp / p);
    CHECK(run(args_new) == 1);
    CHECK(!fs::exists(tmp / "new.exr"));
  }
  // Not a piece: a PNG (usage, 2), a missing file (3), an EXR without metadata (1).
  CHECK(run("merge " + (tmp / "n.exr") + " " + (tmp / "whole.png")) == 2);
  CHECK(run("merge " + (tmp / "n.exr") + " " + (tmp / "left.exr") + " " + (tmp / "gone.exr"),
            tmp / "log.txt") == 3);
  CHECK(slurp(tmp / "log.txt").find("gone.exr: it does not exist") != std::string::npos);
  // A folder is said to be one (OpenImageIO: "Could not open file").
  fs::create_directories(tmp / "dir.exr");
  CHECK(run("merge " + (tmp / "n.exr") + " " + (tmp / "dir.exr"), tmp / "log.txt") == 3);
  CHECK(slurp(tmp / "log.txt").find("dir.exr: it is a folder") != std::string::npos);
  {
    OIIO::ImageSpec spec(4, 4, 3, OIIO::TypeDesc::FLOAT);
    auto out = OIIO::ImageOutput::create(tmp / "plain.exr");
    REQUIRE(out);
    std::vector<float> zero(48, 0.0f);
    REQUIRE(out->open(tmp / "plain.exr", spec));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, zero.data()));
    out->close();
  }
  CHECK(run("merge " + (tmp / "n.exr") + " " + (tmp / "plain.exr"), tmp / "log.txt") == 1);
  CHECK(slurp(tmp / "log.txt").find("not a piece of a Snell render") != std::string::npos);
  CHECK(run("merge " + (tmp / "n.exr")) == 2);  // no pieces
  CHECK(!fs::exists(tmp / "n.exr"));
}

TEST_CASE("animation: a frame's new scene warning is printed once, with its frame",
          "[e2e][animation]") {
  // The sphere grows with the frame: the camera is inside it from frame 4 on. Only
  // the first frame's warnings were printed (none here); now each new one is, once.
  SplitScratch tmp;
  std::ofstream(tmp / "grow.scn") << "settings { resolution <4, 3> samples 1 }\n"
                                     "camera { location <0, 0, -5> }\n"
                                     "point_light { position <0, 5, -5> intensity 10 }\n"
                                     "sphere { radius 1 + clock + frame }\n";
  REQUIRE(run("render " + (tmp / "grow.scn") + " --quiet --threads 1 --frames 3..7 -o " +
                  (tmp / "g_##.exr"),
              tmp / "log.txt") == 0);
  const std::string log = slurp(tmp / "log.txt");
  INFO(log);
  CHECK(log.find("is inside the sphere") != std::string::npos);
  CHECK(log.find("(frame 4)") != std::string::npos);
  CHECK(log.find("(frame 3)") == std::string::npos);
  CHECK(log.find("(frame 5)") == std::string::npos);  // the same warning again
}

TEST_CASE("animation: --frames renders each frame with its clock and names it",
          "[e2e][animation]") {
  SplitScratch tmp;
  // No objects: every pixel is the background, <clock, frame / 10, 0.5>.
  std::ofstream(tmp / "a.scn") << "settings { resolution <4, 2> }\n"
                                  "background <clock, frame / 10, 0.5>\n";
  const std::string a = "render " + (tmp / "a.scn") + " --quiet";
  REQUIRE(run(a + " --frames 2..6 -o " + (tmp / "run_##.exr") + " -o " + (tmp / "plain.exr") +
                  " --stats",
              tmp / "log.txt") == 0);
  for (int f = 2; f < 6; ++f) {
    INFO("frame " << f);
    char hashed[32], plain[32];
    std::snprintf(hashed, sizeof hashed, "run_%02d.exr", f);
    std::snprintf(plain, sizeof plain, "plain_%04d.exr", f);
    Exr e = read_exr(tmp / hashed);
    CHECK(e.at(0, 0)[0] == float((f - 2) / 4.0));
    CHECK(e.at(3, 1)[1] == float(f / 10.0));
    CHECK(e.attr("snell:frame") == std::to_string(f));
    CHECK(fs::exists(tmp / plain));
  }
  CHECK(!fs::exists(tmp / "run_06.exr"));
  CHECK(!fs::exists(tmp / "plain.exr"));
  std::string log = slurp(tmp / "log.txt");
  CHECK(log.find("total over 4 frames") != std::string::npos);
  CHECK(log.find("frame 5 (4/4, clock 0.75)") == std::string::npos);  // --quiet
  // Progress: one line a frame with an ETA.
  REQUIRE(run("render " + (tmp / "a.scn") + " --frames 0..2 -o " + (tmp / "p.exr"),
              tmp / "log.txt") == 0);
  log = slurp(tmp / "log.txt");
  CHECK(log.find("frame 0 (1/2, clock 0) done") != std::string::npos);
  CHECK(log.find("frame 1 (2/2, clock 0.5) done") != std::string::npos);
  CHECK(log.find("ETA") != std::string::npos);
  // --clock: one frame, its name as given (frame stays 0).
  REQUIRE(run(a + " --clock 0.625 -o " + (tmp / "one_#.exr")) == 0);
  Exr one = read_exr(tmp / "one_#.exr");
  CHECK(one.at(1, 1)[0] == 0.625f);
  CHECK(one.at(1, 1)[1] == 0.0f);
  // --frame F: one frame of the sequence, with the sequence's clock (a farm task).
  REQUIRE(run(a + " --frames 2..6 --frame 4 -o " + (tmp / "task_##.exr")) == 0);
  Exr task = read_exr(tmp / "task_04.exr");
  CHECK(task.at(0, 0)[0] == 0.5f);
  CHECK(task.at(0, 0)[1] == 0.4f);
  CHECK(!fs::exists(tmp / "task_02.exr"));
  CHECK(!fs::exists(tmp / "task_05.exr"));
  // A frame number wider than its # run is written whole.
  REQUIRE(run(a + " --frames 9..11 -o " + (tmp / "w#.exr")) == 0);
  CHECK(fs::exists(tmp / "w9.exr"));
  CHECK(fs::exists(tmp / "w10.exr"));
  // An error that only a later frame's clock makes says which frame it was; the
  // frames before it are written.
  std::ofstream(tmp / "late.scn") << "settings { resolution <4, 2> }\n"
                                     "sphere { radius 0.5 - clock }\n";
  CHECK(run("render " + (tmp / "late.scn") + " --quiet --frames 0..4 -o " + (tmp / "l#.exr"),
            tmp / "log.txt") == 1);
  log = slurp(tmp / "log.txt");
  CHECK(log.find("error") != std::string::npos);
  CHECK(log.find("in frame 2 of --frames 0..4 (clock 0.5)") != std::string::npos);
  CHECK(fs::exists(tmp / "l1.exr"));
  CHECK(!fs::exists(tmp / "l2.exr"));
}

// --dump-ir under --frames shows every frame's scene, each under its frame and
// clock (it showed frame A's alone, without saying so).
TEST_CASE("animation: --dump-ir shows each frame's scene", "[e2e][animation]") {
  SplitScratch tmp;
  std::ofstream(tmp / "c.scn") << "settings { resolution <8, 6> }\nsphere { radius 1 + clock }\n";
  REQUIRE(run("render " + (tmp / "c.scn") + " --dump-ir --frames 0..3", tmp / "ir.txt") == 0);
  const std::string ir = slurp(tmp / "ir.txt");
  CHECK(ir.find("frame 0 (clock 0):") != std::string::npos);
  CHECK(ir.find("frame 2 (clock 0.6666666666666666):") != std::string::npos);
  CHECK(ir.find("radius 1.6666666666666665") != std::string::npos);
  CHECK(ir.find("frame 3") == std::string::npos);
}

TEST_CASE("animation and split options: usage errors exit 2 and write nothing",
          "[e2e][animation][split]") {
  SplitScratch tmp;
  std::ofstream(tmp / "ok.scn") << "settings { resolution <8, 6> samples 4 }\nsphere { }\n";
  const std::string r = "render " + (tmp / "ok.scn") + " --quiet -o " + (tmp / "x.exr");
  for (const char* bad : {"--frames 5..3",
                          "--frames 3..3",
                          "--frames 3",
                          "--frames a..b",
                          "--frames -1..2",
                          "--frames 0..2 --clock 0.5",
                          "--frame 1",
                          "--frames 0..2 --frame 2",
                          "--frames 2..4 --frame 1",
                          "--clock abc",
                          "--crop 0,0,9,6",
                          "--crop 4,0,4,6",
                          "--crop 1,2,3",
                          "--crop 0,0,8,6,1",
                          "--crop -1,0,8,6",
                          "--sample-range 0..5",
                          "--sample-range 2..2",
                          "--sample-range 3..1",
                          "--sample-range x",
                          "--pixel 7,5 --crop 0,0,4,4"}) {
    INFO(bad);
    CHECK(run(r + " " + bad) == 2);
  }
  // --dump-ast takes the same options, and the same are wrong (it ignored them all).
  for (const char* bad :
       {"--frames 0..2 --clock 0.5", "--frames 3..1", "--frame 1", "--features bogus"}) {
    INFO(bad);
    CHECK(run("render " + (tmp / "ok.scn") + " --dump-ast " + bad) == 2);
  }
  CHECK(run("render " + (tmp / "ok.scn") + " --dump-ast -o " + (tmp / "x.foo")) == 2);
  CHECK(run("render " + (tmp / "ok.scn") + " --dump-ast --frames 0..2") == 0);
  // --dump-ir, after the scene's size is known: what does not fit it is wrong too.
  for (const char* bad : {"--pixel garbage", "--crop 1,1,0,0", "--sample-range 5..9"}) {
    INFO(bad);
    CHECK(run("render " + (tmp / "ok.scn") + " --dump-ir " + bad) == 2);
  }
  CHECK(run("render " + (tmp / "ok.scn") + " --dump-ir --pixel 3,3") == 0);
  CHECK(!fs::exists(tmp / "x.exr"));
  CHECK(!fs::exists(tmp / "x_0000.exr"));
  CHECK(run("merge --help") == 0);
  CHECK(run("merge") == 2);
}
