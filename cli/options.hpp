// The command line's options, from one table (cli/options.def): every subcommand
// takes its rows from it, so an option shared by several subcommands (-I, --set,
// --res, ...) is spelt, explained and checked in one place. The table is plain
// constexpr data, so tests read it without CLI11; add_commands binds it to CLI11.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "cli/sweep.hpp"
#include "compiler/compile.hpp"
#include "runtime/image_format.hpp"  // rt::DisplayView

namespace CLI {
class App;
}

namespace snell::cli {

// A bit each, so a row can name several.
enum Command : unsigned {
  Render = 1,
  Check = 2,
  Sweep = 4,
  DumpAst = 8,
  Merge = 16,
  Farm = 32,
  Lsp = 64,
  Watch = 128
};

struct CommandInfo {
  Command id;
  std::string_view name;
  std::string_view description;
};

// In the order `snell --help` lists them.
inline constexpr CommandInfo kCommands[] = {
    {Render, "render", "render a scene to images"},
    {Check, "check", "report diagnostics and the effects a scene uses"},
    {Sweep, "sweep",
     "render a scene across settings: time and error against a converged reference"},
    {DumpAst, "dump-ast", "print the syntax tree of a .scn file"},
    {Farm, "farm",
     "split a render over a batch system (slurm): an array job of pieces and a merge job"},
    {Merge, "merge",
     "assemble the pieces of a split render (--crop, --sample-range) into one image"},
    {Lsp, "lsp", "serve the Language Server Protocol on stdin/stdout (for editors)"},
    {Watch, "watch",
     "re-render a scene whenever it or a file it reads changes, progressively, shown on a page "
     "served on localhost (and in tev)"},
};

// What CLI11 checks beyond the value's type.
struct Rule {
  bool required = false;
  bool ranged = false;
  // Checked as 64-bit integers: CLI11's message and --help text for a range are
  // the same for every integer type, and every bound here fits.
  long long lo = 0, hi = 0;
  bool clears = false;  // a flag that sets its bool field to false (--no-images)
  unsigned alt_commands = 0;
  std::string_view alt_help;

  constexpr Rule help_in(unsigned commands, std::string_view help) const {
    Rule r = *this;
    r.alt_commands = commands;
    r.alt_help = help;
    return r;
  }
};

namespace rule {
constexpr Rule none() {
  return {};
}
constexpr Rule required() {
  Rule r;
  r.required = true;
  return r;
}
constexpr Rule range(long long lo, long long hi) {
  Rule r;
  r.ranged = true;
  r.lo = lo;
  r.hi = hi;
  return r;
}
constexpr Rule clears() {
  Rule r;
  r.clears = true;
  return r;
}
}  // namespace rule

struct OptionRow {
  std::string_view field;  // the CliArgs member, as options.def writes it
  std::string_view names;  // CLI11's spelling, comma-separated
  unsigned commands;
  std::string_view help;
  Rule rule;

  constexpr bool in(Command c) const { return (commands & c) != 0; }
  constexpr std::string_view help_for(Command c) const {
    return (rule.alt_commands & c) ? rule.alt_help : help;
  }
};

inline constexpr OptionRow kOptions[] = {
#define SNELL_OPTION(field, names, commands, help, rule) {#field, names, commands, help, rule},
#include "cli/options.def"
};

// Everything the command line can say, whichever subcommand says it. Defaults
// here are the options' defaults.
struct CliArgs {
  std::string scene;
  // Compiling (render, check, sweep).
  std::vector<std::string> include_dirs;
  std::vector<std::string> sets;
  std::size_t max_errors = 0;  // 0: all (§10: all independent errors)
  std::uint64_t max_steps = compile::kDefaultStepBudget;
  // Rendering (render, sweep).
  std::string res;
  int threads = 0;
  bool quiet = false;
  // render only.
  std::vector<std::string> outputs;
  std::optional<int> spp;
  std::optional<std::int64_t> seed;
  bool stats = false;
  bool dump_ast = false;
  bool dump_ir = false;
  std::string pixel;
  std::string features = "auto";
  std::string ocio_config;
  std::string max_memory;  // "8G"; empty: 90 % of the machine's memory
  std::string display;     // OCIO display and view of display-referred outputs
  std::string view;
  rt::DisplayView display_view() const { return {ocio_config, display, view}; }
  // §18 animation and split renders (render; cli/animation.hpp, cli/split.hpp).
  std::string frames;                 // "A..B"
  std::optional<std::int64_t> frame;  // --frame F: one frame of --frames
  std::optional<double> clock;        // --clock X
  std::string crop;                   // "X0,Y0,X1,Y1"
  std::string sample_range;           // "A..B"
  // farm only (cli/farm.hpp).
  std::string farm_backend;
  std::optional<int> farm_tiles, farm_passes;
  std::string farm_dir;
  bool farm_dry_run = false;
  std::vector<std::string> farm_sbatch;
  // watch only (cli/watch.hpp).
  int watch_port = 8787;
  std::string display_server;  // HOST:PORT of tev
  // merge only.
  std::string merge_out;
  std::vector<std::string> pieces;
  // sweep only: --vary and --series are parsed after CLI11 (their errors are
  // ours); the rest land in `sweep` directly. Its scene, threads, quiet and
  // compile options are filled from the fields above when the sweep runs.
  std::vector<std::string> vary;
  std::string series;
  SweepOptions sweep;
};

// Adds every subcommand of kCommands to `app`, each with its rows of kOptions
// bound to `args`.
void add_commands(CLI::App& app, CliArgs& args);
// The subcommand `app` parsed (after app.parse), or 0 for none.
unsigned parsed_command(CLI::App& app);
// After a parse error: "did you mean '--output'?" for the first word of `args`
// that is no option of its subcommand (or no subcommand) but close to one; empty
// when there is none.
std::string did_you_mean(CLI::App& app, const std::vector<std::string>& args);

}  // namespace snell::cli
