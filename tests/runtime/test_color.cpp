// sRGB codes through the OCIO path (robustness.md §3.8) and image writing.
#include <catch2/catch.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>

#include "runtime/color.hpp"
#include "runtime/render.hpp"

using namespace snell::rt;

TEST_CASE("OCIO sRGB display transform gives the reference 8-bit codes", "[color]") {
  const float lin[] = {0.0f, 0.0031308f, 0.01f, 0.18f, 0.2140411f, 0.5f, 0.9f, 1.0f, 4.0f, -1.0f};
  const int code[] = {0, 10, 25, 118, 127, 188, 243, 255, 255, 0};
  std::vector<float> rgb;
  for (float v : lin) rgb.insert(rgb.end(), {v, v, v});
  REQUIRE(apply_display_transform("", rgb.data(), rgb.size() / 3) == "");
  for (std::size_t i = 0; i < std::size(lin); ++i) {
    INFO("linear " << lin[i]);
    CHECK(int(quantize8(rgb[3 * i])) == code[i]);
    CHECK(int(quantize8(rgb[3 * i + 1])) == code[i]);
  }
  CHECK(quantize8(NAN) == 0);
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
  CHECK(write_image((dir / "a.exr").string(), im, info, "") == "");
  CHECK(write_image((dir / "a.png").string(), im, info, "") == "");
  CHECK(fs::file_size(dir / "a.exr") > 0);
  CHECK(fs::file_size(dir / "a.png") > 0);
  // A failing write leaves the old file untouched and no temporary behind.
  { std::ofstream(dir / "b.png") << "old"; }
  CHECK(write_image((dir / "b.png").string(), im, info, "/nonexistent/config.ocio") != "");
  CHECK(fs::file_size(dir / "b.png") == 3);
  CHECK(write_image((dir / "missing" / "c.exr").string(), im, info, "") != "");
  int files = 0;
  for (auto& e : fs::directory_iterator(dir)) (void)e, ++files;
  CHECK(files == 3);
  CHECK_FALSE(is_supported_image_extension("x.bmp"));
  CHECK(is_supported_image_extension("x.JPG"));
  fs::remove_all(dir);
}
