// render, check, dump-ast and merge: read → lex/parse → evaluate → lower →
// ir::Scene → render → write images; and, for a split render (§18), pieces →
// checked and assembled → one image.
#include "cli/commands.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <limits>
#include <memory>
#include <optional>
#include <set>
#include <unordered_map>

#include "cli/animation.hpp"
#include "cli/progress.hpp"
#include "cli/split.hpp"
#include "language/parser.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/image_format.hpp"
#include "runtime/image_helper.hpp"
#include "runtime/memory_estimate.hpp"
#include "runtime/render.hpp"
#include "runtime/scene_checks.hpp"

namespace snell::cli {

namespace {
// "AsepB" of two whole numbers written as digits only (no sign, no spaces), each
// at most 2^32 - 1: strtoul and sscanf's %u would take "-5" as 4294967291.
bool parse_pair(const std::string& s, char sep, unsigned& a, unsigned& b) {
  auto num = [](std::string_view t, unsigned& v) {
    if (t.empty() || t.size() > 10 || t.find_first_not_of("0123456789") != std::string_view::npos)
      return false;
    unsigned long long x = std::stoull(std::string(t));
    if (x > 0xffffffffull) return false;
    v = unsigned(x);
    return true;
  };
  std::size_t k = s.find(sep);
  if (sep == 'x' && k == std::string::npos) k = s.find('X');
  if (k == std::string::npos) return false;
  return num(std::string_view(s).substr(0, k), a) && num(std::string_view(s).substr(k + 1), b);
}
}  // namespace

namespace {
namespace fs = std::filesystem;
}  // namespace

bool color_stderr() {
  return isatty(STDERR_FILENO) && !std::getenv("NO_COLOR");
}

int usage_error(const std::string& message) {
  std::cerr << "snell: error: " << message << "\n";
  return kExitUsage;
}

bool build_compile_options(const CliArgs& o, compile::CompileOptions& c, std::string& error) {
  c.include_dirs = o.include_dirs;
  c.max_errors = o.max_errors;
  c.step_budget = o.max_steps;
  for (const std::string& kv : o.sets) {
    auto eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) {
      error = "--set takes KEY=VALUE, got '" + kv + "'";
      return false;
    }
    c.overrides.push_back({kv.substr(0, eq), kv.substr(eq + 1)});
  }
  // The shorthands' messages name the option the user gave.
  auto shorthand = [&](std::string key, std::string value, std::string written) {
    c.override_labels.resize(c.overrides.size());
    c.overrides.push_back({std::move(key), std::move(value)});
    c.override_labels.push_back(std::move(written));
  };
  if (o.spp) shorthand("samples", std::to_string(*o.spp), "--spp " + std::to_string(*o.spp));
  if (!o.res.empty()) {
    unsigned w = 0, h = 0;
    if (!parse_pair(o.res, 'x', w, h)) {
      error = "--res takes WIDTHxHEIGHT in whole pixels (e.g. 640x480), got '" + o.res + "'";
      return false;
    }
    shorthand("resolution", "<" + std::to_string(w) + ", " + std::to_string(h) + ">",
              "--res " + o.res);
  }
  if (o.seed) shorthand("seed", std::to_string(*o.seed), "--seed " + std::to_string(*o.seed));
  return true;
}

void warn_overridden_overrides(const compile::CompileOptions& c) {
  auto label = [&](std::size_t i) {
    if (i < c.override_labels.size() && !c.override_labels[i].empty()) return c.override_labels[i];
    return "--set " + c.overrides[i].first + "=" + c.overrides[i].second;
  };
  for (std::size_t i = 0; i < c.overrides.size(); ++i) {
    std::size_t last = i;  // the one that takes effect
    for (std::size_t j = i + 1; j < c.overrides.size(); ++j)
      if (c.overrides[j].first == c.overrides[i].first) last = j;
    if (c.overrides[last].second != c.overrides[i].second)
      std::cerr << "snell: warning: '" << c.overrides[i].first << "' is set twice: " << label(last)
                << " wins over " << label(i) << "\n";
  }
}

