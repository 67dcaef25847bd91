// The command line's option table (cli/options.def): which subcommand takes which
// options, and that each lands in its field with its old default and checks. The
// expected lists below are what each subcommand accepted when its options were
// still declared one by one in cli/main.cpp; a new option is added to them on
// purpose, never by accident.
#include <CLI/CLI.hpp>
#include <catch2/catch.hpp>
#include <map>
#include <set>
#include <string>

#include "cli/options.hpp"

using namespace snell;

namespace {

// A command line as snell builds it, parsed into its own CliArgs.
struct Line {
  cli::CliArgs args;
  CLI::App app{"snell", "snell"};
  Line() {
    app.require_subcommand(1);
    cli::add_commands(app, args);
  }
  unsigned parse(const std::string& line) {
    app.parse(line, false);
    return cli::parsed_command(app);
  }
};

// Every option a subcommand accepts, spelt as CLI11 lists it ("-q,--quiet"; a
// positional by its name), without the -h,--help every subcommand has.
std::set<std::string> accepted(CLI::App& sub) {
  std::set<std::string> out;
  for (const CLI::Option* opt : sub.get_options())
    if (opt != sub.get_help_ptr()) out.insert(opt->get_name(true, true));
  return out;
}

std::vector<std::string> split_names(std::string_view names) {
  std::vector<std::string> out;
  std::size_t b = 0;
  while (b <= names.size()) {
    std::size_t e = names.find(',', b);
    if (e == std::string_view::npos) e = names.size();
    out.emplace_back(names.substr(b, e - b));
    b = e + 1;
  }
  return out;
}

}  // namespace

TEST_CASE("the option table names each option once", "[cli][options]") {
  std::set<std::string> names, fields;
  unsigned all = 0;
  for (const cli::CommandInfo& c : cli::kCommands) all |= c.id;
  for (const cli::OptionRow& row : cli::kOptions) {
    INFO("row " << row.field << " (" << row.names << ")");
    CHECK(fields.insert(std::string(row.field)).second);
    for (const std::string& n : split_names(row.names)) {
      INFO("name '" << n << "'");
      CHECK(!n.empty());
      CHECK(names.insert(n).second);
    }
    CHECK(!row.help.empty());
    CHECK(row.commands != 0);
    CHECK((row.commands & ~all) == 0);
    // Other help only for subcommands that take the option at all.
    CHECK((row.rule.alt_commands & ~row.commands) == 0);
    CHECK(row.rule.alt_help.empty() == (row.rule.alt_commands == 0));
    if (row.rule.ranged) CHECK(row.rule.lo <= row.rule.hi);
  }
  CHECK(names.count("-h") == 0);  // CLI11's own
  CHECK(names.count("--help") == 0);
}

TEST_CASE("each subcommand takes exactly the options it took before the table", "[cli][options]") {
  const std::map<std::string, std::set<std::string>> expected = {
      {"render",
       {"scene", "-o,--output", "--spp", "--res", "--threads", "--seed", "--set", "-I", "--stats",
        "-q,--quiet", "--max-errors", "--max-steps", "--dump-ast", "--dump-ir", "--pixel",
        "--features", "--ocio-config",
        // §18, added with animation and split renders.
        "--frames", "--frame", "--clock", "--crop", "--sample-range",
        // #18: any studio OCIO config's display and view; the memory limit.
        "--display", "--view", "--max-memory"}},
      {"check", {"scene", "-I", "--set", "--max-errors", "--max-steps"}},
      {"sweep",
       {"scene", "--vary", "--series", "--repeats", "--reference-spp", "--out", "--markdown",
        "--name", "--res", "--set", "-I", "--threads", "--no-images", "-q,--quiet"}},
      {"dump-ast", {"scene"}},
      {"lsp", {"-I", "--max-steps"}},
      // §18: added with split renders.
      {"merge", {"out", "pieces", "-q,--quiet", "--ocio-config", "--display", "--view"}},
      // §18: the farm forwards render options to its tasks.
      {"farm",
       {"backend",       "scene",     "--tiles",     "--passes",    "--frames",    "--dir",
        "--sbatch",      "--dry-run", "-o,--output", "--spp",       "--res",       "--threads",
        "--seed",        "--set",     "-I",          "--clock",     "--max-steps", "--features",
        "--ocio-config", "--display", "--view",      "--max-memory"}},
      // #20: watch re-renders with the render options that make sense live (no
      // outputs, frames, crops or sample ranges: it renders every sample itself).
      {"watch",
       {"scene", "--port", "--display-server", "--spp", "--res", "--threads", "--seed", "--set",
        "-I", "--stats", "--clock", "-q,--quiet", "--max-errors", "--max-steps", "--features",
        "--ocio-config", "--display", "--view"}},
  };
  Line line;
  std::set<std::string> subcommands;
  for (const CLI::App* sub : line.app.get_subcommands({})) subcommands.insert(sub->get_name());
  CHECK(subcommands == std::set<std::string>{"render", "check", "sweep", "dump-ast", "merge",
                                             "farm", "lsp", "watch"});
  for (const auto& [name, options] : expected) {
    INFO("snell " << name);
    CLI::App* sub = line.app.get_subcommand(name);
    CHECK(accepted(*sub) == options);
    // The scene is required everywhere, --vary by the sweep, merge's output and
    // pieces, the farm's backend and --dir; nothing else is.
    for (const CLI::Option* opt : sub->get_options()) {
      std::string n = opt->get_name(true, true);
      INFO(n);
      CHECK(opt->get_required() == (n == "scene" || n == "--vary" || n == "out" || n == "pieces" ||
                                    n == "backend" || n == "--dir"));
    }
  }
  // The options whose help differs by subcommand.
  CHECK(line.app.get_subcommand("lsp")->get_option("--max-steps")->get_description() ==
        "evaluation step budget per analysis (default 5000000)");
  CHECK(line.app.get_subcommand("render")->get_option("--res")->get_description() ==
        "resolution WIDTHxHEIGHT (overrides settings.resolution)");
  CHECK(line.app.get_subcommand("sweep")->get_option("--res")->get_description() ==
        "resolution WIDTHxHEIGHT for every render");
}

