// snell sweep: renders one scene across settings, measures wall time (median of
// repeats, all in one run so ratios hold on a noisy machine) and error against a
// converged reference, and writes CSV, JSON, SVG plots and a Markdown summary.
//
//   snell sweep SCENE --vary samples=1,4,16,64 [--vary max_depth=1,2,4,8]
//                     [--series fresnel=exact,schlick] [--repeats 3]
//                     [--reference-spp 1024] [--res WxH] [--out DIR] [--markdown FILE]
//
// Each --vary makes one plot of error versus time; --series draws one curve per
// value in every plot. Keys are settings properties, plus `area_samples` (every
// area light's grid, n×n) and `kernel` (specialised | general).
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "compiler/compile.hpp"

namespace snell::cli {

struct SweepAxis {
  std::string key;
  std::vector<std::string> values;
};

struct SweepOptions {
  std::string scene;
  compile::CompileOptions compile;  // base overrides (--set, --res) included
  std::vector<SweepAxis> vary;
  SweepAxis series;  // empty key: one curve
  int repeats = 3;
  std::uint32_t reference_spp = 1024;
  std::string out_dir = "sweep";
  std::string name;      // prefix of every output file; empty: the scene's stem
  std::string markdown;  // empty: none
  int threads = 0;
  bool quiet = false;
  bool images = true;  // write a PNG of each configuration
};

struct SweepRow {
  std::string knob, value, series_value;
  double seconds = 0;      // median wall time of a render
  double seconds_min = 0;  // fastest of the repeats
  double rmse = 0, relmse = 0, dssim = 0;
  std::uint64_t rays = 0;
  std::string image;  // path of the PNG, relative to the output folder
};

// Parses "key=v1,v2,..."; false on a malformed argument.
bool parse_axis(const std::string& text, SweepAxis& axis);

// Runs the sweep; returns the process exit status (spec §10 codes).
int run_sweep(const SweepOptions& options);

}  // namespace snell::cli