namespace {

// Compiles and prints diagnostics; returns an exit code, or -1 to go on.
// §17: every image opens through the texture system as part of the compilation
// (exit 3 before the render), an image it cannot read reported at its `file` beside
// the compiler's other errors (§10: all of them). Loads the image module, so only
// for scenes with images; not for --dump-ir.
int compile_scene(const CliArgs& o, const compile::CompileOptions& given,
                  std::unique_ptr<compile::Compilation>& out) {
  compile::CompileOptions copts = given;
  if (!o.dump_ir) copts.unreadable_images = cached_image_check(o.ocio_config);
  out = compile::compile_file(o.scene, copts);
  out->diags.print(std::cerr, color_stderr());
  switch (out->status) {
    case compile::CompileStatus::Ok:
      break;
    case compile::CompileStatus::SceneErrors:
    case compile::CompileStatus::FileErrors:
      std::cerr << error_count_line(out->diags, o.scene);
      return out->status == compile::CompileStatus::FileErrors ? kExitIo : kExitScene;
    case compile::CompileStatus::UsageError:
      return usage_error(out->message);
    case compile::CompileStatus::IoError:
      std::cerr << "snell: error: " << out->message << "\n";
      return kExitIo;
  }
  // The compiler reports these as diagnostics already; this is the runtime's
  // contract, kept for an IR that did not come from it.
  std::vector<ir::Problem> problems = ir::validate(out->scene);
  if (!problems.empty()) {
    for (const ir::Problem& p : problems) std::cerr << ir::to_string(p, out->scene) << "\n";
    return kExitScene;
  }
  return -1;
}

int compile_scene(const CliArgs& o, std::unique_ptr<compile::Compilation>& out) {
  compile::CompileOptions copts;
  std::string error;
  if (!build_compile_options(o, copts, error)) return usage_error(error);
  warn_overridden_overrides(copts);
  if (o.clock) copts.clock = *o.clock;
  return compile_scene(o, copts, out);
}

}  // namespace

std::string error_count_line(const lang::DiagnosticEngine& diags, const std::string& scene) {
  const std::size_t n = std::max<std::size_t>(diags.error_count(), 1);
  return fmt::format("{}{} error{} in {}\n", diags.counts_are_lower_bounds() ? "at least " : "", n,
                     n == 1 ? "" : "s", scene);
}

// An output that cannot be written fails before the render, not after (exit 3,
// §10): its folder is missing, not a folder or not writable, or the path is a
// folder or something other than a file. (A full disk is found when writing; the
// writer then leaves the old file as it was.)
int check_output_folder(const std::string& out) {
  // A symlink is written through (atomic_file.hpp): its target's folder counts.
  const std::string target = rt::write_target(out);
  fs::path dir = fs::path(target).parent_path();
  std::error_code ec;
  auto fail = [&](const std::string& why) {
    std::cerr << "snell: error: cannot write " << out << ": " << why << "\n";
    return kExitIo;
  };
  if (!dir.empty() && !fs::is_directory(dir, ec))
    return fail("the folder " + dir.string() +
                (fs::exists(dir, ec) ? " is not a folder" : " does not exist"));
  fs::file_status st = fs::status(target, ec);
  if (st.type() == fs::file_type::directory) return fail("it is a folder");
  if (fs::exists(st) && st.type() != fs::file_type::regular)
    return fail("it exists and is not a regular file");
  // The temporary beside it and the rename need the folder writable.
  std::string folder = dir.empty() ? "." : dir.string();
  if (::access(folder.c_str(), W_OK | X_OK) != 0)
    return fail("the folder " + folder + " is not writable (" + std::strerror(errno) + ")");
  return -1;
}

// An output never replaces a file the work reads (§10: nothing is lost): the
// scene, an import, a mesh, an image, a piece being merged. The same file by
// any name counts (a symlink, a hard link, "./a/../a"). Exit 2, before the render.
int check_not_an_input(const std::vector<std::string>& outputs,
                       const std::vector<std::string>& inputs) {
  for (const std::string& out : outputs) {
    std::error_code ec;
    const std::string target = rt::write_target(out);
    if (!fs::exists(target, ec)) continue;
    for (const std::string& in : inputs)
      if (fs::equivalent(target, in, ec))
        return usage_error("the output " + out + " is " + (in == out ? "" : in + ", ") +
                           "a file this command reads: writing it would destroy its input");
  }
  return -1;
}

