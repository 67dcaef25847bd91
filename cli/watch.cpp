#include "cli/watch.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <iterator>
#include <memory>
#include <sstream>
#include <thread>

#include "cli/commands.hpp"
#include "cli/file_watch.hpp"
#include "cli/progress.hpp"
#include "cli/tev.hpp"
#include "cli/watch_http.hpp"
#include "runtime/render.hpp"
#include "runtime/scene_checks.hpp"

namespace snell::cli {

namespace fs = std::filesystem;
using namespace std::chrono_literals;

std::vector<std::pair<std::uint32_t, std::uint32_t>> watch_passes(std::uint32_t spp) {
  std::vector<std::pair<std::uint32_t, std::uint32_t>> out;
  if (spp == 0) spp = 1;
  std::uint32_t a = 0, b = 1;
  while (a < spp) {
    out.push_back({a, b});
    a = b;
    // Each pass about three times the samples of all before it: the picture's
    // noise halves per pass at the same share of waiting.
    b = b > spp / 4 ? spp : b * 4;
  }
  return out;
}

namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) {
  g_stop = true;
}

// The private folder the PNG of each pass is written into (through the same
// writer and display transform as snell render's PNG) and read back from.
struct TempFolder {
  std::string path;
  TempFolder() {
    std::string t = (fs::temp_directory_path() / "snell-watch-XXXXXX").string();
    if (::mkdtemp(t.data())) path = t;
  }
  ~TempFolder() {
    std::error_code ec;
    if (!path.empty()) fs::remove_all(path, ec);
  }
};

bool read_bytes(const std::string& path, std::vector<unsigned char>& out) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  out.assign(std::istreambuf_iterator<char>(in), {});
  return true;
}

// Every file the compilation read (the scene, its imports) or names for the
// runtime (meshes, images), and the scene itself even when it could not be read.
// Every place an `import` of these statements could find its file (§9: the
// importing file's folder, each -I folder, the standard library), so that a file
// saved where an earlier folder of the search now wins is seen (a new
// scene/lib.scn in front of -I's lib.scn): only the files read were watched.
void import_candidates(const std::vector<lang::StmtPtr>& stmts, const std::string& from,
                       const compile::CompileOptions& copts, std::vector<std::string>& out) {
  for (const lang::StmtPtr& s : stmts) {
    if (!s) continue;
    if (s->kind == lang::StmtKind::Import && !fs::path(s->name).is_absolute()) {
      std::vector<std::string> dirs;
      compile::find_import(s->name, from, copts, &dirs);
      for (const std::string& d : dirs) out.push_back((fs::path(d) / s->name).string());
    }
    import_candidates(s->body, from, copts, out);
    import_candidates(s->else_body, from, copts, out);
    for (const auto& b : s->branches) import_candidates(b, from, copts, out);
  }
}

std::vector<std::string> files_read(const std::string& scene, const compile::Compilation* c,
                                    const compile::CompileOptions& copts) {
  std::vector<std::string> out{scene};
  if (!c) return out;
  for (std::size_t i = 0; i < c->sources.size(); ++i)
    out.push_back(c->sources.file(lang::FileId(i)).path());
  for (const auto& program : c->programs)
    if (program && program->file < c->sources.size())
      import_candidates(program->statements, c->sources.file(program->file).path(), copts, out);
  for (const ir::MeshData& m : c->scene.meshes) out.push_back(m.path);
  for (const ir::ImageFile& im : c->scene.images) out.push_back(im.path);
  return out;
}

class Watcher {
 public:
  Watcher(const CliArgs& o, WatchPage& page, TevStream* tev)
      : o_(o), page_(page), tev_(tev), tev_name_("snell watch: " + o.scene) {}

  int run() {
    if (!files_.error().empty() && !o_.quiet)
      std::cerr << "snell watch: " << files_.error() << "\n";
    while (!g_stop) {
      bool changed = false;
      // Whatever a scene asks for (memory for a huge image, say) ends this cycle,
      // never the watch: the page says what happened and the next save is awaited.
      try {
        changed = cycle();
      } catch (const std::bad_alloc&) {
        fail(
            "snell: error: out of memory (the scene needs more memory than this machine has; "
            "lower the resolution, samples or geometry)\n");
      } catch (const std::exception& e) {
        fail(std::string("snell: error: internal error: ") + e.what() + "\n");
      }
      if (!usage_.empty()) return usage_error(usage_);
      if (g_stop) break;
      // Nothing left to do until a file changes.
      if (!changed)
        while (!g_stop && !files_.wait(200ms)) {
        }
      changed_at_ = std::chrono::steady_clock::now();
      first_pass_pending_ = true;
    }
    return kExitOk;
  }

