// The command line end to end (spec §10): exit codes, usage errors under the
// option's own name, what check and render print, outputs that cannot be written.
#include <OpenImageIO/imageio.h>
#include <sys/resource.h>
#include <sys/stat.h>

#include <catch2/catch.hpp>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/e2e/e2e_util.hpp"

using namespace snell::e2e;

TEST_CASE("exit codes follow spec §10", "[e2e]") {
  Scratch tmp;
  std::ofstream(tmp / "bad.scn") << "sphere { radus 1 }\n";
  std::ofstream(tmp / "ok.scn") << "settings { resolution <8, 8> }\nsphere { }\n";
  CHECK(run("render " + (tmp / "ok.scn") + " --quiet -o " + (tmp / "ok.png")) == 0);
  CHECK(run("render " + (tmp / "bad.scn") + " --quiet -o " + (tmp / "x.png")) == 1);
  CHECK(!fs::exists(tmp / "x.png"));
  CHECK(run("check " + (tmp / "bad.scn")) == 1);
  CHECK(run("check " + (tmp / "ok.scn")) == 0);
  // What goes to stdout is output too: a full disk behind it is exit 3, not a loss.
  for (const std::string& cmd : {"check " + (tmp / "ok.scn"), "dump-ast " + (tmp / "ok.scn"),
                                 "render " + (tmp / "ok.scn") + " --dump-ir"}) {
    INFO(cmd);
    int status = std::system((kSnell + " " + cmd + " > /dev/full 2> /dev/null").c_str());
    CHECK((WIFEXITED(status) ? WEXITSTATUS(status) : -1) == 3);
  }
  CHECK(run("render " + (tmp / "missing.scn")) == 3);
  CHECK(run("render") == 2);
  CHECK(run("render " + (tmp / "ok.scn") + " --bogus") == 2);
  CHECK(run("render " + (tmp / "ok.scn") + " -o " + (tmp / "out.bmp")) == 2);
  CHECK(run("render " + (tmp / "ok.scn") + " --set nope=1") == 2);
  CHECK(run("render " + (tmp / "ok.scn") + " --res 10by10") == 2);
  // A film the machine cannot hold is refused up front, never an abort.
  CHECK(run("render " + (tmp / "ok.scn") + " --quiet --res 100000x100000") == 2);
  std::ofstream(tmp / "huge.scn") << "settings { resolution <100000, 100000> }\nsphere { }\n";
  CHECK(run("render " + (tmp / "huge.scn") + " --quiet -o " + (tmp / "huge.png")) == 1);
  CHECK(run("render " + (tmp / "ok.scn") + " --quiet -o " + (tmp / "no/such/dir/x.png")) == 3);
  // A file the scene names that cannot be read is exit 3 too; with any other
  // error beside it, the scene's errors decide (1).
  std::ofstream(tmp / "nomesh.scn") << "mesh { file \"nowhere.obj\" }\n";
  std::ofstream(tmp / "noimport.scn") << "import \"nowhere.scn\";\nsphere { }\n";
  std::ofstream(tmp / "both.scn") << "mesh { file \"nowhere.obj\" }\nsphere { radus 1 }\n";
  CHECK(run("check " + (tmp / "nomesh.scn")) == 3);
  CHECK(run("render " + (tmp / "nomesh.scn") + " --quiet -o " + (tmp / "m.png")) == 3);
  CHECK(!fs::exists(tmp / "m.png"));
  CHECK(run("check " + (tmp / "noimport.scn")) == 3);
  CHECK(run("check " + (tmp / "both.scn")) == 1);
  // §17: a missing image is exit 3 at compile time; one that exists but is not an
  // image is found by the texture system before the render (exit 3, no output).
  std::ofstream(tmp / "noimage.scn")
      << "sphere { material diffuse { color image { file \"nowhere.png\" } } }\n";
  CHECK(run("check " + (tmp / "noimage.scn")) == 3);
  CHECK(run("render " + (tmp / "noimage.scn") + " --quiet -o " + (tmp / "i.png")) == 3);
  std::ofstream(tmp / "text.png") << "not an image\n";
  std::ofstream(tmp / "badimage.scn")
      << "settings { resolution <8, 8> }\nbackground image { file \"text.png\" mapping "
         "\"latlong\" }\n";
  CHECK(run("render " + (tmp / "badimage.scn") + " --quiet -o " + (tmp / "b.png")) == 3);
  CHECK(!fs::exists(tmp / "b.png"));
}