// The files a compiled scene was made from.
std::vector<std::string> scene_inputs(const ir::Scene& s) {
  std::vector<std::string> files = s.files;
  for (const ir::MeshData& m : s.meshes) files.push_back(m.path);
  for (const ir::ImageFile& im : s.images) files.push_back(im.path);
  return files;
}

int dump_ast(const std::string& path) {
  std::string text, message;
  if (!compile::read_file(path, text, message)) {
    std::cerr << "snell: error: " << message << "\n";
    return kExitIo;
  }
  lang::SourceManager sources;
  lang::DiagnosticEngine diags(sources);
  int code = kExitOk;
  compile::run_with_large_stack([&] {
    lang::Program p = lang::parse(sources, sources.add(path, text), diags);
    std::cout << lang::dump_ast(p);
    diags.print(std::cerr, color_stderr());
    if (diags.has_errors()) code = kExitScene;
  });
  return code;
}

decltype(compile::CompileOptions::unreadable_images) cached_image_check(std::string ocio_config) {
  using Verdict = compile::CompileOptions::ImageVerdict;
  struct Seen {
    std::uintmax_t size = 0;
    fs::file_time_type time;
    std::string why;   // "" readable
    std::string note;  // of a readable image
  };
  auto seen = std::make_shared<std::unordered_map<std::string, Seen>>();
  return [seen, ocio = std::move(ocio_config)](const std::vector<ir::ImageFile>& images) {
    std::vector<Verdict> out;
    auto say = [&](std::size_t i, const Seen& s) {
      if (!s.why.empty()) out.push_back({i, s.why, false});
      if (!s.note.empty()) out.push_back({i, s.note, true});
    };
    std::vector<ir::ImageFile> fresh;
    std::vector<std::size_t> fresh_index;
    std::vector<Seen> fresh_seen;
    for (std::size_t i = 0; i < images.size(); ++i) {
      std::error_code ec;
      Seen now{fs::file_size(images[i].path, ec), fs::last_write_time(images[i].path, ec), {}, {}};
      auto it = seen->find(images[i].path);
      if (!ec && it != seen->end() && it->second.size == now.size && it->second.time == now.time) {
        say(i, it->second);
        continue;
      }
      fresh.push_back(images[i]);
      fresh_index.push_back(i);
      fresh_seen.push_back(now);
    }
    if (!fresh.empty()) {
      std::string err;
      std::vector<std::pair<std::size_t, std::string>> notes;
      auto found = rt::unreadable_images(fresh, ocio, err, &notes);
      for (auto& [k, why] : found) fresh_seen[k].why = why;
      for (auto& [k, note] : notes) fresh_seen[k].note = note;
      if (!err.empty())  // the image module itself: nothing is remembered
        for (std::size_t k = 0; k < fresh.size(); ++k) out.push_back({fresh_index[k], err, false});
      else
        for (std::size_t k = 0; k < fresh.size(); ++k) {
          say(fresh_index[k], fresh_seen[k]);
          (*seen)[fresh[k].path] = fresh_seen[k];
        }
    }
    std::sort(out.begin(), out.end(), [](const Verdict& a, const Verdict& b) {
      return a.image != b.image ? a.image < b.image : a.readable < b.readable;
    });
    return out;
  };
}

int run_check(const CliArgs& o) {
  std::unique_ptr<compile::Compilation> c;
  if (int code = compile_scene(o, c); code >= 0) return code;
  const ir::Scene& s = c->scene;
  std::cout << o.scene << ": ok: " << s.shapes.size() << " object(s), " << s.materials.size()
            << " material(s), " << s.point_lights.size() << " point light(s), "
            << s.area_lights.size() << " area light(s); " << s.settings.width << "x"
            << s.settings.height << " at " << s.settings.samples << " spp\n";
  for (const rt::SceneWarning& w : rt::scene_warnings(s))
    std::cout << o.scene << ": warning: " << w.message << "\n";
  std::cout << "effects:\n";
  ir::Features f = ir::analyze_features(s);
  if (f.reasons.empty()) std::cout << "  (none beyond diffuse shading)\n";
  for (const auto& [effect, why] : f.reasons) std::cout << "  " << effect << ": " << why << "\n";
  return kExitOk;
}

