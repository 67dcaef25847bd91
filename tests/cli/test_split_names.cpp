// §18's command-line values: A..B ranges, frame clocks and output names, crops.
#include <catch2/catch.hpp>

#include "cli/animation.hpp"
#include "cli/split.hpp"

using namespace snell;

TEST_CASE("A..B ranges: integers, A < B, inside the limit", "[cli][animation]") {
  cli::IntRange r;
  std::string err;
  REQUIRE(cli::parse_range("2..6", "--frames", 100, r, err));
  CHECK(r.begin == 2);
  CHECK(r.end == 6);
  CHECK(r.size() == 4);
  REQUIRE(cli::parse_range("0..8", "--sample-range", 8, r, err));
  for (const char* bad : {"5..3", "3..3", "3", "..3", "3..", "a..b", "1.5..3", "-1..2", "0..9",
                          "1..2..3", " 1..2", ""}) {
    INFO(bad);
    err.clear();
    CHECK(!cli::parse_range(bad, "--sample-range", 8, r, err));
    CHECK(err.find("--sample-range") != std::string::npos);
  }
  CHECK(!cli::parse_range("5..3", "--frames", 100, r, err));
  CHECK(err.find("B must be greater than A") != std::string::npos);
}

TEST_CASE("a frame's clock is (frame - A) / (B - A)", "[cli][animation]") {
  cli::IntRange f{10, 14};
  CHECK(cli::frame_clock(f, 10) == 0);
  CHECK(cli::frame_clock(f, 11) == 0.25);
  CHECK(cli::frame_clock(f, 13) == 0.75);  // the last frame's clock is below 1
  CHECK(cli::frame_clock({0, 1}, 0) == 0);
}

TEST_CASE("frame output names: a # run, else _NNNN before the extension", "[cli][animation]") {
  CHECK(cli::frame_output_name("out_####.png", 7) == "out_0007.png");
  CHECK(cli::frame_output_name("out_#.exr", 7) == "out_7.exr");
  CHECK(cli::frame_output_name("out_#.exr", 123) == "out_123.exr");  // wider than the run
  CHECK(cli::frame_output_name("a##b##.png", 3) == "a##b03.png");    // the last run only
  CHECK(cli::frame_output_name("shots/f##/x.png", 3) == "shots/f##/x_0003.png");  // not folders
  CHECK(cli::frame_output_name("dir/out.png", 12) == "dir/out_0012.png");
  CHECK(cli::frame_output_name("out.png", 12345) == "out_12345.png");
  CHECK(cli::frame_output_name("a.b.exr", 1) == "a.b_0001.exr");
}

TEST_CASE("crops: X0,Y0,X1,Y1 inside the image, non-empty", "[cli][split]") {
  cli::Window w;
  std::string err;
  REQUIRE(cli::parse_crop("0,0,640,480", 640, 480, w, err));
  REQUIRE(cli::parse_crop("5,3,37,22", 640, 480, w, err));
  CHECK(w.x0 == 5);
  CHECK(w.y0 == 3);
  CHECK(w.x1 == 37);
  CHECK(w.y1 == 22);
  CHECK(cli::to_string(w) == "5,3,37,22");
  for (const char* bad : {"0,0,641,480", "0,0,640,481", "4,0,4,8", "5,0,4,8", "1,2,3", "1,2,3,4,5",
                          "-1,0,4,4", "a,0,4,4", "1,2,3,4,", "1 ,2,3,4", ""}) {
    INFO(bad);
    CHECK(!cli::parse_crop(bad, 640, 480, w, err));
  }
}
