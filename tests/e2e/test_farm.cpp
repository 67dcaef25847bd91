// snell farm slurm end to end with a stand-in `sbatch` on PATH: it runs an array
// script once per index (SLURM_ARRAY_TASK_ID set, output where #SBATCH --output
// says) and the merge script after it, in order, as Slurm would with afterany, and
// logs how it was called. The real-Slurm run is docs/distributed.md's recipe; this
// checks what snell writes and submits: the scripts render and merge the image one
// process gives (tiles bit for bit, passes within 1e-6), a failed task fails the
// merge naming it, and --dry-run submits nothing.
#include <OpenImageIO/imageio.h>

#include <catch2/catch.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <thread>

#include "tests/e2e/e2e_util.hpp"

namespace fs = std::filesystem;

namespace {

using snell::e2e::kShowcase;
using snell::e2e::kSnell;
using snell::e2e::slurp;

// The stand-in. FAKE_FAIL_TASK=i makes task i exit 1 without running snell.
const char* kFakeSbatch = R"(#!/bin/bash
set -u
echo "sbatch $*" >> "$FAKE_LOG"
dep="" array=""
while [ $# -gt 1 ]; do
  case "$1" in
    --dependency=*) dep="${1#--dependency=}" ;;
    --array=*) array="${1#--array=}" ;;
  esac
  shift