namespace {

// One frame: compiled with its clock and frame, rendered, written. Returns an exit
// code, or -1 when it went well; `total` gathers the statistics.
struct FrameJob {
  const CliArgs& o;
  const compile::CompileOptions& copts;
  std::vector<std::string> outputs;  // this frame's names
  std::int64_t frame = 0;
  double clock = 0;
  bool first = true;  // the first frame rendered: checks that need a scene run once
  rt::RenderStats* total = nullptr;
  // Under --frames: the scene warnings printed for earlier frames. Each frame's
  // scene is compiled afresh and may warn of something new (the camera inside a
  // sphere that grows with the clock); one said already is not said again.
  std::set<std::string>* warned = nullptr;
  bool of_frames = false;
};

// What the image helper found, said as the in-process checks of render_frame
// would say it: exit 3 with the message, or -1 when the writer is ready.
int helper_verdict(const rt::ImageHelperStatus& status, const std::vector<std::string>& outputs) {
  if (!status.load_error.empty()) {
    std::cerr << "snell: error: cannot write images: " << status.load_error << "\n";
    return kExitIo;
  }
  if (!status.display_error.empty())
    for (const std::string& out : outputs)
      if (rt::lower_extension(out) != ".exr") {
        std::cerr << "snell: error: cannot write " << out << ": " << status.display_error << "\n";
        return kExitIo;
      }
  return -1;
}

int render_frame(FrameJob& job) {
  const CliArgs& o = job.o;
  compile::CompileOptions copts = job.copts;
  copts.clock = job.clock;
  copts.frame = double(job.frame);
  std::unique_ptr<compile::Compilation> c;
  if (int code = compile_scene(o, copts, c); code >= 0) return code;
  const ir::Scene& scene = c->scene;
  rt::RenderOptions ropts;
  ropts.threads = o.threads;
  ropts.general_kernel = o.features == "all";
  ropts.ocio_config = o.ocio_config;
  ropts.measure_cost = o.stats;
  const std::uint32_t W = scene.settings.width, H = scene.settings.height;
  const std::uint32_t spp = scene.settings.samples ? scene.settings.samples : 1;
  PieceInfo piece{Window{0, 0, W, H}, IntRange{0, spp}, job.frame, job.clock};
  std::string error;
  if (!o.crop.empty()) {
    if (!parse_crop(o.crop, W, H, piece.crop, error)) return usage_error(error);
    ropts.crop = piece.crop;
  }
  if (!o.sample_range.empty()) {
    if (!parse_range(o.sample_range, "--sample-range", spp, piece.samples, error))
      return usage_error(error + fmt::format(" (the scene has {} samples per pixel)", spp));
    ropts.sample_range = {std::uint32_t(piece.samples.begin), std::uint32_t(piece.samples.end)};
  }
  if (!o.pixel.empty()) {
    unsigned x = 0, y = 0;
    if (!parse_pair(o.pixel, ',', x, y))
      return usage_error("--pixel takes X,Y (e.g. 320,240), got '" + o.pixel + "'");
    const Window& w = piece.crop;
    if (x < w.x0 || x >= w.x1 || y < w.y0 || y >= w.y1)
      return usage_error("--pixel " + o.pixel + " is outside the " +
                         (o.crop.empty() ? std::to_string(W) + "x" + std::to_string(H) + " image"
                                         : "crop " + o.crop));
    ropts.trace_pixel = {{x, y}};
    // Alone (no image asked for) only that pixel is rendered: the whole image was
    // rendered and thrown away (a second where a millisecond does), and --stats
    // counts that pixel's rays.
    if (job.outputs.empty()) ropts.crop = Window{x, y, x + 1, y + 1};
  }
  // --dump-ir after the options that take the scene's size are checked (a
  // --pixel, --crop or --sample-range it cannot have was taken silently): every
  // frame's, under --frames, each under its own header.
  if (o.dump_ir) {
    if (job.of_frames) std::cout << fmt::format("frame {} (clock {}):\n", job.frame, job.clock);
    std::cout << ir::to_string(scene);
    std::cout << "features:\n" << ir::to_string(ir::analyze_features(scene));
    return -1;
  }

  if (int code = check_not_an_input(job.outputs, scene_inputs(scene)); code >= 0) return code;
  // §17 images need the image module in this process (the texture system reads
  // them during the render): the helper would only load it a second time.
  if (!scene.images.empty()) rt::stop_image_helper();
  if (job.first) {
    for (const std::string& out : job.outputs) {
      if (int code = check_output_folder(out); code >= 0) return code;
      const Window& w = piece.crop;
      if (std::string why = rt::format_limit(out, w.x1 - w.x0, w.y1 - w.y0); !why.empty()) {
        std::cerr << "snell: error: cannot write " << out << ": " << why << "\n";
        return kExitIo;
      }
    }
    // The image writer (OIIO, ~0.25 s to load) is loading in the helper process
    // since run_render began (image_helper.hpp); what it has found so far is
    // said now, the rest as soon as it is known (the render is then cancelled).
    // Without a helper it loads here, before the render, so a writer that cannot
    // load fails now, not after the render is done. Not on a thread beside the
    // render: its dlopen holds the loader lock, which Embree's and TBB's thread
    // start-up wait for (measured: 0.33 -> 0.25 s for a tiny render).
    if (rt::image_helper_running()) {
      if (auto status = rt::image_helper_status(false))
        if (int code = helper_verdict(*status, job.outputs); code >= 0) return code;
    } else {
      if (std::string err = rt::preload_image_writer(); !err.empty()) {
        std::cerr << "snell: error: cannot write images: " << err << "\n";
        return kExitIo;
      }
      // A display-referred output needs the OCIO config's display transform.
      for (const std::string& out : job.outputs)
        if (rt::lower_extension(out) != ".exr") {
          if (std::string err = rt::check_display_transform(o.display_view()); !err.empty()) {
            std::cerr << "snell: error: cannot write " << out << ": " << err << "\n";
            return kExitIo;
          }
          break;
        }
    }
  }
  // Memory the render would need beyond the scene, before any of it is taken.
  {
    std::uint64_t limit = rt::physical_memory() / 10 * 9;
    if (!o.max_memory.empty() && !rt::parse_bytes(o.max_memory, limit))
      return usage_error("--max-memory takes a size such as 8G, 512M or 2.5GB, not '" +
                         o.max_memory + "'");
    const Window& w = piece.crop;
    rt::MemoryEstimate need = rt::estimate_memory(scene, w.x1 - w.x0, w.y1 - w.y0, job.outputs);
    if (limit > 0 && need.total() > limit) {
      std::cerr << "snell: error: " << o.scene << ": the render needs about " << need.to_string()
                << ", more than the limit of " << rt::format_bytes(limit)
                << (o.max_memory.empty() ? " (90 % of this machine's memory)" : " (--max-memory)")
                << "; lower the resolution, split it with --crop, or raise --max-memory\n";
      return kExitScene;
    }
  }
  if (job.first || job.warned)
    for (const rt::SceneWarning& w : rt::scene_warnings(scene))
      if (!job.warned || job.warned->insert(w.message).second)
        std::cerr << o.scene << ": warning: " << w.message
                  << (job.of_frames ? fmt::format(" (frame {})", job.frame) : std::string())
                  << "\n";
  Progress progress(!o.quiet, isatty(STDERR_FILENO));
  // A helper still loading is asked after each tile: a writer that cannot load
  // or a display transform that cannot be made cancels the render at once.
  std::atomic<bool> helper_pending{job.first && rt::image_helper_running()};
  std::atomic<bool> cancel{false};
  ropts.cancel = &cancel;
  ropts.progress = [&](double f) {
    progress.update(f);
    if (!helper_pending.load(std::memory_order_relaxed)) return;
    if (auto status = rt::image_helper_status(false)) {
      helper_pending.store(false, std::memory_order_relaxed);
      if (!status->load_error.empty() || !status->display_error.empty()) cancel.store(true);
    }
  };
  rt::RenderResult result = rt::render(scene, ropts);
  progress.finish();
  if (job.first && rt::image_helper_running())
    if (int code = helper_verdict(*rt::image_helper_status(true), job.outputs); code >= 0)
      return code;
  if (!result.trace.empty())
    std::cerr << (job.of_frames ? fmt::format("frame {} (clock {}): ", job.frame, job.clock)
                                : std::string())
              << result.trace;

  rt::OutputInfo info;
  info.scene_path = o.scene;
  info.samples = scene.settings.samples;
  info.seed = scene.settings.seed;
  info.render_seconds = result.stats.render_seconds;
  info.attributes = piece_attributes(scene, piece);
  int code = -1;
  for (const std::string& out : job.outputs) {
    std::string err = rt::write_image(out, result.image, info, o.display_view());
    if (!err.empty()) {
      std::cerr << "snell: error: " << err << "\n";
      code = kExitIo;
    } else if (!o.quiet) {
      std::cerr << "wrote " << out << "\n";
    }
  }
  if (o.stats)
    std::cerr << result.stats.to_string() << result.texture_stats
              << "images encoded by: " << rt::image_encoder_for(result.image) << "\n";
  if (result.stats.nonfinite_samples > 0)
    std::cerr << "snell: warning: " << result.stats.nonfinite_samples
              << " non-finite sample(s) were dropped\n";
  if (job.total) {
    job.total->merge(result.stats);
    job.total->build_seconds += result.stats.build_seconds;
    job.total->render_seconds += result.stats.render_seconds;
  }
  return code;
}

}  // namespace