TEST_CASE("options keep their defaults when not given", "[cli][options]") {
  Line line;
  REQUIRE(line.parse("render a.scn") == cli::Render);
  const cli::CliArgs& a = line.args;
  CHECK(a.scene == "a.scn");
  CHECK(a.outputs.empty());
  CHECK(!a.spp);
  CHECK(!a.seed);
  CHECK(a.res.empty());
  CHECK(a.threads == 0);
  CHECK(a.max_errors == 0);  // all errors, as §10 asks
  CHECK(a.max_steps == compile::kDefaultStepBudget);
  CHECK(a.features == "auto");
  CHECK(!a.quiet);
  CHECK(!a.stats);
  CHECK(!a.dump_ast);
  CHECK(!a.dump_ir);
  CHECK(a.sweep.repeats == 3);
  CHECK(a.sweep.reference_spp == 1024);
  CHECK(a.sweep.out_dir == "sweep");
  CHECK(a.sweep.images);
}

TEST_CASE("options land in the fields the table names", "[cli][options]") {
  {
    Line line;
    REQUIRE(line.parse("render a.scn -o x.exr --output y.png --spp 7 --res 4x3 --threads 2 "
                       "--seed 4294967295 --set samples=2 --set seed=1 -I d1 -I d2 --stats -q "
                       "--max-errors 0 --max-steps 99 --dump-ast --dump-ir --pixel 1,2 "
                       "--features all --ocio-config c.ocio") == cli::Render);
    const cli::CliArgs& a = line.args;
    CHECK(a.outputs == std::vector<std::string>{"x.exr", "y.png"});
    CHECK(a.spp == 7);
    CHECK(a.res == "4x3");
    CHECK(a.threads == 2);
    CHECK(a.seed == 4294967295LL);
    CHECK(a.sets == std::vector<std::string>{"samples=2", "seed=1"});
    CHECK(a.include_dirs == std::vector<std::string>{"d1", "d2"});
    CHECK(a.stats);
    CHECK(a.quiet);
    CHECK(a.max_errors == 0);
    CHECK(a.max_steps == 99);
    CHECK(a.dump_ast);
    CHECK(a.dump_ir);
    CHECK(a.pixel == "1,2");
    CHECK(a.features == "all");
    CHECK(a.ocio_config == "c.ocio");
  }
  {
    Line line;
    REQUIRE(line.parse("sweep s.scn --vary samples=1,2 --vary max_depth=1 --series fresnel=exact "
                       "--repeats 5 --reference-spp 64 --out o --markdown m.md --name n "
                       "--res 8x8 --set seed=3 -I inc --threads 1 --no-images --quiet") ==
            cli::Sweep);
    const cli::CliArgs& a = line.args;
    CHECK(a.scene == "s.scn");
    CHECK(a.vary == std::vector<std::string>{"samples=1,2", "max_depth=1"});
    CHECK(a.series == "fresnel=exact");
    CHECK(a.sweep.repeats == 5);
    CHECK(a.sweep.reference_spp == 64);
    CHECK(a.sweep.out_dir == "o");
    CHECK(a.sweep.markdown == "m.md");
    CHECK(a.sweep.name == "n");
    CHECK(a.res == "8x8");
    CHECK(a.sets == std::vector<std::string>{"seed=3"});
    CHECK(a.include_dirs == std::vector<std::string>{"inc"});
    CHECK(a.threads == 1);
    CHECK(!a.sweep.images);
    CHECK(a.quiet);
  }
  {
    Line line;
    REQUIRE(line.parse("check c.scn -I i --set samples=4 --max-errors 3 --max-steps 10") ==
            cli::Check);
    CHECK(line.args.max_errors == 3);
    CHECK(line.args.max_steps == 10);
  }
  {
    Line line;
    REQUIRE(line.parse("render a.scn --frames 0..24 --frame 3 --clock 0.5 --crop 1,2,3,4 "
                       "--sample-range 0..8") == cli::Render);
    CHECK(line.args.frames == "0..24");
    CHECK(line.args.frame == 3);
    CHECK(line.args.clock == 0.5);
    CHECK(line.args.crop == "1,2,3,4");
    CHECK(line.args.sample_range == "0..8");
  }
  {
    Line line;
    REQUIRE(line.parse("merge out.exr a.exr b.exr -q --ocio-config c.ocio") == cli::Merge);
    CHECK(line.args.merge_out == "out.exr");
    CHECK(line.args.pieces == std::vector<std::string>{"a.exr", "b.exr"});
    CHECK(line.args.quiet);
    CHECK(line.args.ocio_config == "c.ocio");
  }
  {
    Line line;
    REQUIRE(line.parse("dump-ast d.scn") == cli::DumpAst);
    CHECK(line.args.scene == "d.scn");
  }
  {
    Line line;
    REQUIRE(line.parse("lsp -I inc --max-steps 1000") == cli::Lsp);
    CHECK(line.args.include_dirs == std::vector<std::string>{"inc"});
    CHECK(line.args.max_steps == 1000);
  }
  {
    Line line;
    REQUIRE(line.parse("watch w.scn") == cli::Watch);
    CHECK(line.args.watch_port == 8787);
    CHECK(line.args.display_server.empty());
  }
  {
    Line line;
    REQUIRE(line.parse("watch w.scn --port 0 --display-server 127.0.0.1:14158 --spp 64 "
                       "--res 8x4 --stats -q") == cli::Watch);
    const cli::CliArgs& a = line.args;
    CHECK(a.scene == "w.scn");
    CHECK(a.watch_port == 0);
    CHECK(a.display_server == "127.0.0.1:14158");
    CHECK(a.spp == 64);
    CHECK(a.res == "8x4");
    CHECK(a.stats);
    CHECK(a.quiet);
  }
}