done
script="$1"
n=$(( $(cat "$FAKE_DIR/next_id" 2>/dev/null || echo 100) + 1 )); echo $n > "$FAKE_DIR/next_id"
out=$(sed -n 's/^#SBATCH --output=//p' "$script")
range=${array:-$(sed -n 's/^#SBATCH --array=//p' "$script")}
if [ -n "$range" ]; then
  for i in $(seq ${range%-*} ${range#*-}); do
    log=${out//%a/$i}
    if [ "${FAKE_FAIL_TASK:-}" = "$i" ]; then echo "killed" > "$log"; continue; fi
    SLURM_ARRAY_TASK_ID=$i bash "$script" > "$log" 2>&1
  done
else
  bash "$script" > "$out" 2>&1
  echo $? > "$FAKE_DIR/merge_exit"
fi
echo "$n;cluster"
)";

// Each test's own folder, with the stand-in in its bin/.
struct FarmScratch : snell::e2e::Scratch {
  FarmScratch() : snell::e2e::Scratch("snell_farm_") {
    fs::create_directories(dir / "bin");
    std::ofstream(dir / "bin/sbatch") << kFakeSbatch;
    fs::permissions(dir / "bin/sbatch", fs::perms::owner_all);
  }
  // snell with the stand-in first on PATH.
  int farm(const std::string& args, const std::string& env = "") const {
    std::string cmd = "PATH=" + (*this / "bin") + ":$PATH FAKE_LOG=" + (*this / "calls.txt") +
                      " FAKE_DIR=" + dir.string() + " " + env + " " + kSnell + " farm slurm " +
                      args + " > " + (*this / "farm.out") + " 2>&1";
    int status = std::system(cmd.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
};

std::vector<float> read_pixels(const std::string& path) {
  auto in = OIIO::ImageInput::open(path);
  REQUIRE(in);
  std::vector<float> px(std::size_t(in->spec().width) * in->spec().height * 3);
  REQUIRE(in->read_image(0, 0, 0, 3, OIIO::TypeDesc::FLOAT, px.data()));
  return px;
}

int render(const std::string& args) {
  return snell::e2e::run("render " + args);
}

const std::string kOpts = " --res 48x27 --spp 6 --set sampler=stratified";

}  // namespace

TEST_CASE("farm --tiles: the array's crops merge into the one-process image, bit for bit",
          "[e2e][farm]") {
  FarmScratch tmp;
  REQUIRE(render(kShowcase + kOpts + " --quiet -o " + (tmp / "one.exr")) == 0);
  REQUIRE(tmp.farm(kShowcase + kOpts + " --tiles 4 --dir " + (tmp / "shared") +
                   " -o out.exr --sbatch=--partition=debug") == 0);
  std::string said = slurp(tmp / "farm.out"), calls = slurp(tmp / "calls.txt");
  INFO(said << calls << slurp(tmp / "shared/logs/merge.out"));
  CHECK(said.find("submitted array job 101 (4 tasks) and merge job 102") != std::string::npos);
  CHECK(said.find("squeue -j 101,102") != std::string::npos);
  CHECK(calls.find("--partition=debug --dependency=afterany:101 ") != std::string::npos);
  CHECK(slurp(tmp / "merge_exit") == "0\n");
  std::vector<float> one = read_pixels(tmp / "one.exr"), farm = read_pixels(tmp / "shared/out.exr");
  REQUIRE(one.size() == farm.size());
  CHECK(std::memcmp(one.data(), farm.data(), one.size() * sizeof(float)) == 0);
}

TEST_CASE("farm --passes: the array's sample ranges merge within 1e-6", "[e2e][farm]") {
  FarmScratch tmp;
  REQUIRE(render(kShowcase + kOpts + " --quiet -o " + (tmp / "one.exr")) == 0);
  REQUIRE(tmp.farm(kShowcase + kOpts + " --passes 4 --dir " + (tmp / "shared") + " -o out.exr") ==
          0);
  INFO(slurp(tmp / "shared/logs/merge.out"));
  std::vector<float> one = read_pixels(tmp / "one.exr"), farm = read_pixels(tmp / "shared/out.exr");
  REQUIRE(one.size() == farm.size());
  double worst = 0;
  for (std::size_t i = 0; i < one.size(); ++i)
    if (one[i] != 0 || farm[i] != 0)
      worst = std::max(worst, double(std::fabs(one[i] - farm[i]) / std::max(one[i], farm[i])));
  CHECK(worst <= 1e-6);
}

TEST_CASE("farm --frames: one task a frame, each with the sequence's clock", "[e2e][farm]") {
  FarmScratch tmp;
  std::ofstream(tmp / "a.scn") << "settings { resolution <4, 2> }\nbackground <clock, 0, 0>\n";
  REQUIRE(tmp.farm((tmp / "a.scn") + " --frames 0..4 --dir " + (tmp / "shared") + " -o f_##.exr") ==
          0);
  INFO(slurp(tmp / "shared/logs/merge.out"));
  CHECK(slurp(tmp / "merge_exit") == "0\n");
  for (int f = 0; f < 4; ++f) {
    std::vector<float> px = read_pixels(tmp / ("shared/f_0" + std::to_string(f) + ".exr"));
    CHECK(px[0] == float(f / 4.0));
  }
}

TEST_CASE("farm: a failed task fails the merge job, naming it, nothing is merged", "[e2e][farm]") {
  FarmScratch tmp;
  // An earlier run's image is gone at submission, not left where this run's is due.
  fs::create_directories(tmp / "shared");
  std::ofstream(tmp / "shared/out.exr") << "stale";
  REQUIRE(tmp.farm(kShowcase + kOpts + " --tiles 3 --dir " + (tmp / "shared") + " -o out.exr",
                   "FAKE_FAIL_TASK=1") == 0);
  CHECK(slurp(tmp / "merge_exit") == "1\n");
  std::string log = slurp(tmp / "shared/logs/merge.out");
  INFO(log);
  CHECK(log.find("task 1 failed") != std::string::npos);
  CHECK(log.find("sbatch --array=1 ") != std::string::npos);
  CHECK(log.find("task 0 failed") == std::string::npos);
  CHECK(!fs::exists(tmp / "shared/out.exr"));
}

TEST_CASE(
    "farm: never replaces what the scene reads, checks its outputs first, and a failed "
    "submission leaves every file as it was",
    "[e2e][farm]") {
  FarmScratch tmp;
  fs::create_directories(tmp / "s");
  const std::string scene = tmp / "s/a.scn";
  std::ofstream(scene) << "settings { resolution <16, 12> }\n"
                          "point_light { position <0, 5, -5> intensity 20 }\n"
                          "sphere { center <0, 0, 5> }\n";
  const std::string kept = slurp(scene);
  auto calls = [&] { return fs::exists(tmp / "calls.txt") ? slurp(tmp / "calls.txt") : ""; };
  // The scene as the result (a scene file named sc.png), or as a script's path:
  // exit 2, nothing submitted, the scene whole (it was deleted, or overwritten by
  // the script).
  std::ofstream(tmp / "s/sc.png") << kept;
  CHECK(tmp.farm(tmp / "s/sc.png" + std::string(" --tiles 2 --dir ") + (tmp / "d1") + " -o " +
                 (tmp / "s/sc.png")) == 2);
  CHECK(slurp(tmp / "farm.out").find("a file this command reads") != std::string::npos);
  CHECK(slurp(tmp / "s/sc.png") == kept);
  std::ofstream(tmp / "s/render.sbatch") << slurp(scene);
  CHECK(tmp.farm(tmp / "s/render.sbatch" + std::string(" --tiles 2 --dir ") + (tmp / "s")) == 2);
  CHECK(slurp(tmp / "s/render.sbatch") == kept);
  CHECK(slurp(scene) == kept);
  // A result that is one of the pieces, a result in a folder that does not exist,
  // a display the config lacks: refused before anything is submitted.
  CHECK(tmp.farm(scene + " --tiles 2 --dir " + (tmp / "d2") + " -o pieces/piece_0000.exr") == 2);
  CHECK(tmp.farm(scene + " --tiles 2 --dir " + (tmp / "d3") + " -o nodir/x.png") == 3);
  CHECK(tmp.farm(scene + " --tiles 2 --dir " + (tmp / "d4") + " -o x.png --display nosuch") == 3);
  CHECK(calls().empty());
  // A dry run makes the same checks (it printed scripts a real run refuses), and
  // still writes nothing; a result in the farm's own folder, which a real run
  // makes, is fine.
  CHECK(tmp.farm(scene + " --tiles 2 --dry-run --dir " + (tmp / "d2") +
                 " -o pieces/piece_0000.exr") == 2);
  CHECK(tmp.farm(scene + " --tiles 2 --dry-run --dir " + (tmp / "d3") + " -o nodir/x.png") == 3);
  CHECK(tmp.farm(scene + " --tiles 2 --dry-run --dir " + (tmp / "d6") + " -o x.png") == 0);
  CHECK_FALSE(fs::exists(tmp / "d6"));
  CHECK(calls().empty());
  // sbatch fails: the earlier run's result and pieces are as they were.
  fs::create_directories(tmp / "d5/pieces");
  std::ofstream(tmp / "d5/out.exr") << "earlier";
  std::ofstream(tmp / "d5/render.sbatch") << "earlier script";
  std::ofstream(tmp / "d5/pieces/piece_0000.exr") << "earlier piece";
  fs::remove(tmp / "bin/sbatch");
  std::ofstream(tmp / "bin/sbatch") << "#!/bin/bash\necho refused >&2\nexit 1\n";
  fs::permissions(tmp / "bin/sbatch", fs::perms::owner_all);
  CHECK(tmp.farm(scene + " --tiles 2 --dir " + (tmp / "d5") + " -o out.exr") == 3);
  CHECK(slurp(tmp / "d5/out.exr") == "earlier");
  CHECK(slurp(tmp / "d5/pieces/piece_0000.exr") == "earlier piece");
  // The scripts too: the earlier one back, no new one left (they were written over).
  CHECK(slurp(tmp / "d5/render.sbatch") == "earlier script");
  CHECK_FALSE(fs::exists(tmp / "d5/merge.sbatch"));
  for (const auto& e : fs::directory_iterator(tmp / "d5"))
    CHECK(e.path().filename().string().find("farm-stale") == std::string::npos);
}

TEST_CASE("farm: the merge job prints a folder named like a command, never runs it",
          "[e2e][farm]") {
  // The merge script's messages name the shared folder; in double quotes a name
  // with $(...) in it ran as a command.
  FarmScratch tmp;
  const std::string dir = tmp / "shared$(echo INJECTED)";
  REQUIRE(tmp.farm(kShowcase + kOpts + " --tiles 2 --dir '" + dir + "' -o out.exr",
                   "FAKE_FAIL_TASK=1") == 0);
  std::string log = slurp(dir + "/logs/merge.out");
  INFO(log);
  CHECK(log.find("task 1 failed") != std::string::npos);
  CHECK(log.find("shared$(echo INJECTED)/logs/task_1.out") != std::string::npos);
  CHECK(log.find("sharedINJECTED") == std::string::npos);
}

TEST_CASE("farm: --dry-run prints and submits nothing, usage errors exit 2", "[e2e][farm]") {
  FarmScratch tmp;
  REQUIRE(tmp.farm(kShowcase + kOpts + " --tiles 2 --dry-run --dir " + (tmp / "shared")) == 0);
  std::string out = slurp(tmp / "farm.out");
  CHECK(out.find("#SBATCH --array=0-1") != std::string::npos);
  CHECK(out.find("--dependency=afterany:$ARRAY") != std::string::npos);
  CHECK(out.find("'--crop' '0,13,48,27'") != std::string::npos);
  CHECK(!fs::exists(tmp / "calls.txt"));
  CHECK(!fs::exists(tmp / "shared"));
  const std::string d = " --dir " + (tmp / "shared");
  for (const std::string& bad :
       {kShowcase + d, kShowcase + d + " --tiles 2 --passes 2", kShowcase + d + " --tiles 0",
        kShowcase + kOpts + d + " --tiles 28", kShowcase + kOpts + d + " --passes 7",
        kShowcase + d + " --frames 3..1", kShowcase + d + " --frames 0..2 --clock 0.5",
        kShowcase + " --tiles 2", kShowcase + d + " --tiles 2 -o x.bmp"}) {
    INFO(bad);
    CHECK(tmp.farm(bad) == 2);
  }
  // The dry run's array script, saved at its path, runs outside Slurm as it is (the
  // Kubernetes recipe of docs/distributed.md): it makes its pieces' folder.
  {
    const std::string dir = tmp / "k8s";
    REQUIRE(tmp.farm(kShowcase + kOpts + " --tiles 2 --dry-run --dir " + dir) == 0);
    std::string dry = slurp(tmp / "farm.out");
    const std::string head = "# " + dir + "/";
    std::size_t a = dry.find(head), b = dry.find(head, a + 1);
    REQUIRE(a != std::string::npos);
    REQUIRE(b != std::string::npos);
    std::size_t body = dry.find('\n', a) + 1;
    fs::create_directories(dir);
    std::string script = dry.substr(a + 2, body - a - 3);
    std::ofstream(script) << dry.substr(body, b - body);
    CHECK(
        std::system(("cd " + dir + " && SLURM_ARRAY_TASK_ID=1 bash " + script + " > /dev/null 2>&1")
                        .c_str()) == 0);
    CHECK(fs::exists(dir + "/pieces/piece_0001.exr"));
  }
  int status =
      std::system((kSnell + " farm pbs " + kShowcase + d + " --tiles 2 >/dev/null 2>&1").c_str());
  CHECK(WEXITSTATUS(status) == 2);
  CHECK(!fs::exists(tmp / "calls.txt"));
}

namespace {

// Runs `cmd`, returns its stdout.
std::string output_of(const std::string& cmd) {
  std::string out;
  FILE* f = ::popen(cmd.c_str(), "r");
  REQUIRE(f);
  char buf[512];
  while (std::fgets(buf, sizeof buf, f)) out += buf;
  ::pclose(f);
  return out;
}

double now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// Submits a real farm run, waits for both jobs to leave the queue, returns the
// wall time from submission to the merged image.
double farm_on_slurm(const std::string& args, const std::string& dir) {
  double t0 = now();
  std::string out = output_of(kSnell + " farm slurm " + args + " --dir " + dir + " 2>&1");
  INFO(out);
  std::size_t last = out.find_last_of('\n', out.size() - 2);
  std::string ids = out.substr(last == std::string::npos ? 0 : last + 1);
  unsigned array = 0, merge = 0;
  REQUIRE(std::sscanf(ids.c_str(), "%u %u", &array, &merge) == 2);
  std::string wait = "squeue -h -j " + std::to_string(array) + "," + std::to_string(merge);
  for (int i = 0; i < 1500 && !output_of(wait + " 2>/dev/null").empty(); ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  REQUIRE(output_of(wait + " 2>/dev/null").empty());
  return now() - t0;
}

}  // namespace

// Run by tests/farm/slurm_cluster.sh (CTest label `farm`), which starts a one-node
// cluster and sets SLURM_CONF; hidden from the plain test_e2e run.
TEST_CASE("farm on a real Slurm: 4 tiles bit for bit, 4 passes within 1e-6", "[.][slurm]") {
  REQUIRE(std::getenv("SLURM_CONF"));
  FarmScratch tmp;
  const std::string opts = " --res 160x90 --spp 8";
  double t0 = now();
  REQUIRE(render(kShowcase + opts + " --quiet -o " + (tmp / "one.exr")) == 0);
  double one_seconds = now() - t0;
  std::vector<float> one = read_pixels(tmp / "one.exr");

  double tiles_seconds = farm_on_slurm(kShowcase + opts + " --tiles 4 -o out.exr", tmp / "tiles");
  INFO(slurp(tmp / "tiles/logs/merge.out"));
  CHECK(slurp(tmp / "tiles/logs/merge.out").find("snell farm: done") != std::string::npos);
  std::vector<float> tiles = read_pixels(tmp / "tiles/out.exr");
  REQUIRE(tiles.size() == one.size());
  CHECK(std::memcmp(tiles.data(), one.data(), one.size() * sizeof(float)) == 0);

  double passes_seconds =
      farm_on_slurm(kShowcase + opts + " --passes 4 -o out.exr", tmp / "passes");
  std::vector<float> passes = read_pixels(tmp / "passes/out.exr");
  REQUIRE(passes.size() == one.size());
  double worst = 0;
  for (std::size_t i = 0; i < one.size(); ++i)
    if (one[i] != 0 || passes[i] != 0)
      worst = std::max(worst, double(std::fabs(one[i] - passes[i]) / std::max(one[i], passes[i])));
  CHECK(worst <= 1e-6);
  std::printf(
      "farm on Slurm, showcase 160x90 at 8 spp: one process %.2f s; 4 tiles %.2f s; 4 passes "
      "%.2f s (submission to merged image); passes' worst relative difference %.2g\n",
      one_seconds, tiles_seconds, passes_seconds, worst);
}
