// sRGB codes through the OCIO path (robustness.md §3.8) and image writing.
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "runtime/color.hpp"
#include "runtime/primaries.hpp"
#include "runtime/render.hpp"

using namespace snell::rt;

TEST_CASE("OCIO sRGB display transform gives the reference 8-bit codes", "[color]") {
  const float lin[] = {0.0f, 0.0031308f, 0.01f, 0.18f, 0.2140411f, 0.5f, 0.9f, 1.0f, 4.0f, -1.0f};
  const int code[] = {0, 10, 25, 118, 127, 188, 243, 255, 255, 0};
  std::vector<float> rgb;
  for (float v : lin) rgb.insert(rgb.end(), {v, v, v});
  std::string error;
  auto srgb = ColorTransform::to_display({}, error);
  REQUIRE(srgb);
  CHECK(error == "");
  srgb->apply(rgb.data(), rgb.size() / 3);
  for (std::size_t i = 0; i < std::size(lin); ++i) {
    INFO("linear " << lin[i]);
    CHECK(int(quantize8(rgb[3 * i])) == code[i]);
    CHECK(int(quantize8(rgb[3 * i + 1])) == code[i]);
  }
  CHECK(quantize8(NAN) == 0);
}

TEST_CASE("a studio OCIO config: its default display and view, or the ones named", "[color]") {
  // tests/ocio/studio.ocio: codes follow by formula (its header says which).
  const float lin[] = {0.0f, 0.01f, 0.18f, 0.5f, 1.0f};
  auto codes_of = [&](const DisplayView& dv, std::string& error) {
    std::vector<int> codes;
    auto t = ColorTransform::to_display(dv, error);
    if (!t) return codes;
    std::vector<float> rgb;
    for (float v : lin) rgb.insert(rgb.end(), {v, v, v});
    t->apply(rgb.data(), rgb.size() / 3);
    for (std::size_t i = 0; i < std::size(lin); ++i) codes.push_back(quantize8(rgb[3 * i + 1]));
    return codes;
  };
  auto expected = [&](double gamma) {
    std::vector<int> codes;
    for (float v : lin) codes.push_back(int(std::lround(std::pow(double(v), 1 / gamma) * 255)));
    return codes;
  };
  std::string error;
  CHECK(codes_of({SNELL_STUDIO_OCIO, "", ""}, error) == expected(2.2));
  CHECK(error == "");
  CHECK(codes_of({SNELL_STUDIO_OCIO, "Rec.1886", ""}, error) == expected(2.4));
  CHECK(codes_of({SNELL_STUDIO_OCIO, "Rec.1886", "Raw"}, error) == expected(1.0));
  CHECK(error == "");
  // What does not exist is named, with what does.
  CHECK(codes_of({SNELL_STUDIO_OCIO, "sRGB - Display", ""}, error).empty());
  CHECK(error.find("has no display 'sRGB - Display' (it has 'Gamma 2.2 Monitor' and "
                   "'Rec.1886')") != std::string::npos);
  CHECK(codes_of({SNELL_STUDIO_OCIO, "", "Standard"}, error).empty());
  CHECK(error.find("the display 'Gamma 2.2 Monitor' has no view 'Standard' (it has 'Display "
                   "Gamma' and 'Raw')") != std::string::npos);
  // Snell's own config: its defaults are the sRGB display's Standard view.
  auto own = ColorTransform::to_display({}, error);
  REQUIRE(own);
  CHECK(own->name() == "sRGB - Display / Standard");
}

TEST_CASE("a file's colour space converts to scene_linear through the config", "[color]") {
  std::string error;
  auto x2 = ColorTransform::to_scene_linear(SNELL_STUDIO_OCIO, "scaled linear X2", error);
  REQUIRE(x2);  // names are matched without regard to case
  float rgb[3] = {0.25f, 0.5f, 1.5f};
  x2->apply(rgb, 1);
  CHECK(rgb[0] == Approx(0.5f));
  CHECK(rgb[1] == Approx(1.0f));
  CHECK(rgb[2] == Approx(3.0f));
  CHECK_FALSE(ColorTransform::to_scene_linear(SNELL_STUDIO_OCIO, "ACEScg", error));
  CHECK(error.find("has no colour space 'ACEScg'") != std::string::npos);
  // Snell's config has the ACES working spaces.
  CHECK(ColorTransform::to_scene_linear("", "ACEScg", error));
}