TEST_CASE("every subcommand's usage errors exit 2, its --help 0", "[e2e]") {
  Scratch tmp;
  std::ofstream(tmp / "ok.scn") << "settings { resolution <8, 8> }\nsphere { }\n";
  const std::string ok = tmp / "ok.scn";
  for (const char* sub : {"render", "check", "sweep", "dump-ast"}) {
    INFO(sub);
    CHECK(run(std::string(sub) + " --help") == 0);
    CHECK(run(sub) == 2);  // no scene
    CHECK(run(std::string(sub) + " " + ok + " --bogus") == 2);
  }
  CHECK(run("render " + ok + " --spp 0") == 2);
  CHECK(run("render " + ok + " --seed 4294967296") == 2);
  // Said in Snell's form, as every other usage error (the argument parser's own
  // lines were "--spp: Value 0 not in range ..." and "Run with --help ...").
  std::string err;
  CHECK(run_capture("render " + ok + " --spp 0", err, tmp) == 2);
  CHECK(err.rfind("snell: error: --spp: Value 0 not in range 1 to 1048576\n", 0) == 0);
  CHECK(err.find("Run with --help") == std::string::npos);
  CHECK(run_capture("render " + ok + " --bogus", err, tmp) == 2);
  CHECK(err.rfind("snell: error: ", 0) == 0);
  CHECK(run("check " + ok + " --spp 4") == 2);  // a render option
  CHECK(run("check " + ok + " --set x") == 2);
  CHECK(run("sweep " + ok) == 2);  // no --vary
  CHECK(run("sweep " + ok + " --vary samples=1 --repeats 0") == 2);
  CHECK(run("sweep " + ok + " --vary bad") == 2);
  CHECK(run("sweep " + ok + " --vary samples=1 --series bad") == 2);
  CHECK(run("dump-ast " + ok + " -I .") == 2);
  // Counts are not negative (an unsigned field read "-5" as 2^64 - 5: no limit).
  CHECK(run("check " + ok + " --max-steps -5") == 2);
  CHECK(run("check " + ok + " --max-steps 0") == 2);
  CHECK(run("check " + ok + " --max-steps 1e20") == 2);
  CHECK(run("check " + ok + " --max-errors -5") == 2);
  CHECK(run("check " + ok + " --max-errors 99999999999999999999") == 2);
  CHECK(run("check " + ok + " --max-steps 1000000 --max-errors 0") == 0);
  // §18's clock is a number: one that is not finite is wrong usage, not a scene
  // error at the line that reads it (nor exit 0 for a scene that does not).
  std::ofstream(tmp / "clock.scn") << "settings { resolution <8, 8> }\nlet x = clock * 2;\n"
                                      "sphere { }\n";
  for (const char* c : {"nan", "inf", "-inf", "1e400"}) {
    INFO(c);
    CHECK(run("render " + ok + " --quiet --clock " + c + " -o " + (tmp / "c.exr")) == 2);
    CHECK(run("render " + (tmp / "clock.scn") + " --quiet --clock " + c + " -o " +
              (tmp / "c.exr")) == 2);
  }
  CHECK(!fs::exists(tmp / "c.exr"));
  CHECK(run("render " + (tmp / "clock.scn") + " --quiet --clock 0.25 -o " + (tmp / "c.exr")) == 0);
}

// snell watch prints its URL only once it runs: options that no edit of the scene
// fixes are exit 2 with nothing on stdout (a script that reads the URL took the
// watch as started).
TEST_CASE("watch's bad options exit 2 before any URL is printed", "[e2e]") {
  Scratch tmp;
  std::ofstream(tmp / "w.scn") << "sphere { }\n";
  for (const char* opt : {"--set foo=1", "--res 0x0", "--set samples=-1"}) {
    INFO(opt);
    const std::string out = tmp / "stdout.txt";
    int status = std::system(("timeout 20 " + kSnell + " watch " + (tmp / "w.scn") + " --port 0 " +
                              opt + " > " + out + " 2> /dev/null")
                                 .c_str());
    CHECK((WIFEXITED(status) ? WEXITSTATUS(status) : -1) == 2);
    CHECK(slurp(out).empty());
  }
}

TEST_CASE("a failed write leaves an existing output untouched", "[e2e]") {
  Scratch tmp;
  std::ofstream(tmp / "ok.scn") << "settings { resolution <8, 8> }\nsphere { }\n";
  fs::create_directories(tmp / "ro");
  std::ofstream(tmp / "ro/keep.png") << "previous contents";
  fs::permissions(tmp / "ro", fs::perms::owner_read | fs::perms::owner_exec);
  bool root = ::geteuid() == 0;  // root ignores directory permissions
  int code = run("render " + (tmp / "ok.scn") + " --quiet -o " + (tmp / "ro/keep.png"));
  fs::permissions(tmp / "ro", fs::perms::owner_all);
  if (!root) {
    CHECK(code == 3);
    CHECK(slurp(tmp / "ro/keep.png") == "previous contents");
  }
  // No temporary file is left behind either way.
  for (const auto& e : fs::directory_iterator(tmp / "ro")) CHECK(e.path().filename() == "keep.png");
}

