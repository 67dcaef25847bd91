// snell: the command line. Wires the passes together:
//   read → lex/parse → evaluate → lower → ir::Scene → render → write images.
// Exit status (spec §10): 0 success; 1 errors in the scene; 2 wrong usage;
// 3 a file could not be read or written.
// The subcommands themselves are in cli/commands.cpp and cli/sweep.cpp.
#include <CLI/CLI.hpp>
#include <iostream>

#include "cli/commands.hpp"
#include "cli/farm.hpp"
#include "cli/options.hpp"
#include "cli/sweep.hpp"
#include "cli/watch.hpp"
#include "compiler/compile.hpp"
#include "lsp/server.hpp"
#include "runtime/atomic_file.hpp"
#include "runtime/scene_checks.hpp"

namespace {

using namespace snell;
using cli::kExitOk, cli::kExitScene, cli::kExitUsage;

// Runs the subcommand the command line chose.
int dispatch(unsigned command, const cli::CliArgs& o) {
  switch (command) {
    case cli::Render:
      return cli::run_render(o);
    case cli::Check:
      return cli::run_check(o);
    case cli::DumpAst:
      return cli::dump_ast(o.scene);
    case cli::Merge:
      return cli::run_merge(o);
    case cli::Farm:
      return cli::run_farm(o);
    case cli::Watch:
      return cli::run_watch(o);
    case cli::Lsp: {
      lsp::ServerOptions so;
      so.include_dirs = o.include_dirs;
      // The render default is far too much work per keystroke: the server's own
      // budget applies unless --max-steps says otherwise.
      if (o.max_steps != compile::kDefaultStepBudget) so.step_budget = o.max_steps;
      so.unreadable_images = cli::cached_image_check(o.ocio_config);
      so.scene_warnings = [](const ir::Scene& scene) {
        lsp::AnalysisOptions::SceneWarnings out;
        for (rt::SceneWarning& w : rt::scene_warnings(scene))
          out.emplace_back(std::move(w.message), w.where);
        return out;
      };
      return lsp::run_stdio(so);
    }
    case cli::Sweep: {
      cli::SweepOptions so = o.sweep;
      so.scene = o.scene;
      so.threads = o.threads;
      so.quiet = o.quiet;
      std::string error;
      if (!cli::build_compile_options(o, so.compile, error)) return cli::usage_error(error);
      cli::warn_overridden_overrides(so.compile);
      for (const std::string& v : o.vary) {
        cli::SweepAxis axis;
        if (!cli::parse_axis(v, axis))
          return cli::usage_error("--vary takes KEY=V1,V2,..., got '" + v + "'");
        // One knob is one table and one plot: a second --vary of it wrote over the
        // first's plot and repeated its table.
        for (const cli::SweepAxis& earlier : so.vary)
          if (earlier.key == axis.key)
            return cli::usage_error("--vary " + axis.key +
                                    " is given twice: give all its values in one --vary");
        so.vary.push_back(axis);
      }
      if (!o.series.empty() && !cli::parse_axis(o.series, so.series))
        return cli::usage_error("--series takes KEY=V1,V2,..., got '" + o.series + "'");
      // A knob both varied and the series: the series' value was overridden by the
      // row's, yet the rows were labelled with it.
      for (const cli::SweepAxis& axis : so.vary)
        if (!so.series.key.empty() && axis.key == so.series.key)
          return cli::usage_error("'" + axis.key +
                                  "' is both varied and the series: a knob can be only one");
      return cli::run_sweep(so);
    }
  }
  return kExitUsage;
}

}  // namespace

int main(int argc, char** argv) {
  // SIGINT/SIGTERM while an output is being written removes its temporary (§10:
  // nothing half-written is left, not even hidden).
  rt::remove_temporaries_on_signals();
  CLI::App app{"snell: a scene language and ray tracer", "snell"};
  app.require_subcommand(1);
  app.set_version_flag("--version", "snell 0.1.0");
  cli::CliArgs o;
  cli::add_commands(app, o);  // every subcommand and its options: cli/options.def

  // A first word that is no command is said as such: CLI11 reports "A subcommand
  // is required" for `snell rendr scene.scn`.
  bool command = argc <= 1 || argv[1][0] == '-';
  if (!command) try {
      command = app.get_subcommand(argv[1]) != nullptr;
    } catch (const CLI::OptionNotFound&) {
    }
  if (!command) {
    std::cerr << "snell: error: '" << argv[1] << "' is not a snell command (render, check, "
              << "sweep, dump-ast, farm, merge, lsp, watch)\n";
    if (std::string hint = cli::did_you_mean(app, std::vector<std::string>(argv + 1, argv + argc));
        !hint.empty())
      std::cerr << "snell: note: " << hint << "\n";
    return kExitUsage;
  }
  // CLI11's own failures ("--spp: Value 0 not in range ...") in Snell's form.
  app.failure_message([](const CLI::App*, const CLI::Error& e) {
    return "snell: error: " + std::string(e.what()) +
           "\nsnell: note: 'snell --help' and 'snell COMMAND --help' list the options\n";
  });
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    int code = app.exit(e);
    if (code != 0)
      if (std::string hint =
              cli::did_you_mean(app, std::vector<std::string>(argv + 1, argv + argc));
          !hint.empty())
        std::cerr << "snell: note: " << hint << "\n";
    return code == 0 ? kExitOk : kExitUsage;
  }
  // Last line of defence: nothing a user types may end in an abort. Memory the
  // machine does not have is reported (exit 1: the scene asks for it); anything
  // else escaping is a Snell bug, reported as such.
  try {
    int code = dispatch(cli::parsed_command(app), o);
    // What was printed on stdout (check's report, --dump-ir, dump-ast, watch's URL)
    // is output too (§10: 3 when it cannot be written): a full disk or a closed
    // pipe behind it lost it, with exit 0.
    std::cout.flush();
    if (!std::cout && code == kExitOk) {
      std::cerr << "snell: error: cannot write the standard output\n";
      return cli::kExitIo;
    }
    return code;
  } catch (const std::bad_alloc&) {
    std::cerr << "snell: error: out of memory (the scene needs more memory than this machine "
                 "has; lower the resolution, samples or geometry)\n";
    return kExitScene;
  } catch (const std::exception& e) {
    std::cerr << "snell: error: internal error: " << e.what() << "\n";
    return kExitScene;
  }
}