TEST_CASE("option values are checked as before the table", "[cli][options]") {
  // Each of these is a CLI11 parse error, which snell turns into exit status 2.
  auto rejects = [](const std::string& command_line) {
    Line line;
    INFO(command_line);
    CHECK_THROWS_AS(line.parse(command_line), CLI::ParseError);
  };
  rejects("render");                                // the scene is required
  rejects("render a.scn b.scn");                    // one scene
  rejects("render a.scn --spp 0");                  // 1 ..= 2^20
  rejects("render a.scn --spp 1048577");            //
  rejects("render a.scn --threads 1025");           // 0 ..= 1024
  rejects("render a.scn --threads -1");             //
  rejects("render a.scn --seed -1");                // 0 ..= 2^32 - 1
  rejects("render a.scn --seed 4294967296");        //
  rejects("render a.scn --max-errors x");           // a number
  rejects("sweep s.scn");                           // --vary is required
  rejects("sweep s.scn --vary a=1 --repeats 0");    // 1 ..= 100
  rejects("sweep s.scn --vary a=1 --repeats 101");  //
  rejects("sweep s.scn --vary a=1 --reference-spp 0");
  rejects("sweep s.scn --vary a=1 --threads 2000");
  // Options of other subcommands are not accepted.
  rejects("check c.scn --spp 4");
  rejects("check c.scn --res 4x4");
  rejects("check c.scn --threads 2");
  rejects("sweep s.scn --vary a=1 --spp 3");
  rejects("dump-ast d.scn -I .");
  rejects("render a.scn --vary a=1");
  rejects("watch w.scn --port 65536");  // 0 ..= 65535
  rejects("watch w.scn --port -1");
  rejects("watch w.scn -o x.png");  // watch writes no images
  rejects("render a.scn --port 8787");
  // And the bounds themselves are accepted.
  Line line;
  CHECK_NOTHROW(line.parse("render a.scn --spp 1048576 --threads 1024 --seed 0"));
}

