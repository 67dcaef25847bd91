#include "runtime/shading/image_texture.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <unistd.h>

#include <cstdio>

#include "runtime/image_module.hpp"
#include "runtime/render.hpp"

namespace snell::rt {

namespace {

// Standard error pointed at /dev/null while readers run whose libraries print on
// their own (libpng's default error handler writes "libpng error: ..." before
// OIIO turns it into the reason): the reason is what the user is shown, at its
// `file`. Only around the checks, which run before any render thread exists.
class QuietStderr {
 public:
  QuietStderr() {
    std::fflush(stderr);
    saved_ = ::dup(2);
    int null = ::open("/dev/null", O_WRONLY | O_CLOEXEC);
    if (saved_ >= 0 && null >= 0) ::dup2(null, 2);
    if (null >= 0) ::close(null);
  }
  ~QuietStderr() {
    if (saved_ < 0) return;
    std::fflush(stderr);
    ::dup2(saved_, 2);
    ::close(saved_);
  }
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  int saved_ = -1;
};

const ImageTextures::Api& api() {
  static const ImageTextures::Api a = [] {
    ImageTextures::Api r;
    auto sym = [&](auto& f, const char* name) {
      if (r.error.empty())
        f = reinterpret_cast<std::remove_reference_t<decltype(f)>>(
            image_module_symbol(name, r.error));
    };
    sym(r.create, "snell_texture_create_v1");
    sym(r.destroy, "snell_texture_destroy_v1");
    sym(r.open, "snell_texture_open_v3");
    sym(r.lookup, "snell_texture_lookup_v2");
    sym(r.stats, "snell_texture_stats_v1");
    return r;
  }();
  return a;
}

// "FILE:LINE:COL: cannot read image 'PATH': WHY" for scene.images[image].
std::string image_error(const ir::Scene& scene, std::size_t image, const std::string& why) {
  const ir::ImageFile& f = scene.images[image];
  std::string where = f.src.line > 0 ? ir::to_string(f.src, scene) + ": " : "";
  return fmt::format("{}cannot read image '{}': {}", where, f.path, why);
}

}  // namespace

std::unique_ptr<ImageTextures> ImageTextures::open(const ir::Scene& scene,
                                                   const std::string& ocio_config,
                                                   std::string& error, std::size_t* failed,
                                                   std::string* reason) {
  const Api& a = api();
  if (!a.error.empty()) {
    error = "cannot read images: " + a.error;
    return nullptr;
  }
  std::unique_ptr<ImageTextures> t(new ImageTextures);
  t->api_ = &a;
  t->ts_ = a.create(kTextureCacheMB);
  for (const ir::ImageFile& f : scene.images) {
    std::string why, note;  // the note was said when the scene was checked
    void* h = a.open(t->ts_, f.path, ocio_config, why, note);
    if (!h) {
      error = image_error(scene, std::size_t(&f - scene.images.data()), why);
      if (failed) *failed = std::size_t(&f - scene.images.data());
      if (reason) *reason = why;
      return nullptr;
    }
    t->handles_.push_back(h);
  }
  return t;
}

ImageTextures::~ImageTextures() {
  if (api_ && ts_) api_->destroy(ts_);
}

std::string ImageTextures::stats() const {
  std::string s;
  api_->stats(ts_, s);
  return s;
}

std::string check_images(const ir::Scene& scene, const std::string& ocio_config,
                         std::size_t* failed, std::string* why) {
  std::string error;
  const auto bad = unreadable_images(scene.images, ocio_config, error);
  if (!error.empty() || bad.empty()) return error;
  if (failed) *failed = bad[0].first;
  if (why) *why = bad[0].second;
  return image_error(scene, bad[0].first, bad[0].second);
}

std::vector<std::pair<std::size_t, std::string>> unreadable_images(
    const std::vector<ir::ImageFile>& images, const std::string& ocio_config, std::string& error,
    std::vector<std::pair<std::size_t, std::string>>* notes) {
  std::vector<std::pair<std::size_t, std::string>> bad;
  if (images.empty()) return bad;
  const ImageTextures::Api& a = api();
  if (!a.error.empty()) {
    error = "cannot read images: " + a.error;
    return bad;
  }
  void* ts = a.create(kTextureCacheMB);
  QuietStderr quiet;
  for (std::size_t i = 0; i < images.size(); ++i) {
    std::string why, note;
    if (!a.open(ts, images[i].path, ocio_config, why, note))
      bad.emplace_back(i, why);
    else if (notes && !note.empty())
      notes->emplace_back(i, note);
  }
  a.destroy(ts);
  return bad;
}

}  // namespace snell::rt
