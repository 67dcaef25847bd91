#include "cli/options.hpp"

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <type_traits>

namespace snell::cli {
namespace {

template <class T>
struct Real : std::is_floating_point<T> {};
template <class T>
struct Real<std::optional<T>> : std::is_floating_point<T> {};

// A number option takes finite values only: CLI11 reads "nan", "inf" and 1e400
// as doubles, and a NaN clock reached the scene as its own expression's error.
// Text that is no number at all is left to CLI11's conversion and its message.
const CLI::Validator kFinite(
    [](std::string& s) -> std::string {
      const double v = std::strtod(s.c_str(), nullptr);
      return std::isfinite(v) ? "" : "needs a finite number, not " + s;
    },
    "FINITE");

// An option's value is never empty: `--crop ""` (a script's unset variable) would
// otherwise read as no --crop at all and render the whole image.
const CLI::Validator kNonEmpty(
    [](std::string& s) -> std::string {
      return s.empty() ? "needs a value, not an empty one" : "";
    },
    "");

// One row bound to its field: a bool is a flag, anything else takes a value.
template <class T>
void bind(CLI::App& app, const OptionRow& row, Command cmd, T& field) {
  std::string names(row.names), help(row.help_for(cmd));
  const Rule& r = row.rule;
  CLI::Option* opt = nullptr;
  if constexpr (std::is_same_v<T, bool>) {
    // A callback, not a bool target, so that any value given to the flag
    // (--no-images=0 included) still clears it, as it always did.
    if (r.clears)
      opt = app.add_flag(
          names, [&field](std::int64_t) { field = false; }, help);
    else
      opt = app.add_flag(names, field, help);
  } else {
    opt = app.add_option(names, field, help);
    opt->check(kNonEmpty);
  }
  if (r.ranged) opt->check(CLI::Range(r.lo, r.hi));
  if constexpr (Real<T>::value) opt->check(kFinite);
  if (r.required) opt->required();
}

void add_options(CLI::App& app, Command cmd, CliArgs& args) {
  const OptionRow* row = kOptions;
  // Walks options.def again beside kOptions: the rows' fields have different
  // types, so only the macro can name each one.
#define SNELL_OPTION(field, names, commands, help, rule) \
  if (row->in(cmd)) bind(app, *row, cmd, args.field);    \
  ++row;
#include "cli/options.def"
}

}  // namespace

void add_commands(CLI::App& app, CliArgs& args) {
  for (const CommandInfo& c : kCommands)
    add_options(*app.add_subcommand(std::string(c.name), std::string(c.description)), c.id, args);
}

unsigned parsed_command(CLI::App& app) {
  for (const CommandInfo& c : kCommands)
    if (app.get_subcommand(std::string(c.name))->parsed()) return c.id;
  return 0;
}

}  // namespace snell::cli