TEST_CASE("an empty option value is a usage error, not the option left out", "[cli][options]") {
  // A script's `--crop "$C"` with C unset rendered the whole image and exited 0.
  // Every option that takes a value, in every subcommand that takes it.
  std::size_t tried = 0;
  for (const cli::CommandInfo& c : cli::kCommands) {
    Line probe;
    CLI::App* sub = probe.app.get_subcommand(std::string(c.name));
    for (const CLI::Option* opt : sub->get_options()) {
      if (opt == sub->get_help_ptr() || opt->get_items_expected_min() == 0) continue;
      // argv after the program's name: the subcommand, its required options and
      // positionals with some value, then this option with an empty one.
      std::vector<std::string> argv = {std::string(c.name)};
      for (const CLI::Option* req : sub->get_options())
        if (req != opt && req->get_required()) {
          if (!req->get_positional()) argv.push_back(req->get_name(false, false));
          argv.push_back("x=1");
        }
      if (!opt->get_positional()) argv.push_back(opt->get_name(false, false));
      argv.push_back("");
      Line line;
      INFO(c.name << " " << opt->get_name());
      CHECK_THROWS_AS(line.app.parse(std::vector<std::string>(argv.rbegin(), argv.rend())),
                      CLI::ValidationError);
      ++tried;
    }
  }
  CHECK(tried > 40);
}

TEST_CASE("integer options are decimal, leading zeros and all", "[cli][options]") {
  // CLI11 read "010" as octal 8 and "0x10" as 16: --frame 0042 rendered frame 34.
  Line line;
  line.parse("render a.scn --spp 010 --seed 0042 --threads 0002 --max-errors 010");
  CHECK(line.args.spp == 10u);
  CHECK(line.args.seed == 42u);
  CHECK(line.args.threads == 2);
  CHECK(line.args.max_errors == 10u);
  Line zero;
  zero.parse("render a.scn --seed 000");
  CHECK(zero.args.seed == 0u);
  for (const char* bad : {"render a.scn --spp 0x10", "render a.scn --seed 1e3",
                          "render a.scn --spp 4.0", "render a.scn --seed 0b11"}) {
    Line l;
    INFO(bad);
    CHECK_THROWS_AS(l.parse(bad), CLI::ParseError);
  }
}

TEST_CASE("a repeatable option takes one value each time, never the scene", "[cli][options]") {
  // -o, -I and --set took every word up to the next option: `-o out.png a.scn
  // --spp 4` made a.scn a second output and said the scene was missing.
  Line line;
  line.parse("render -o out.png a.scn --spp 4 -I inc --set seed=3 -o b.exr");
  CHECK(line.args.scene == "a.scn");
  CHECK(line.args.outputs == std::vector<std::string>{"out.png", "b.exr"});
  CHECK(line.args.include_dirs == std::vector<std::string>{"inc"});
  CHECK(line.args.sets == std::vector<std::string>{"seed=3"});
  Line l2;
  l2.parse("check -I inc c.scn --max-errors 5");
  CHECK(l2.args.scene == "c.scn");
}

TEST_CASE("a misspelt option or subcommand gets a did-you-mean note", "[cli][options]") {
  Line line;
  CHECK_THROWS_AS(line.parse("render w.scn --outptu x.png"), CLI::ParseError);
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "--outptu", "x.png"}) ==
        "did you mean '--output'?");
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "--stat"}) == "did you mean '--stats'?");
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "--spp=4", "--sed", "3"}) ==
        "did you mean '--seed'?");
  CHECK(cli::did_you_mean(line.app, {"rendr", "w.scn"}) == "did you mean 'snell render'?");
  // The start of one option's name, too far for an edit distance.
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "--sample", "2"}) ==
        "did you mean '--sample-range'?");
  // A negative value is no option: `-1` is not a misspelt `-h`.
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "--seed", "-1"}).empty());
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "--seed", "-.5"}).empty());
  // Known options and words nothing is close to: no note.
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "--spp", "4"}).empty());
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "--xyzzyplugh"}).empty());
  // Another command's option is said to be that command's; one letter is no slip.
  CHECK(cli::did_you_mean(line.app, {"watch", "w.scn", "-o", "x.png"}) ==
        "'-o' is an option of 'snell render', not of 'snell watch'");
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "--port", "3"}) ==
        "'--port' is an option of 'snell watch', not of 'snell render'");
  CHECK(cli::did_you_mean(line.app, {"render", "w.scn", "-z"}).empty());
}
