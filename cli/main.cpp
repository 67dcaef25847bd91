// snell: the command line. Wires the passes together:
//   read → lex/parse → evaluate → lower → ir::Scene → render → write images.
// Exit status (spec §10): 0 success; 1 errors in the scene; 2 wrong usage;
// 3 a file could not be read or written.
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <optional>

#include "cli/options.hpp"
#include "cli/progress.hpp"
#include "cli/sweep.hpp"
#include "compiler/compile.hpp"
#include "language/parser.hpp"
#include "lsp/server.hpp"
#include "runtime/render.hpp"

namespace {

namespace fs = std::filesystem;
using namespace snell;

constexpr int kExitOk = 0, kExitScene = 1, kExitUsage = 2, kExitIo = 3;

bool color_stderr() {
  return isatty(STDERR_FILENO) && !std::getenv("NO_COLOR");
}

int usage_error(const std::string& message) {
  std::cerr << "snell: error: " << message << "\n";
  return kExitUsage;
}

// Turns the shorthand flags into settings overrides, in the order a user expects:
// --set first, then the dedicated flags (which are more specific).
bool build_compile_options(const cli::CliArgs& o, compile::CompileOptions& c, std::string& error) {
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
  if (o.spp) c.overrides.push_back({"samples", std::to_string(*o.spp)});
  if (!o.res.empty()) {
    unsigned w = 0, h = 0;
    char x = 0, extra = 0;
    if (std::sscanf(o.res.c_str(), "%u%c%u%c", &w, &x, &h, &extra) != 3 || (x != 'x' && x != 'X')) {
      error = "--res takes WIDTHxHEIGHT (e.g. 640x480), got '" + o.res + "'";
      return false;
    }
    c.overrides.push_back({"resolution", "<" + std::to_string(w) + ", " + std::to_string(h) + ">"});
  }
  if (o.seed) c.overrides.push_back({"seed", std::to_string(*o.seed)});
  return true;
}

// Compiles and prints diagnostics; returns an exit code, or -1 to go on.
int compile_scene(const cli::CliArgs& o, std::unique_ptr<compile::Compilation>& out) {
  compile::CompileOptions copts;
  std::string error;
  if (!build_compile_options(o, copts, error)) return usage_error(error);
  out = compile::compile_file(o.scene, copts);
  out->diags.print(std::cerr, color_stderr());
  switch (out->status) {
    case compile::CompileStatus::Ok:
      break;
    case compile::CompileStatus::SceneErrors:
    case compile::CompileStatus::FileErrors: {
      std::size_t n = out->diags.error_count();
      std::cerr << n << " error" << (n == 1 ? "" : "s") << " in " << o.scene << "\n";
      return out->status == compile::CompileStatus::FileErrors ? kExitIo : kExitScene;
    }
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

int run_check(const cli::CliArgs& o) {
  std::unique_ptr<compile::Compilation> c;
  if (int code = compile_scene(o, c); code >= 0) return code;
  const ir::Scene& s = c->scene;
  std::cout << o.scene << ": ok: " << s.shapes.size() << " object(s), " << s.materials.size()
            << " material(s), " << s.point_lights.size() << " point light(s), "
            << s.area_lights.size() << " area light(s); " << s.settings.width << "x"
            << s.settings.height << " at " << s.settings.samples << " spp\n";
  std::cout << "effects:\n";
  ir::Features f = ir::analyze_features(s);
  if (f.reasons.empty()) std::cout << "  (none beyond diffuse shading)\n";
  for (const auto& [effect, why] : f.reasons) std::cout << "  " << effect << ": " << why << "\n";
  return kExitOk;
}

int run_render(const cli::CliArgs& o) {
  if (o.dump_ast) return dump_ast(o.scene);
  std::vector<std::string> outputs = o.outputs;
  if (outputs.empty()) outputs.push_back(fs::path(o.scene).stem().string() + ".png");
  for (const std::string& out : outputs)
    if (!rt::is_supported_image_extension(out))
      return usage_error("cannot tell the image format of '" + out +
                         "': use .exr, .png, .jpg, .jpeg, .tif or .tiff");
  if (o.features != "auto" && o.features != "all")
    return usage_error("--features takes 'auto' or 'all', not '" + o.features + "'");
  rt::RenderOptions ropts;
  ropts.threads = o.threads;
  ropts.general_kernel = o.features == "all";
  ropts.measure_cost = o.stats;
  if (!o.pixel.empty()) {
    unsigned x = 0, y = 0;
    char comma = 0, extra = 0;
    if (std::sscanf(o.pixel.c_str(), "%u%c%u%c", &x, &comma, &y, &extra) != 3 || comma != ',')
      return usage_error("--pixel takes X,Y (e.g. 320,240), got '" + o.pixel + "'");
    ropts.trace_pixel = {{x, y}};
  }

  std::unique_ptr<compile::Compilation> c;
  if (int code = compile_scene(o, c); code >= 0) return code;
  const ir::Scene& scene = c->scene;
  if (o.dump_ir) {
    std::cout << ir::to_string(scene);
    std::cout << "features:\n" << ir::to_string(ir::analyze_features(scene));
    return kExitOk;
  }
  if (ropts.trace_pixel && (ropts.trace_pixel->first >= scene.settings.width ||
                            ropts.trace_pixel->second >= scene.settings.height))
    return usage_error("--pixel " + o.pixel + " is outside the " +
                       std::to_string(scene.settings.width) + "x" +
                       std::to_string(scene.settings.height) + " image");

  // An output whose folder is missing fails now, not after the render (exit 3, §10).
  for (const std::string& out : outputs) {
    fs::path dir = fs::path(out).parent_path();
    std::error_code ec;
    if (!dir.empty() && !fs::is_directory(dir, ec)) {
      std::cerr << "snell: error: cannot write " << out << ": the folder " << dir.string()
                << (fs::exists(dir, ec) ? " is not a folder" : " does not exist") << "\n";
      return kExitIo;
    }
  }
  // The image writer (OIIO, ~0.25 s to load) loads before the render: a writer that
  // cannot load fails now, not after the render is done. Not on a thread beside
  // the render: its dlopen holds the loader lock, which Embree's and TBB's thread
  // start-up wait for, and its CPU time is taken from the render's cores
  // (measured: 0.33 -> 0.25 s for a tiny render, 3.8 -> 3.6 s for a 3.5 s one).
  if (std::string err = rt::preload_image_writer(); !err.empty()) {
    std::cerr << "snell: error: cannot write images: " << err << "\n";
    return kExitIo;
  }
  // §17: every image opens through the texture system before the render (exit 3).
  if (std::string err = rt::check_images(scene); !err.empty()) {
    std::cerr << "snell: error: " << err << "\n";
    return kExitIo;
  }
  cli::Progress progress(!o.quiet, isatty(STDERR_FILENO));
  ropts.progress = [&](double f) { progress.update(f); };
  rt::RenderResult result = rt::render(scene, ropts);
  progress.finish();
  if (!result.trace.empty()) std::cerr << result.trace;

  rt::OutputInfo info;
  info.scene_path = o.scene;
  info.samples = scene.settings.samples;
  info.seed = scene.settings.seed;
  info.render_seconds = result.stats.render_seconds;
  int code = kExitOk;
  for (const std::string& out : outputs) {
    std::string err = rt::write_image(out, result.image, info, o.ocio_config);
    if (!err.empty()) {
      std::cerr << "snell: error: " << err << "\n";
      code = kExitIo;
    } else if (!o.quiet) {
      std::cerr << "wrote " << out << "\n";
    }
  }
  if (o.stats) std::cerr << result.stats.to_string() << result.texture_stats;
  if (result.stats.nonfinite_samples > 0)
    std::cerr << "snell: warning: " << result.stats.nonfinite_samples
              << " non-finite sample(s) were dropped\n";
  return code;
}

}  // namespace

namespace {
// Runs the subcommand the command line chose.
int dispatch(unsigned command, const cli::CliArgs& o) {
  switch (command) {
    case cli::Render:
      return run_render(o);
    case cli::Check:
      return run_check(o);
    case cli::DumpAst:
      return dump_ast(o.scene);
    case cli::Lsp: {
      lsp::ServerOptions so;
      so.include_dirs = o.include_dirs;
      // The render default is far too much work per keystroke: the server's own
      // budget applies unless --max-steps says otherwise.
      if (o.max_steps != compile::kDefaultStepBudget) so.step_budget = o.max_steps;
      return lsp::run_stdio(so);
    }
    case cli::Sweep: {
      cli::SweepOptions so = o.sweep;
      so.scene = o.scene;
      so.threads = o.threads;
      so.quiet = o.quiet;
      std::string error;
      if (!build_compile_options(o, so.compile, error)) return usage_error(error);
      for (const std::string& v : o.vary) {
        cli::SweepAxis axis;
        if (!cli::parse_axis(v, axis))
          return usage_error("--vary takes KEY=V1,V2,..., got '" + v + "'");
        so.vary.push_back(axis);
      }
      if (!o.series.empty() && !cli::parse_axis(o.series, so.series))
        return usage_error("--series takes KEY=V1,V2,..., got '" + o.series + "'");
      return cli::run_sweep(so);
    }
  }
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"snell: a scene language and ray tracer", "snell"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "snell 0.1.0");
  cli::CliArgs o;
  cli::add_commands(app, o);  // every subcommand and its options: cli/options.def

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    return code == 0 ? kExitOk : kExitUsage;
  }
  // Last line of defence: nothing a user types may end in an abort. Memory the
  // machine does not have is reported (exit 1: the scene asks for it); anything
  // else escaping is a Snell bug, reported as such.
  try {
    return dispatch(cli::parsed_command(app), o);
  } catch (const std::bad_alloc&) {
    std::cerr << "snell: error: out of memory (the scene needs more memory than this machine "
                 "has; lower the resolution, samples or geometry)\n";
    return kExitScene;
  } catch (const std::exception& e) {
    std::cerr << "snell: error: internal error: " << e.what() << "\n";
    return kExitScene;
  }
}