 private:
  void fail(const std::string& message) {
    page_.set_diagnostics(message, true);
    page_.set_status("stopped by an error: waiting for a change");
    if (!o_.quiet) std::cerr << message;
  }

  // Compiles and renders every pass; true when a change cut it short (compile
  // again at once), false when it finished or stopped at an error.
  bool cycle() {
    page_.set_status("compiling");
    compile::CompileOptions copts;
    std::string error;
    std::unique_ptr<compile::Compilation> c;
    std::string diagnostics;
    bool ok = false;
    if (!build_compile_options(o_, copts, error)) {
      diagnostics = "snell: error: " + error + "\n";
    } else {
      copts.clock = o_.clock.value_or(0.0);
      // An exception here is a compiler bug or memory the machine lacks; either
      // way the watch goes on and says so.
      try {
        c = compile::compile_file(o_.scene, copts);
        // Options no edit of the scene can fix (`--set foo=1`, `--res 0x0`): exit
        // 2 as render does, rather than wait for a change.
        if (c->status == compile::CompileStatus::UsageError) {
          usage_ = c->message;
          return false;
        }
        std::ostringstream text;
        c->diags.print(text, false);
        diagnostics = text.str();
        ok = c->status == compile::CompileStatus::Ok;
        if (!ok && !c->message.empty()) diagnostics += "snell: error: " + c->message + "\n";
        if (ok)
          for (const ir::Problem& p : ir::validate(c->scene)) {
            diagnostics += ir::to_string(p, c->scene) + "\n";
            ok = false;
          }
        if (ok)
          if (std::string err = rt::check_images(c->scene, o_.ocio_config); !err.empty()) {
            diagnostics += "snell: error: " + err + "\n";
            ok = false;
          }
      } catch (const std::bad_alloc&) {
        diagnostics += "snell: error: out of memory compiling the scene\n";
        ok = false;
      } catch (const std::exception& e) {
        diagnostics += std::string("snell: error: internal error: ") + e.what() + "\n";
        ok = false;
      }
    }
    // A failed compile watches every file in the folders: the missing import may
    // be the next file saved.
    files_.set_files(files_read(o_.scene, c.get(), copts), !ok);
    if (!ok) {
      const std::size_t n = c ? std::max<std::size_t>(c->diags.error_count(), 1) : 1;
      diagnostics +=
          c ? error_count_line(c->diags, o_.scene) : fmt::format("1 error in {}\n", o_.scene);
      page_.set_diagnostics(diagnostics, true);
      page_.set_status(fmt::format("{} error{}: waiting for a change", n, n == 1 ? "" : "s"));
      if (!o_.quiet) std::cerr << diagnostics;
      return false;
    }
    // The warnings `snell check` prints about the scene as a whole (no light, the
    // camera inside an object): what explains a black or empty preview.
    for (const rt::SceneWarning& w : rt::scene_warnings(c->scene))
      diagnostics += o_.scene + ": warning: " + w.message + "\n";
    page_.set_diagnostics(diagnostics, false);
    if (!o_.quiet && !diagnostics.empty()) std::cerr << diagnostics;
    return render_passes(c->scene);
  }

  enum class Outcome { Done, Changed, Stopped, Failed };

  // One render on a worker thread while this thread watches the files: a change
  // cancels it (the tiles begun still finish, then it returns).
  Outcome render_watching(const ir::Scene& scene, std::pair<std::uint32_t, std::uint32_t> range,
                          rt::RenderResult& result) {
    std::atomic<bool> cancel{false}, done{false};
    rt::RenderOptions ropts;
    ropts.threads = o_.threads;
    ropts.general_kernel = o_.features == "all";
    ropts.ocio_config = o_.ocio_config;
    ropts.measure_cost = o_.stats;
    ropts.sample_range = range;
    ropts.cancel = &cancel;
    std::string failure;
    std::thread worker([&] {
      try {
        result = rt::render(scene, ropts);
      } catch (const std::exception& e) {
        failure = std::string("snell: error: the render failed: ") + e.what() + "\n";
      }
      done = true;
    });
    Outcome out = Outcome::Done;
    while (!done) {
      if (g_stop) {
        out = Outcome::Stopped;
      } else if (files_.wait(50ms, 40ms)) {
        out = Outcome::Changed;
      } else {
        continue;
      }
      cancel = true;
      break;
    }
    worker.join();
    if (out == Outcome::Done && !failure.empty()) {
      page_.set_diagnostics(failure, true);
      return Outcome::Failed;
    }
    return out;
  }