int run_render(const CliArgs& o) {
  std::vector<std::string> outputs = o.outputs;
  // --pixel alone is a look at one pixel's ray tree: it writes an image only where
  // -o asks for one, never over the default SCENE-STEM.png.
  if (outputs.empty() && o.pixel.empty())
    outputs.push_back(fs::path(o.scene).stem().string() + ".png");
  for (const std::string& out : outputs)
    if (!rt::is_supported_image_extension(out))
      return usage_error("cannot tell the image format of '" + out +
                         "': use .exr, .png, .jpg, .jpeg, .tif or .tiff");
  // The same file named twice (`-o a.exr -o ./a.exr`, or by a link) is written once.
  {
    std::vector<std::string> distinct;
    for (const std::string& out : outputs) {
      std::error_code ec;
      auto same = [&](const std::string& d) {
        return fs::absolute(d, ec).lexically_normal() == fs::absolute(out, ec).lexically_normal() ||
               (fs::exists(d, ec) && fs::equivalent(d, out, ec));
      };
      auto it = std::find_if(distinct.begin(), distinct.end(), same);
      if (it == distinct.end())
        distinct.push_back(out);
      else
        std::cerr << "snell: warning: -o " << out << " is the same file as -o " << *it
                  << "; it is written once\n";
    }
    outputs = std::move(distinct);
  }
  if (o.features != "auto" && o.features != "all")
    return usage_error("--features takes 'auto' or 'all', not '" + o.features + "'");
  compile::CompileOptions copts;
  std::string error;
  if (!build_compile_options(o, copts, error)) return usage_error(error);
  warn_overridden_overrides(copts);
  // §18: one frame (clock from --clock, default 0), or --frames A..B. Checked with
  // the other options, before any work (and for --dump-ast too, which takes them).
  if (o.frames.empty() && o.frame)
    return usage_error("--frame F picks one frame of a sequence: give --frames A..B with it");
  IntRange frames, run;  // all the frames, and those this process renders
  if (!o.frames.empty()) {
    if (o.clock)
      return usage_error(
          "--clock sets the clock of a single frame; with --frames each frame's clock is "
          "(frame - A) / (B - A): give one or the other");
    if (!parse_range(o.frames, "--frames", std::numeric_limits<std::int32_t>::max(), frames, error))
      return usage_error(error);
    run = frames;
    if (o.frame) {
      if (*o.frame < frames.begin || *o.frame >= frames.end)
        return usage_error(fmt::format("--frame {} is not one of --frames {}", *o.frame, o.frames));
      run = {*o.frame, *o.frame + 1};
    }
  }
  if (o.dump_ast) return dump_ast(o.scene);

  // The image module loads in a helper process while the scene compiles and
  // renders (image_helper.hpp); stopped, however this returns.
  if (!o.dump_ir) {
    std::optional<rt::DisplayView> display;
    for (const std::string& out : outputs)
      if (rt::lower_extension(out) != ".exr") display = o.display_view();
    rt::start_image_helper(display);
  }
  struct StopHelper {
    ~StopHelper() { rt::stop_image_helper(/*leave_resident=*/true); }
  } stop_helper;

  if (o.frames.empty()) {
    FrameJob job{o, copts, outputs, 0, o.clock.value_or(0.0)};
    int code = render_frame(job);
    return code < 0 ? kExitOk : code;
  }
  rt::RenderStats total;
  std::set<std::string> warned;
  Progress overall(false, false);  // its clock only: the frames' ETA
  for (std::int64_t f = run.begin; f < run.end; ++f) {
    FrameJob job{o, copts, {}, f, frame_clock(frames, f), f == run.begin, &total, &warned, true};
    for (const std::string& out : outputs) job.outputs.push_back(frame_output_name(out, f));
    if (int code = render_frame(job); code >= 0) {
      // Which frame it was: an error that depends on the clock names no frame.
      if (code != kExitOk)
        std::cerr << fmt::format("snell: note: in frame {} of --frames {} (clock {})\n", f,
                                 o.frames, job.clock);
      return code;
    }
    std::int64_t done = f - run.begin + 1;
    double elapsed = overall.seconds();
    if (!o.quiet && !o.dump_ir)
      std::cerr << fmt::format("frame {} ({}/{}, clock {}) done: {:.1f}s elapsed, ETA {:.1f}s\n", f,
                               done, run.size(), job.clock, elapsed,
                               elapsed / double(done) * double(run.size() - done));
  }
  if (o.stats) std::cerr << fmt::format("total over {} frames:\n", run.size()) << total.to_string();
  return kExitOk;
}