TEST_CASE("a file-size limit is exit 3, the old file kept, the later outputs tried", "[e2e]") {
  // ulimit -f: SIGXFSZ killed the process (exit 153) mid-write, leaving its
  // temporary and never reaching the next output.
  Scratch tmp;
  std::ofstream(tmp / "b.scn") << "settings { resolution <64, 48> }\n"
                                  "point_light { position <0, 5, -5> intensity 20 }\n"
                                  "sphere { center <0, 0, 5> }\n";
  std::ofstream(tmp / "big.exr") << "previous contents";
  const std::string log = tmp / "log.txt";
  int status =
      std::system(("cd " + tmp.dir.string() + " && (ulimit -f 2; " + kSnell +
                   " render b.scn -q --threads 1 -o big.exr -o small.png) > " + log + " 2>&1")
                      .c_str());
  const std::string out = slurp(log);
  INFO(out);
  CHECK((WIFEXITED(status) ? WEXITSTATUS(status) : -1) == 3);
  CHECK(out.find("cannot write big.exr: File too large") != std::string::npos);
  CHECK(slurp(tmp / "big.exr") == "previous contents");
  // The next output is tried (and fails on its own, or is written when it fits).
  CHECK((out.find("cannot write small.png") != std::string::npos || fs::exists(tmp / "small.png")));
  for (const auto& e : fs::directory_iterator(tmp.dir))
    CHECK(e.path().filename().string().find("snell-tmp") == std::string::npos);
}

TEST_CASE("snell check lists the effects a scene uses", "[e2e]") {
  Scratch tmp;
  std::ofstream(tmp / "fx.scn")
      << "camera { aperture 0.1 location <0,0,-5> look_at 0 }\n"
         "area_light { corner 0 edge1 <1,0,0> edge2 <0,0,1> radiance 1 }\n"
         "sphere { material dielectric <1.5, 0.2> }\n";
  std::string cmd = kSnell + " check " + (tmp / "fx.scn") + " > " + (tmp / "out.txt");
  REQUIRE(std::system(cmd.c_str()) == 0);
  const std::string out = slurp(tmp / "out.txt");
  CHECK(out.find("depth of field") != std::string::npos);
  CHECK(out.find("area lights") != std::string::npos);
  CHECK(out.find("dielectric") != std::string::npos);
  CHECK(out.find("absorption") != std::string::npos);
  CHECK(out.find("motion blur:") == std::string::npos);
}

TEST_CASE("a shorthand option's bad value is reported under its own name", "[e2e]") {
  // --res, --spp and --seed are settings overrides inside; their errors name the
  // option given, not a --set the user never wrote.
  Scratch tmp;
  std::ofstream(tmp / "ok.scn") << "settings { resolution <8, 8> }\nsphere { }\n";
  std::string err;
  CHECK(run_capture("render " + (tmp / "ok.scn") + " --quiet --res 0x24 -o " + (tmp / "x.exr"), err,
                    tmp) == 2);
  CHECK(err.find("--res 0x24: 'resolution' must be >= 1") != std::string::npos);
  CHECK(err.find("--set") == std::string::npos);
  CHECK(run_capture(
            "render " + (tmp / "ok.scn") + " --quiet --set resolution=0 -o " + (tmp / "x.exr"), err,
            tmp) == 2);
  CHECK(err.find("--set resolution=0: 'resolution' must be >= 1") != std::string::npos);
  // A number option given no number says so in the same words (CLI11's own was
  // "Could not convert: --clock = abc").
  CHECK(run_capture("render " + (tmp / "ok.scn") + " --quiet --clock abc", err, tmp) == 2);
  CHECK(err.find("--clock: needs a number, not abc") != std::string::npos);
  CHECK(run_capture("render " + (tmp / "ok.scn") + " --quiet --clock 1e400", err, tmp) == 2);
  CHECK(err.find("--clock: needs a finite number, not 1e400") != std::string::npos);
}

TEST_CASE("a first word that is no command is said to be none", "[e2e]") {
  // CLI11 said "A subcommand is required" for `snell rendr a.scn` and `snell a.scn`.
  Scratch tmp;
  std::string err;
  CHECK(run_capture("rendr a.scn", err, tmp) == 2);
  CHECK(err.find("'rendr' is not a snell command") != std::string::npos);
  CHECK(err.find("did you mean 'snell render'?") != std::string::npos);
  CHECK(run_capture("a.scn", err, tmp) == 2);
  CHECK(err.find("'a.scn' is not a snell command") != std::string::npos);
  CHECK(run_capture("--version", err, tmp) == 0);
}

