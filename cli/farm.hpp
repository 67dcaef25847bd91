// snell farm slurm: one render spread over a Slurm array job (§18's pieces), and a
// merge job that runs after every task has ended, however it ended
// (--dependency=afterany: an `afterok` merge would wait forever on a failed task,
// ../shared/reference/ecosystem-2.md §5.1) and checks every task's output first, so
// a failed task fails the merge with its index instead of hanging or giving a
// partial image.
//
//   snell farm slurm SCENE [render options] (--tiles N | --passes N | --frames A..B)
//                    --dir SHARED [--sbatch ARG]... [--dry-run]
//
// --tiles N: N row bands (--crop); --passes N: N sample ranges (--sample-range);
// --frames A..B: one task a frame (--frames A..B --frame F). Scripts, pieces, logs
// and the result land in SHARED, a folder every node sees. The plan and the
// scripts are pure functions of the options (tests pin them); farm.cpp's
// run_farm submits them with sbatch.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "cli/options.hpp"

namespace snell::cli {

struct FarmTask {
  std::vector<std::string> args;     // what this task adds to the common render arguments
  std::vector<std::string> outputs;  // the files it must leave behind
};

struct FarmPlan {
  std::string snell;                     // absolute path of the snell program
  std::string dir;                       // the shared folder, absolute
  std::string name;                      // job name: snell-STEM
  std::vector<std::string> render_args;  // "render SCENE options…", every task's
  std::vector<FarmTask> tasks;           // task i is array index i
  // The merge job's commands (snell merge OUT PIECES… for each output); empty for
  // frames, whose tasks write the outputs themselves.
  std::vector<std::vector<std::string>> merges;
  std::vector<std::string> results;  // what the user gets
  std::vector<std::string> sbatch;   // extra sbatch arguments (--partition=…)
  std::string array_script_path() const { return dir + "/render.sbatch"; }
  std::string merge_script_path() const { return dir + "/merge.sbatch"; }
};

// The plan for `o` (farm options and the render options to forward) and the
// compiled scene's width, height and spp; false with `error` set (a usage error).
bool plan_farm(const CliArgs& o, const std::string& snell_exe, std::uint32_t width,
               std::uint32_t height, std::uint32_t spp, FarmPlan& plan, std::string& error);

std::string array_script(const FarmPlan& plan);
std::string merge_script(const FarmPlan& plan);

// `s` quoted for a POSIX shell ('…', with ' written '\'').
std::string shell_quote(const std::string& s);

// Compiles the scene (its errors stop here, before anything is submitted), plans,
// and writes and submits the scripts, or prints them with --dry-run.
int run_farm(const CliArgs& o);

}  // namespace snell::cli