int run_merge(const CliArgs& o) {
  if (!rt::is_supported_image_extension(o.merge_out))
    return usage_error("cannot tell the image format of '" + o.merge_out +
                       "': use .exr, .png, .jpg, .jpeg, .tif or .tiff");
  for (const std::string& p : o.pieces)
    if (rt::lower_extension(p) != ".exr")
      return usage_error("merge reads EXR pieces (linear radiance), not '" + p + "'");
  if (int code = check_not_an_input({o.merge_out}, o.pieces); code >= 0) return code;
  if (int code = check_output_folder(o.merge_out); code >= 0) return code;
  if (rt::lower_extension(o.merge_out) != ".exr")
    if (std::string err = rt::check_display_transform(o.display_view()); !err.empty()) {
      std::cerr << "snell: error: cannot write " << o.merge_out << ": " << err << "\n";
      return kExitIo;
    }
  std::vector<Piece> pieces(o.pieces.size());
  for (std::size_t i = 0; i < pieces.size(); ++i) {
    pieces[i].path = o.pieces[i];
    // Said as such (OpenImageIO's word for them is "Could not open file").
    std::error_code ec;
    if (const fs::file_status st = fs::status(o.pieces[i], ec);
        !fs::exists(st) || fs::is_directory(st)) {
      std::cerr << "snell: error: cannot read " << o.pieces[i] << ": "
                << (fs::is_directory(st) ? "it is a folder" : "it does not exist") << "\n";
      return kExitIo;
    }
    if (std::string err = rt::read_image(o.pieces[i], pieces[i].file); !err.empty()) {
      std::cerr << "snell: error: " << err << "\n";
      return kExitIo;
    }
  }
  rt::Image image;
  rt::OutputInfo info;
  if (std::string err = merge_pieces(pieces, image, info.attributes); !err.empty()) {
    std::cerr << "snell: error: merge: " << err << "; nothing written\n";
    return kExitScene;
  }
  const rt::ImageFile& first = pieces[0].file;
  if (const std::string* s = first.attribute("snell:scene")) info.scene_path = *s;
  if (const std::string* s = first.attribute("snell:samples")) info.samples = std::stoul(*s);
  if (const std::string* s = first.attribute("snell:seed")) info.seed = std::stoull(*s);
  for (const Piece& p : pieces)
    if (const std::string* s = p.file.attribute("snell:render_seconds"))
      info.render_seconds += std::atof(s->c_str());
  if (std::string err = rt::write_image(o.merge_out, image, info, o.display_view()); !err.empty()) {
    std::cerr << "snell: error: " << err << "\n";
    return kExitIo;
  }
  if (!o.quiet) std::cerr << "merged " << pieces.size() << " pieces into " << o.merge_out << "\n";
  return kExitOk;
}

}  // namespace snell::cli