TEST_CASE("primaries convert to Rec.709 by the published matrices", "[color]") {
  std::string err;
  Mat3f m;
  // Rec.709 itself is the identity (to float rounding of its own round trip).
  REQUIRE(rec709_from(kRec709Chromaticities, m, err));
  for (int i = 0; i < 9; ++i) CHECK(m[i] == Approx(i % 4 == 0 ? 1.0 : 0.0).margin(1e-6));
  CHECK(is_rec709(kRec709Chromaticities));
  // ACEScg (AP1, ACES white ~D60) to linear Rec.709/D65 with Bradford adaptation:
  // the matrix as published with four decimals (e.g. colour-science, and OCIO's
  // ACES configs), so 1e-4 is their rounding.
  const Chromaticities ap1 = {0.713f, 0.293f, 0.165f, 0.830f, 0.128f, 0.044f, 0.32168f, 0.33767f};
  const float want[9] = {1.7051f,  -0.6218f, -0.0833f, -0.1303f, 1.1408f,
                         -0.0105f, -0.0240f, -0.1290f, 1.1530f};
  CHECK_FALSE(is_rec709(ap1));
  REQUIRE(rec709_from(ap1, m, err));
  for (int i = 0; i < 9; ++i) {
    INFO("entry " << i);
    CHECK(m[i] == Approx(want[i]).margin(1.5e-4));
  }
  // White stays white when the file's white is D65: each row sums to 1.
  const Chromaticities p3d65 = {0.680f, 0.320f, 0.265f, 0.690f, 0.150f, 0.060f, 0.3127f, 0.3290f};
  REQUIRE(rec709_from(p3d65, m, err));
  for (int r = 0; r < 3; ++r)
    CHECK(m[3 * r] + m[3 * r + 1] + m[3 * r + 2] == Approx(1).margin(1e-5));
  // Not primaries: collinear, a zero y, a NaN.
  for (Chromaticities bad :
       {Chromaticities{0.2f, 0.2f, 0.4f, 0.4f, 0.6f, 0.6f, 0.3127f, 0.329f},
        Chromaticities{0.64f, 0.33f, 0.3f, 0.0f, 0.15f, 0.06f, 0.3127f, 0.329f},
        Chromaticities{0.64f, NAN, 0.3f, 0.6f, 0.15f, 0.06f, 0.3127f, 0.329f}}) {
    err.clear();
    CHECK_FALSE(rec709_from(bad, m, err));
    CHECK(err.find("not a set of RGB primaries") != std::string::npos);
  }
}

TEST_CASE("write_image writes EXR and PNG atomically", "[color][io]") {
  namespace fs = std::filesystem;
  fs::path dir = fs::temp_directory_path() / "snell_rt_test_io";
  fs::remove_all(dir);
  fs::create_directories(dir);
  Image im;
  im.width = 4;
  im.height = 2;
  im.rgb.assign(4 * 2 * 3, 0.18f);
  OutputInfo info{"test.scn", 4, 1, 0.5, {}};
  CHECK(write_image((dir / "a.exr").string(), im, info, {}) == "");
  CHECK(write_image((dir / "a.png").string(), im, info, {}) == "");
  CHECK(fs::file_size(dir / "a.exr") > 0);
  CHECK(fs::file_size(dir / "a.png") > 0);
  // A failing write leaves the old file untouched and no temporary behind.
  { std::ofstream(dir / "b.png") << "old"; }
  CHECK(write_image((dir / "b.png").string(), im, info, {"/nonexistent/config.ocio", "", ""}) !=
        "");
  CHECK(fs::file_size(dir / "b.png") == 3);
  CHECK(write_image((dir / "missing" / "c.exr").string(), im, info, {}) != "");
  int files = 0;
  for (auto& e : fs::directory_iterator(dir)) (void)e, ++files;
  CHECK(files == 3);
  CHECK_FALSE(is_supported_image_extension("x.bmp"));
  CHECK(is_supported_image_extension("x.JPG"));
  fs::remove_all(dir);
}
