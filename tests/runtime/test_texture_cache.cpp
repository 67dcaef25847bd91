// The decoded textures' folder (runtime/texture_cache.hpp): the user's own, and
// bounded, least recently used first.
#include <OpenImageIO/imageio.h>
#include <sys/stat.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "runtime/render.hpp"
#include "runtime/shading/textures.hpp"
#include "runtime/texture_cache.hpp"

namespace fs = std::filesystem;
using namespace snell;

namespace {

// A fresh folder under the temporary one, removed after the test; the cache
// variables point into it while the test runs, as they were after.
struct Sandbox {
  fs::path root;
  std::string old_cache, old_mb;
  bool had_cache = false, had_mb = false;
  Sandbox() {
    root = fs::temp_directory_path() / ("snell_texcache_" + std::to_string(::getpid()));
    fs::remove_all(root);
    fs::create_directories(root);
    if (const char* c = std::getenv("SNELL_TEXTURE_CACHE")) had_cache = true, old_cache = c;
    if (const char* m = std::getenv("SNELL_TEXTURE_CACHE_MB")) had_mb = true, old_mb = m;
  }
  ~Sandbox() {
    if (had_cache)
      ::setenv("SNELL_TEXTURE_CACHE", old_cache.c_str(), 1);
    else
      ::unsetenv("SNELL_TEXTURE_CACHE");
    if (had_mb)
      ::setenv("SNELL_TEXTURE_CACHE_MB", old_mb.c_str(), 1);
    else
      ::unsetenv("SNELL_TEXTURE_CACHE_MB");
    std::error_code ec;
    fs::remove_all(root, ec);
  }
};

void write_bytes(const fs::path& p, std::size_t n) {
  std::ofstream(p, std::ios::binary) << std::string(n, 'x');
}
void set_age(const fs::path& p, std::chrono::seconds age) {
  fs::last_write_time(p, fs::file_time_type::clock::now() - age);
}

}  // namespace

TEST_CASE("the texture cache folder is made private and refused when it is not the user's",
          "[images]") {
  Sandbox box;
  std::string error;
  ::setenv("SNELL_TEXTURE_CACHE", (box.root / "made").c_str(), 1);
  fs::path dir = rt::texture_cache_dir(error);
  INFO(error);
  REQUIRE(dir == box.root / "made");
  struct stat st {};
  REQUIRE(::stat(dir.c_str(), &st) == 0);
  CHECK((st.st_mode & 0777) == 0700);
  CHECK(rt::texture_cache_dir(error) == dir);  // made already: taken as it is

  // Others can write to it: they could put their files where ours are read.
  fs::create_directories(box.root / "open");
  fs::permissions(box.root / "open", fs::perms::all);
  ::setenv("SNELL_TEXTURE_CACHE", (box.root / "open").c_str(), 1);
  error.clear();
  CHECK(rt::texture_cache_dir(error).empty());
  CHECK(error.find("other users can write to it") != std::string::npos);

  // A link (to a folder of ours or not) is not followed.
  fs::create_directory_symlink(box.root / "made", box.root / "link");
  ::setenv("SNELL_TEXTURE_CACHE", (box.root / "link").c_str(), 1);
  error.clear();
  CHECK(rt::texture_cache_dir(error).empty());
  CHECK(error.find("not a folder") != std::string::npos);

  // Another user's (root can make one to test with).
  if (::geteuid() == 0) {
    fs::create_directories(box.root / "theirs");
    fs::permissions(box.root / "theirs", fs::perms::owner_all);
    REQUIRE(::chown((box.root / "theirs").c_str(), 65534, 65534) == 0);
    ::setenv("SNELL_TEXTURE_CACHE", (box.root / "theirs").c_str(), 1);
    error.clear();
    CHECK(rt::texture_cache_dir(error).empty());
    CHECK(error.find("another user owns it") != std::string::npos);
  }
}

