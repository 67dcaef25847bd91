#include "cli/options.hpp"

#include <CLI/CLI.hpp>
#include <cctype>
#include <cmath>
#include <cstdlib>
#include <optional>
#include <string>
#include <type_traits>
#include <vector>

#include "language/diagnostics.hpp"

namespace snell::cli {
namespace {

template <class T>
struct Real : std::is_floating_point<T> {};
template <class T>
struct Real<std::optional<T>> : std::is_floating_point<T> {};
template <class T>
struct Integral : std::is_integral<T> {};
template <class T>
struct Integral<std::optional<T>> : std::is_integral<T> {};
template <class T>
struct Repeatable : std::false_type {};
template <class T>
struct Repeatable<std::vector<T>> : std::true_type {};

// An integer option is decimal, as every number of §2 is: CLI11 reads "010" as
// octal 8 and "0x10" as 16, so `--frame 0042` rendered frame 34 and `--seed 010`
// differed from `--set seed=010`. Leading zeros are taken off before CLI11 reads it.
const CLI::Validator kDecimal(
    [](std::string& s) -> std::string {
      std::size_t i = s.empty() || (s[0] != '-' && s[0] != '+') ? 0 : 1;
      if (i == s.size() || s.find_first_not_of("0123456789", i) != std::string::npos)
        return "needs a whole number in decimal, not " + s;
      std::size_t z = s.find_first_not_of('0', i);
      s.erase(i, (z == std::string::npos ? s.size() - 1 : z) - i);
      return "";
    },
    "");

// A number option takes finite values only: CLI11 reads "nan", "inf" and 1e400
// as doubles, and a NaN clock reached the scene as its own expression's error.
// Text that is no number at all is said in the words of the other options (CLI11's
// own was "Could not convert: --clock = abc").
const CLI::Validator kFinite(
    [](std::string& s) -> std::string {
      char* end = nullptr;
      const double v = std::strtod(s.c_str(), &end);
      if (end == s.c_str() || *end != '\0') return "needs a number, not " + s;
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
    if constexpr (Integral<T>::value) opt->transform(kDecimal);
    // `-o a.png scene.scn --spp 4`: one value per occurrence, so a repeatable
    // option does not take the scene (or a second output) as its own.
    if constexpr (Repeatable<T>::value)
      if (names[0] == '-') opt->allow_extra_args(false);
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

namespace snell::cli {

std::string did_you_mean(CLI::App& app, const std::vector<std::string>& args) {
  CLI::App* sub = nullptr;
  for (const std::string& a : args) {
    if (a == "--") break;
    if (!sub) {
      if (a.empty() || a[0] == '-') continue;
      for (const CommandInfo& c : kCommands)
        if (a == c.name) sub = app.get_subcommand(std::string(c.name));
      if (sub) continue;
      std::vector<std::string_view> names;
      for (const CommandInfo& c : kCommands) names.emplace_back(c.name);
      std::string guess = lang::closest_match(a, names);
      return guess.empty() ? "" : "did you mean 'snell " + guess + "'?";
    }
    if (a.size() < 2 || a[0] != '-') continue;
    // A negative number is a value (`--seed -1`), not a misspelt `-h`.
    if (std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.') continue;
    const std::string word = a.substr(0, a.find('='));
    std::vector<std::string> spelt;
    bool known = false;
    for (const CLI::Option* opt : sub->get_options()) {
      for (const std::string& l : opt->get_lnames()) spelt.push_back("--" + l);
      for (const std::string& n : opt->get_snames()) spelt.push_back("-" + n);
    }
    for (const std::string& n : spelt) known = known || n == word;
    if (known) continue;
    // Another command's option (`snell watch -o x.png`): say whose it is.
    for (const CommandInfo& c : kCommands) {
      CLI::App* other = app.get_subcommand(std::string(c.name));
      if (other == sub) continue;
      for (const CLI::Option* opt : other->get_options())
        if (opt->check_name(word))
          return "'" + word + "' is an option of 'snell " + std::string(c.name) +
                 "', not of 'snell " + sub->get_name() + "'";
    }
    // One letter is one edit from every other (`-o` is not a misspelt `-h`).
    if (word.size() <= 2) continue;
    std::vector<std::string_view> names(spelt.begin(), spelt.end());
    std::string guess = lang::closest_match(word, names);
    if (!guess.empty()) return "did you mean '" + guess + "'?";
    // The start of one option's name (`--sample` of `--sample-range`): too far for
    // an edit distance, plainly meant.
    std::string only;
    int starts = 0;
    if (word.size() >= 5)
      for (const std::string& n : spelt)
        if (n.size() > word.size() && n.compare(0, word.size(), word) == 0) only = n, ++starts;
    if (starts == 1) return "did you mean '" + only + "'?";
  }
  return "";
}

}  // namespace snell::cli