// §10: "all independent errors are reported, not just the first": by default
// every one (the limit is --max-errors, an opt-in).
TEST_CASE("every independent error is printed by default, --max-errors caps them", "[e2e]") {
  Scratch tmp;
  std::ofstream f(tmp / "many.scn");
  for (int i = 1; i <= 25; ++i) f << "sphere { radius -" << i << " }\n";
  f.close();
  auto count = [](const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
      ++n;
    return n;
  };
  std::string err;
  CHECK(run_capture("check " + (tmp / "many.scn"), err, tmp) == 1);
  CHECK(count(err, ": error: ") == 25);
  CHECK(err.find("TooManyErrors") == std::string::npos);
  CHECK(run_capture("check " + (tmp / "many.scn") + " --max-errors 5", err, tmp) == 1);
  CHECK(count(err, ": error: ") == 5);
  CHECK(err.find("25 in all, 20 not shown") != std::string::npos);
}

TEST_CASE("an output named twice is written once, with a warning", "[e2e]") {
  Scratch tmp;
  std::ofstream(tmp / "ok.scn") << "settings { resolution <4, 4> samples 1 }\nsphere { }\n";
  fs::create_directories(tmp / "sub");
  std::string err;
  const std::string a = tmp / "a.exr";
  REQUIRE(run_capture("render " + (tmp / "ok.scn") + " --quiet -o " + a + " -o " +
                          tmp.dir.string() + "/sub/../a.exr -o " + (tmp / "b.exr"),
                      err, tmp) == 0);
  CHECK(err.find("sub/../a.exr is the same file as -o " + a) != std::string::npos);
  CHECK(err.find("b.exr is the same") == std::string::npos);
  CHECK(fs::exists(a));
  CHECK(fs::exists(tmp / "b.exr"));
}

TEST_CASE("a settings key set twice on the command line says which one wins", "[e2e]") {
  Scratch tmp;
  std::ofstream(tmp / "ok.scn") << "settings { resolution <4, 4> samples 1 }\nsphere { }\n";
  std::string err;
  const std::string base = "render " + (tmp / "ok.scn") + " --quiet -o " + (tmp / "a.exr");
  REQUIRE(run_capture(base + " --set samples=2 --spp 3", err, tmp) == 0);
  CHECK(err.find("'samples' is set twice: --spp 3 wins over --set samples=2") != std::string::npos);
  REQUIRE(run_capture(base + " --set seed=1 --set seed=2 --set seed=3", err, tmp) == 0);
  CHECK(err.find("--set seed=3 wins over --set seed=1") != std::string::npos);
  CHECK(err.find("--set seed=3 wins over --set seed=2") != std::string::npos);
  // The same value twice is no conflict.
  REQUIRE(run_capture(base + " --set samples=3 --spp 3", err, tmp) == 0);
  CHECK(err.find("set twice") == std::string::npos);
}

TEST_CASE("an image with NaN texels is a MendedImage warning at its file, and renders finite",
          "[e2e]") {
  Scratch tmp;
  const std::string exr = tmp / "nan.exr";
  {
    std::vector<float> f(8 * 8 * 3, 0.5f);
    f[3 * 9] = NAN;  // texel (1, 1), red
    auto out = OIIO::ImageOutput::create(exr);
    REQUIRE(out);
    REQUIRE(out->open(exr, OIIO::ImageSpec(8, 8, 3, OIIO::TypeDesc::FLOAT)));
    REQUIRE(out->write_image(OIIO::TypeDesc::FLOAT, f.data()));
    REQUIRE(out->close());
  }
  std::ofstream(tmp / "s.scn") << "settings { resolution <8, 8> samples 1 }\n"
                                  "background image { file \"nan.exr\" mapping \"latlong\" }\n";
  std::string err;
  REQUIRE(run_capture("check " + (tmp / "s.scn"), err, tmp) == 0);
  INFO(err);
  CHECK(err.find("s.scn:2:25: warning: image '" + exr +
                 "': 1 pixel of it holds NaN or infinite values") != std::string::npos);
  CHECK(err.find("[MendedImage]") != std::string::npos);
  REQUIRE(run_capture("render " + (tmp / "s.scn") + " --stats -o " + (tmp / "o.exr"), err, tmp) ==
          0);
  CHECK(err.find("non-finite samples dropped: 0") != std::string::npos);
  auto in = OIIO::ImageInput::open(tmp / "o.exr");
  REQUIRE(in);
  std::vector<float> px(8 * 8 * 3);
  REQUIRE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data()));
  for (float v : px) CHECK(v == Approx(0.5f).margin(1e-6));
}