TEST_CASE("the texture cache is pruned least recently used first, sparing recent files",
          "[images]") {
  Sandbox box;
  const fs::path d = box.root;
  // Five 1000-byte textures used 5, 4, 3, 2 hours and 10 minutes ago, a partial
  // file of a killed process two days old and one of a running process.
  const char* names[] = {"a.tx", "b.tx", "c.tx", "d.tx", "e.tx"};
  const int hours_ago[] = {5 * 60, 4 * 60, 3 * 60, 2 * 60, 10};
  for (int i = 0; i < 5; ++i) {
    write_bytes(d / names[i], 1000);
    set_age(d / names[i], std::chrono::minutes(hours_ago[i]));
  }
  write_bytes(d / ".old-123.tx", 50);
  set_age(d / ".old-123.tx", std::chrono::hours(48));
  write_bytes(d / ".new-456.tx", 50);
  write_bytes(d / "notes.txt", 5000);  // not the cache's: never counted or removed

  // Under the bound: nothing goes but the old partial file.
  rt::texture_cache_prune(d, 5000, std::chrono::hours(1), {});
  CHECK(fs::exists(d / "a.tx"));
  CHECK_FALSE(fs::exists(d / ".old-123.tx"));
  CHECK(fs::exists(d / ".new-456.tx"));

  // 3000 bytes: the oldest go first, except `keep` (a) and the one used within
  // the grace (e), so a, d and e stay.
  rt::texture_cache_prune(d, 3000, std::chrono::hours(1), d / "a.tx");
  CHECK(fs::exists(d / "a.tx"));
  CHECK_FALSE(fs::exists(d / "b.tx"));
  CHECK_FALSE(fs::exists(d / "c.tx"));
  CHECK(fs::exists(d / "d.tx"));
  CHECK(fs::exists(d / "e.tx"));
  CHECK(fs::exists(d / "notes.txt"));

  // A partial file of a process that is gone (a ^C during a decoding) goes once
  // it is a minute old, not a day; one of a live process (this one) stays, and so
  // does a fresh one whatever its process (it may be another namespace's).
  const std::string gone = ".0123456789abcdef-" + std::to_string(4194304 - 7) + ".1a2b.temp.tx";
  const std::string live = ".0123456789abcdef-" + std::to_string(::getpid()) + ".tx";
  const std::string fresh = ".fedcba9876543210-" + std::to_string(4194304 - 7) + ".tx";
  for (const std::string& n : {gone, live, fresh}) write_bytes(d / n, 50);
  set_age(d / gone, std::chrono::minutes(5));
  set_age(d / live, std::chrono::minutes(5));
  rt::texture_cache_prune(d, 1u << 30, std::chrono::hours(1), {});
  CHECK_FALSE(fs::exists(d / gone));
  CHECK(fs::exists(d / live));
  CHECK(fs::exists(d / fresh));

  // A touched file is used now: it outlives an older one.
  rt::texture_cache_touch(d / "d.tx");
  rt::texture_cache_prune(d, 2000, std::chrono::seconds(0), d / "e.tx");
  CHECK_FALSE(fs::exists(d / "a.tx"));
  CHECK(fs::exists(d / "d.tx"));
  CHECK(fs::exists(d / "e.tx"));
}

TEST_CASE("a render's decoded textures stay within the cache bound", "[images]") {
  // Eight different PNGs (each decoded to a .tx of a few KB) with a bound of
  // 0 MB: each new decoding prunes the ones before it that are past the grace,
  // and none is (all were just made), so all stay: the grace protects renders in
  // progress. Then with every file aged past the grace, the next decoding leaves
  // only itself.
  Sandbox box;
  const fs::path cache = box.root / "cache";
  ::setenv("SNELL_TEXTURE_CACHE", cache.c_str(), 1);
  ::setenv("SNELL_TEXTURE_CACHE_MB", "0", 1);
  auto png = [&](int k) {
    const std::string path = (box.root / ("img" + std::to_string(k) + ".png")).string();
    std::vector<unsigned char> px(16 * 16 * 3, static_cast<unsigned char>(10 + 20 * k));
    auto out = OIIO::ImageOutput::create(path);
    REQUIRE(out);
    REQUIRE(out->open(path, OIIO::ImageSpec(16, 16, 3, OIIO::TypeDesc::UINT8)));
    REQUIRE(out->write_image(OIIO::TypeDesc::UINT8, px.data()));
    REQUIRE(out->close());
    return path;
  };
  auto open_one = [&](int k) {
    ir::Scene s;
    s.images.push_back({png(k), {}});
    std::string err;
    auto tex = rt::ImageTextures::open(s, "", err);
    INFO(err);
    REQUIRE(tex);
  };
  auto count = [&] {
    int n = 0;
    for (const auto& e : fs::directory_iterator(cache)) n += e.path().extension() == ".tx";
    return n;
  };
  for (int k = 0; k < 8; ++k) open_one(k);
  CHECK(count() == 8);
  for (const auto& e : fs::directory_iterator(cache)) set_age(e.path(), std::chrono::hours(2));
  open_one(8);
  CHECK(count() == 1);
}
