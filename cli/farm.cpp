#include "cli/farm.hpp"

#include <fmt/format.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>

#include "cli/animation.hpp"
#include "cli/commands.hpp"
#include "cli/split.hpp"
#include "runtime/color.hpp"
#include "runtime/image_format.hpp"

namespace snell::cli {

namespace {
namespace fs = std::filesystem;

std::string absolute(const std::string& p) {
  std::error_code ec;
  fs::path a = fs::absolute(p, ec);
  return (ec ? fs::path(p) : a).lexically_normal().string();
}

// Relative output names land in the shared folder.
std::string in_dir(const std::string& dir, const std::string& name) {
  return fs::path(name).is_absolute() ? name : (fs::path(dir) / name).lexically_normal().string();
}

std::string join_quoted(const std::vector<std::string>& args) {
  std::string s;
  for (const std::string& a : args) s += (s.empty() ? "" : " ") + shell_quote(a);
  return s;
}

}  // namespace

std::string shell_quote(const std::string& s) {
  std::string out = "'";
  for (char c : s) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return out + "'";
}

bool plan_farm(const CliArgs& o, const std::string& snell_exe, std::uint32_t width,
               std::uint32_t height, std::uint32_t spp, FarmPlan& plan, std::string& error) {
  if (o.farm_backend != "slurm") {
    error = "farm: unknown batch system '" + o.farm_backend + "' (Snell submits to: slurm)";
    return false;
  }
  int ways =
      int(o.farm_tiles.has_value()) + int(o.farm_passes.has_value()) + int(!o.frames.empty());
  if (ways != 1) {
    error = "farm: give exactly one of --tiles N, --passes N and --frames A..B";
    return false;
  }
  if (!o.frames.empty() && o.clock) {
    error = "farm: --clock is for one frame; with --frames each frame has its own clock";
    return false;
  }
  FarmPlan p;
  p.snell = snell_exe;
  p.dir = absolute(o.farm_dir);
  p.name = "snell-" + fs::path(o.scene).stem().string();
  p.sbatch = o.farm_sbatch;
  // The render options every task repeats; paths made absolute, for nodes that
  // start elsewhere.
  std::vector<std::string>& r = p.render_args;
  r = {"render", absolute(o.scene)};
  for (const std::string& d : o.include_dirs) r.insert(r.end(), {"-I", absolute(d)});
  for (const std::string& s : o.sets) r.insert(r.end(), {"--set", s});
  if (o.spp) r.insert(r.end(), {"--spp", std::to_string(*o.spp)});
  if (!o.res.empty()) r.insert(r.end(), {"--res", o.res});
  if (o.seed) r.insert(r.end(), {"--seed", std::to_string(*o.seed)});
  if (o.threads) r.insert(r.end(), {"--threads", std::to_string(o.threads)});
  if (o.clock) r.insert(r.end(), {"--clock", fmt::format("{}", *o.clock)});
  if (o.features != "auto") r.insert(r.end(), {"--features", o.features});
  r.insert(r.end(), {"--max-steps", std::to_string(o.max_steps)});
  if (!o.ocio_config.empty()) r.insert(r.end(), {"--ocio-config", absolute(o.ocio_config)});
  if (!o.display.empty()) r.insert(r.end(), {"--display", o.display});
  if (!o.max_memory.empty()) r.insert(r.end(), {"--max-memory", o.max_memory});
  if (!o.view.empty()) r.insert(r.end(), {"--view", o.view});

  std::vector<std::string> outputs;
  for (const std::string& out : o.outputs) outputs.push_back(in_dir(p.dir, out));
  if (outputs.empty()) outputs.push_back(in_dir(p.dir, fs::path(o.scene).stem().string() + ".png"));
  for (const std::string& out : outputs)
    if (!rt::is_supported_image_extension(out)) {
      error = "cannot tell the image format of '" + out +
              "': use .exr, .png, .jpg, .jpeg, .tif or .tiff";
      return false;
    }

  if (!o.frames.empty()) {
    IntRange frames;
    if (!parse_range(o.frames, "--frames", std::numeric_limits<std::int32_t>::max(), frames, error))
      return false;
    for (std::int64_t f = frames.begin; f < frames.end; ++f) {
      FarmTask t;
      t.args = {"--frames", o.frames, "--frame", std::to_string(f)};
      for (const std::string& out : outputs) {
        t.args.insert(t.args.end(), {"-o", out});
        t.outputs.push_back(frame_output_name(out, f));
      }
      p.tasks.push_back(t);
    }
    for (const FarmTask& t : p.tasks)
      p.results.insert(p.results.end(), t.outputs.begin(), t.outputs.end());
  } else {
    std::int64_t n = o.farm_tiles ? *o.farm_tiles : *o.farm_passes;
    std::int64_t total = o.farm_tiles ? height : spp;
    if (n > total) {
      error =
          o.farm_tiles
              ? fmt::format("farm: --tiles {}: the image has only {} rows", n, height)
              : fmt::format("farm: --passes {}: the scene has only {} samples per pixel", n, spp);
      return false;
    }
    std::vector<std::string> pieces;
    for (std::int64_t i = 0; i < n; ++i) {
      // Even shares; the first (total mod n) get one more.
      std::int64_t a = i * total / n, b = (i + 1) * total / n;
      FarmTask t;
      std::string piece = fmt::format("{}/pieces/piece_{:04}.exr", p.dir, i);
      if (o.farm_tiles)
        t.args = {"--crop", to_string(Window{0, std::uint32_t(a), width, std::uint32_t(b)})};
      else
        t.args = {"--sample-range", to_string(IntRange{a, b})};
      t.args.insert(t.args.end(), {"-o", piece});
      t.outputs.push_back(piece);
      pieces.push_back(piece);
      p.tasks.push_back(t);
    }
    for (const std::string& out : outputs) {
      std::vector<std::string> m = {p.snell, "merge", out};
      if (!o.ocio_config.empty()) m.insert(m.end(), {"--ocio-config", absolute(o.ocio_config)});
      if (!o.display.empty()) m.insert(m.end(), {"--display", o.display});
      if (!o.view.empty()) m.insert(m.end(), {"--view", o.view});
      m.insert(m.end(), pieces.begin(), pieces.end());
      p.merges.push_back(m);
      p.results.push_back(out);
    }
  }
  plan = std::move(p);
  return true;
}

std::string array_script(const FarmPlan& p) {
  std::string s = "#!/bin/bash\n";
  s += fmt::format("# Written by snell farm slurm: array task i renders piece i of {} tasks.\n",
                   p.tasks.size());
  s += fmt::format("#SBATCH --job-name={}\n", p.name);
  s += fmt::format("#SBATCH --array=0-{}\n", p.tasks.size() - 1);
  s += fmt::format("#SBATCH --output={}/logs/task_%a.out\n", p.dir);
  s += "set -eu\n";
  s += "case \"${SLURM_ARRAY_TASK_ID:?not run as a Slurm array task}\" in\n";
  for (std::size_t i = 0; i < p.tasks.size(); ++i)
    s += fmt::format("  {}) set -- {} ;;\n", i, join_quoted(p.tasks[i].args));
  s += "  *) echo \"snell farm: no task $SLURM_ARRAY_TASK_ID\" >&2; exit 2 ;;\n";
  s += "esac\n";
  // The folders its outputs go to, made here too: the script also runs outside
  // Slurm unchanged (docs/distributed.md: a Kubernetes indexed job), where no
  // submission made them.
  std::vector<std::string> dirs;
  for (const FarmTask& t : p.tasks)
    for (const std::string& out : t.outputs) {
      std::string d = fs::path(out).parent_path().string();
      if (!d.empty() && std::find(dirs.begin(), dirs.end(), d) == dirs.end()) dirs.push_back(d);
    }
  if (!dirs.empty()) s += "mkdir -p " + join_quoted(dirs) + "\n";
  s += fmt::format("exec {} {} \"$@\"\n", shell_quote(p.snell), join_quoted(p.render_args));
  return s;
}

std::string merge_script(const FarmPlan& p) {
  std::string s = "#!/bin/bash\n";
  s += "# Written by snell farm slurm: runs after every array task has ended (afterany),\n";
  s += "# checks that each left its output, then merges the pieces.\n";
  s += fmt::format("#SBATCH --job-name={}-merge\n", p.name);
  s += fmt::format("#SBATCH --output={}/logs/merge.out\n", p.dir);
  s += "set -u\n";
  s += "failed=0\n";
  s += "check() {\n";
  s += "  if [ ! -s \"$2\" ]; then\n";
  // Paths go in single-quoted between the double-quoted text: a folder named
  // 'x$(cmd)' is printed, never run.
  s += fmt::format(
      "    echo \"snell farm: task $1 failed: it wrote no $2 (see \"{}\"/logs/task_$1.out; re-run "
      "it with: sbatch --array=$1 \"{}\", then sbatch \"{}\")\" >&2\n",
      shell_quote(p.dir), shell_quote(p.array_script_path()), shell_quote(p.merge_script_path()));
  s += "    failed=1\n";
  s += "  fi\n";
  s += "}\n";
  for (std::size_t i = 0; i < p.tasks.size(); ++i)
    for (const std::string& out : p.tasks[i].outputs)
      s += fmt::format("check {} {}\n", i, shell_quote(out));
  s += "[ \"$failed\" = 0 ] || exit 1\n";
  for (const std::vector<std::string>& m : p.merges) s += join_quoted(m) + " || exit 1\n";
  s += fmt::format("echo \"snell farm: done: \"{}\n",
                   shell_quote(p.results.size() == 1 ? p.results[0]
                                                     : fmt::format("{} images", p.results.size())));
  return s;
}

namespace {

std::string self_exe() {
  std::error_code ec;
  fs::path exe = fs::read_symlink("/proc/self/exe", ec);
  return ec ? "snell" : exe.string();
}

// Runs `command`, returns its stdout (trimmed) and exit status.
int capture(const std::string& command, std::string& out) {
  out.clear();
  FILE* f = ::popen(command.c_str(), "r");
  if (!f) return -1;
  char buf[256];
  while (std::fgets(buf, sizeof buf, f)) out += buf;
  int status = ::pclose(f);
  while (!out.empty() && (out.back() == '\n' || out.back() == '\r')) out.pop_back();
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

// `sbatch --parsable` prints "ID" or "ID;CLUSTER".
std::string job_id(const std::string& out) {
  std::string id = out.substr(0, out.find(';'));
  return id.find_first_not_of("0123456789") == std::string::npos && !id.empty() ? id : "";
}

}  // namespace

int run_farm(const CliArgs& o) {
  compile::CompileOptions copts;
  std::string error;
  if (!build_compile_options(o, copts, error)) return usage_error(error);
  warn_overridden_overrides(copts);
  if (o.clock) copts.clock = *o.clock;
  if (!o.frames.empty()) {  // the first frame: the resolution and spp for the plan
    IntRange f;
    if (!parse_range(o.frames, "--frames", std::numeric_limits<std::int32_t>::max(), f, error))
      return usage_error(error);
    copts.frame = double(f.begin);
  }
  auto c = compile::compile_file(o.scene, copts);
  c->diags.print(std::cerr, color_stderr());
  if (c->status != compile::CompileStatus::Ok) {
    if (c->status == compile::CompileStatus::UsageError) return usage_error(c->message);
    if (!c->message.empty()) std::cerr << "snell: error: " << c->message << "\n";
    return c->status == compile::CompileStatus::SceneErrors ? kExitScene : kExitIo;
  }
  const ir::Settings& st = c->scene.settings;
  FarmPlan plan;
  if (!plan_farm(o, self_exe(), st.width, st.height, st.samples ? st.samples : 1, plan, error))
    return usage_error(error);
  std::string array = array_script(plan), merge = merge_script(plan);
  std::string extra;
  for (const std::string& a : plan.sbatch) extra += " " + shell_quote(a);
  std::string submit_array =
      "sbatch --parsable" + extra + " " + shell_quote(plan.array_script_path());
  std::string submit_merge = "sbatch --parsable" + extra + " --dependency=afterany:$ARRAY " +
                             shell_quote(plan.merge_script_path());
  // What the farm writes (the pieces, the results, its two scripts) never replaces
  // a file the scene reads (exit 2, as render and merge), a result is no piece, and
  // the results can be written: their folders, and the display transform of a
  // display-referred one (exit 3). All before anything is written or submitted: a
  // task or merge job that fails for it would fail only after the whole run.
  std::vector<std::string> written = plan.results;
  written.push_back(plan.array_script_path());
  written.push_back(plan.merge_script_path());
  std::vector<std::string> pieces;
  for (const FarmTask& t : plan.tasks)
    for (const std::string& out : t.outputs) pieces.push_back(out), written.push_back(out);
  if (int code = check_not_an_input(written, scene_inputs(c->scene)); code >= 0) return code;
  if (!plan.merges.empty())
    for (const std::string& r : plan.results)
      for (const std::string& piece : pieces)
        if (fs::path(r).lexically_normal() == fs::path(piece).lexically_normal())
          return usage_error("the output " + r +
                             " is one of the render's pieces: the merge would read and replace "
                             "it; choose another name");
  std::error_code ec;
  // A dry run makes the same checks and writes nothing: a result in a folder a
  // real run makes (the farm's, its logs' and pieces') is not asked to exist.
  fs::path farm_dir = fs::absolute(plan.dir, ec).lexically_normal();
  if (farm_dir.filename().empty()) farm_dir = farm_dir.parent_path();  // "d/" is "d"
  auto made_by_run = [&](const std::string& r) {
    const fs::path folder = fs::absolute(r, ec).lexically_normal().parent_path();
    return !fs::exists(folder, ec) &&
           (folder == farm_dir || folder == farm_dir / "logs" || folder == farm_dir / "pieces");
  };
  if (!o.farm_dry_run) {
    for (const char* sub : {"", "/logs", "/pieces"}) fs::create_directories(plan.dir + sub, ec);
    if (ec) {
      std::cerr << "snell: error: cannot create " << plan.dir << ": " << ec.message() << "\n";
      return kExitIo;
    }
  }
  for (const std::string& r : plan.results) {
    if (o.farm_dry_run && made_by_run(r)) continue;
    if (int code = check_output_folder(r); code >= 0) return code;
    if (rt::lower_extension(r) != ".exr")
      if (std::string err = rt::check_display_transform(o.display_view()); !err.empty()) {
        std::cerr << "snell: error: cannot write " << r << ": " << err << "\n";
        return kExitIo;
      }
  }
  if (o.farm_dry_run) {
    std::cout << "# " << plan.array_script_path() << "\n" << array << "\n";
    std::cout << "# " << plan.merge_script_path() << "\n" << merge << "\n";
    std::cout << "# submitted with:\nARRAY=$(" << submit_array << ")\n" << submit_merge << "\n";
    return kExitOk;
  }
  // A stale output of an earlier run would pass the merge job's check, and a stale
  // final image would sit where a failed merge leaves none: they are set aside
  // (renamed beside themselves) now, removed once both jobs are submitted, and put
  // back when a submission fails, so a failing command leaves every file as it was.
  // The scripts too: a failed submission left the new ones over the old.
  std::vector<std::pair<fs::path, fs::path>> aside;
  std::vector<fs::path> scripts_written;
  auto put_back = [&] {
    for (const fs::path& s : scripts_written) fs::remove(s, ec);
    for (const auto& [was, now] : aside) fs::rename(now, was, ec);
  };
  for (const std::string& out : written) {
    const fs::path p(out);
    if (!fs::exists(fs::symlink_status(p, ec))) continue;
    const fs::path stale =
        p.parent_path() / fmt::format(".{}.farm-stale-{}", p.filename().string(), ::getpid());
    fs::rename(p, stale, ec);
    if (ec) {
      std::cerr << "snell: error: cannot set aside the earlier " << out << ": " << ec.message()
                << "\n";
      put_back();
      return kExitIo;
    }
    aside.emplace_back(p, stale);
  }
  for (const auto& [path, text] :
       {std::pair{plan.array_script_path(), array}, std::pair{plan.merge_script_path(), merge}}) {
    scripts_written.push_back(path);
    std::ofstream f(path);
    f << text;
    if (!f) {
      std::cerr << "snell: error: cannot write " << path << "\n";
      put_back();
      return kExitIo;
    }
  }
  std::string out;
  int code = capture(submit_array, out);
  std::string array_id = job_id(out);
  if (code != 0 || array_id.empty()) {
    put_back();
    std::cerr << "snell: error: farm: `" << submit_array << "` failed (exit " << code << ")"
              << (out.empty() ? "" : ": " + out) << "; is Slurm installed and running?\n";
    return kExitIo;
  }
  std::string merge_cmd = submit_merge;
  merge_cmd.replace(merge_cmd.find("$ARRAY"), 6, array_id);
  code = capture(merge_cmd, out);
  std::string merge_id = job_id(out);
  // The array job is submitted: its tasks may be writing their pieces now.
  for (const auto& [was, now] : aside) fs::remove(now, ec);
  if (code != 0 || merge_id.empty()) {
    std::cerr << "snell: error: farm: `" << merge_cmd << "` failed (exit " << code << ")"
              << (out.empty() ? "" : ": " + out) << "; the array job " << array_id
              << " is submitted: scancel it, or run " << plan.merge_script_path()
              << " when it is done\n";
    return kExitIo;
  }
  std::cout << fmt::format(
      "submitted array job {} ({} tasks) and merge job {}\n"
      "follow:  squeue -j {},{}   (logs in {}/logs/)\n"
      "result:  {}\n"
      "a failed task i: sbatch --array=i {}, then sbatch {}\n",
      array_id, plan.tasks.size(), merge_id, array_id, merge_id, plan.dir,
      plan.results.size() == 1 ? plan.results[0]
                               : fmt::format("{} images in {}", plan.results.size(), plan.dir),
      plan.array_script_path(), plan.merge_script_path());
  // The job ids alone on the last line, for scripts: "ARRAY MERGE".
  std::cout << array_id << " " << merge_id << "\n";
  return kExitOk;
}

}  // namespace snell::cli