  // A large image first shows a preview: 1 spp at about 160x120 pixels, blown up
  // to the full size (each preview pixel a block), in a small share of the full 1
  // spp pass's time. Its factor, or 1 for no preview.
  static std::uint32_t preview_factor(std::uint32_t w, std::uint32_t h) {
    double f = std::ceil(std::sqrt(double(w) * double(h) / (160.0 * 120.0)));
    return f < 2 ? 1 : std::uint32_t(std::min(f, double(std::min(w, h))));
  }

  // Renders the passes; true when a change cut them short (compile again at once).
  bool render_passes(ir::Scene& scene) {
    const std::uint32_t W = scene.settings.width, H = scene.settings.height;
    const std::uint32_t spp = scene.settings.samples ? scene.settings.samples : 1;
    auto passes = watch_passes(spp);
    rt::RenderResult result;
    auto first_shown = [&](const char* what, const rt::Image& im) {
      if (!first_pass_pending_ || o_.quiet) return;
      first_pass_pending_ = false;
      double s =
          std::chrono::duration<double>(std::chrono::steady_clock::now() - changed_at_).count();
      std::cerr << fmt::format("snell watch: {} ({}x{}, 1 spp) shown {:.2f} s after the change\n",
                               what, im.width, im.height, s);
    };

    if (std::uint32_t f = preview_factor(W, H); f > 1 && W > 0 && H > 0) {
      page_.set_status("rendering a preview (1 spp, 1/" + std::to_string(f) + " size)");
      scene.settings.width = std::max(1u, W / f);
      scene.settings.height = std::max(1u, H / f);
      Outcome out = render_watching(scene, {0, 1}, result);
      scene.settings.width = W;
      scene.settings.height = H;
      if (out != Outcome::Done) return out == Outcome::Changed;
      const rt::Image& small = result.image;
      rt::Image big;
      big.width = W;
      big.height = H;
      big.rgb.resize(std::size_t(W) * H * 3);
      for (std::uint32_t y = 0; y < H; ++y)
        for (std::uint32_t x = 0; x < W; ++x) {
          const float* p = small.at(std::min(x * small.width / W, small.width - 1),
                                    std::min(y * small.height / H, small.height - 1));
          std::copy(p, p + 3, big.at(x, y));
        }
      publish(scene, std::move(big), 0, spp, result.stats, result.texture_stats,
              fmt::format("preview: {}x{} at 1 spp, shown at {}x{}\n", small.width, small.height, W,
                          H));
      first_shown("preview", small);
    }

    rt::Image sum;  // the passes' samples summed per pixel
    rt::RenderStats total;
    for (std::size_t k = 0; k < passes.size(); ++k) {
      auto [a, b] = passes[k];
      page_.set_status(
          fmt::format("rendering pass {}/{} ({} of {} spp)", k + 1, passes.size(), b, spp));
      Outcome out = render_watching(scene, passes[k], result);
      if (out == Outcome::Changed && !o_.quiet)
        std::cerr << fmt::format("snell watch: a file changed; pass {} ({} spp) dropped\n", k + 1,
                                 b);
      if (out != Outcome::Done) return out == Outcome::Changed;
      // The mean of [0, b) from the mean of [0, a) and of [a, b).
      const rt::Image& im = result.image;
      if (k == 0) {
        sum = im;
      } else {
        for (std::size_t i = 0; i < sum.rgb.size(); ++i) sum.rgb[i] += im.rgb[i] * float(b - a);
      }
      rt::Image shown = sum;
      if (b > 1)
        for (float& v : shown.rgb) v /= float(b);
      total.merge(result.stats);
      total.build_seconds += result.stats.build_seconds;
      total.render_seconds += result.stats.render_seconds;
      // merge() sums the counters; the times are each render's own.
      const rt::RenderStats& r = result.stats;
      total.camera_seconds += r.camera_seconds;
      total.shadow_seconds += r.shadow_seconds;
      total.reflection_seconds += r.reflection_seconds;
      total.refraction_seconds += r.refraction_seconds;
      total.glossy_seconds += r.glossy_seconds;
      total.lens_seconds += r.lens_seconds;
      total.time_seconds += r.time_seconds;
      total.kernel = result.stats.kernel;
      total.cost_stride = result.stats.cost_stride;
      publish(scene, std::move(shown), b, spp, total, result.texture_stats, "");
      if (!o_.quiet)
        std::cerr << fmt::format(
            "snell watch: pass {}/{}: {} of {} spp ({:.2f} s, {:.2f} s in all)\n", k + 1,
            passes.size(), b, spp, result.stats.render_seconds, total.render_seconds);
      first_shown("first pass", im);
    }
    page_.set_status(fmt::format("done: {} spp; waiting for a change", spp));
    return false;
  }

  // Shows an image on the page and in tev; `spp` 0 is the preview, `note` heads
  // the statistics.
  void publish(const ir::Scene& scene, rt::Image image, std::uint32_t spp, std::uint32_t target,
               const rt::RenderStats& total, const std::string& extra, const std::string& note) {
    std::vector<unsigned char> png;
    if (!temp_.path.empty()) {
      rt::OutputInfo info;
      info.scene_path = o_.scene;
      info.samples = spp;
      info.seed = scene.settings.seed;
      info.render_seconds = total.render_seconds;
      std::string path = temp_.path + "/pass.png";
      std::string err = rt::write_image(path, image, info, o_.display_view());
      if (!err.empty() || !read_bytes(path, png)) {
        png.clear();
        page_.set_diagnostics("snell: error: the page's PNG: " + err + "\n", true);
      }
    }
    std::string stats =
        note + fmt::format("{}x{}, {} of {} spp\n", image.width, image.height, spp, target);
    stats += total.to_string() + extra;
    // Moved, not copied, into the page: an image can be gigabytes (16384² is 3 GB).
    if (tev_) tev_->show(tev_name_, image);
    page_.set_image(std::move(image), std::move(png), spp, target, stats);
  }

  const CliArgs& o_;
  WatchPage& page_;
  TevStream* tev_;
  std::string tev_name_;
  FileWatch files_;
  TempFolder temp_;
  std::chrono::steady_clock::time_point changed_at_ = std::chrono::steady_clock::now();
  bool first_pass_pending_ = true;
  std::string usage_;  // a usage error in the options: the watch ends with exit 2
};

}  // namespace

int run_watch(const CliArgs& o) {
  if (o.features != "auto" && o.features != "all")
    return usage_error("--features takes 'auto' or 'all', not '" + o.features + "'");
  compile::CompileOptions copts;
  std::string error;
  if (!build_compile_options(o, copts, error)) return usage_error(error);
  // Options no edit of the scene can fix (`--set foo=1`, `--res 0x0`) are wrong
  // usage before the URL is printed: a script reading it took the watch as
  // started. They are checked on an empty scene (the real one may not exist yet).
  if (auto empty = compile::compile_source(o.scene, "", copts);
      empty->status == compile::CompileStatus::UsageError)
    return usage_error(empty->message);
  std::string host, port;
  if (!o.display_server.empty() && !TevStream::parse_address(o.display_server, host, port, error))
    return usage_error(error);
  // The image writer and display transform are needed for every pass's PNG: a
  // missing module or a broken OCIO config is said now (exit 3), not per pass.
  if (std::string err = rt::preload_image_writer(); !err.empty()) {
    std::cerr << "snell: error: cannot write images: " << err << "\n";
    return kExitIo;
  }
  if (std::string err = rt::check_display_transform(o.display_view()); !err.empty()) {
    std::cerr << "snell: error: the page's PNG: " << err << "\n";
    return kExitIo;
  }
  WatchPage page(o.scene);
  if (!page.start(o.watch_port, error)) {
    std::cerr << "snell: error: " << error << "\n";
    return kExitIo;
  }
  // The URL on stdout, alone on its line and flushed: scripts read it from there.
  std::cout << "http://127.0.0.1:" << page.port() << "/" << std::endl;
  std::unique_ptr<TevStream> tev;
  if (!o.display_server.empty()) tev = std::make_unique<TevStream>(host, port, o.quiet);

  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  std::signal(SIGPIPE, SIG_IGN);  // a browser that goes away mid-answer

  int code = Watcher(o, page, tev.get()).run();
  page.stop();
  if (!o.quiet) std::cerr << "snell watch: stopped\n";
  return code;
}

}  // namespace snell::cli
