// Instrumentation in one object: the counters of --stats, the --pixel ray-tree
// trace and the per-effect cost clock, handed through the hot code as one
// parameter. Probe<false> carries only the counters (always kept: they are a few
// increments, and --stats must not change the picture); its `trace` and `cost`
// are compile-time null, so every `if (probe.tracing())` of a fast kernel
// compiles to nothing. Probe<true> runs for the one traced pixel and the timed
// subset of samples.
#pragma once

#include <chrono>
#include <cmath>
#include <string>

#include "runtime/render.hpp"

namespace snell::rt {

// Per-effect time, measured on a subset of camera samples (render.cpp picks which;
// docs/effects.md). Indexed by CostKind; nanoseconds of one thread.
enum CostKind : int {
  kCostCamera = 0,  // same order as RayKind
  kCostReflection,
  kCostRefraction,
  kCostGlossy,
  kCostShadow,
  kCostLens,
  kCostTime,
  kCostKinds
};
struct CostClock {
  double overhead_ns = 0;  // one now_ns() pair, subtracted from every interval
  double ns[kCostKinds] = {};
  static double now_ns() {
    return double(std::chrono::duration_cast<std::chrono::nanoseconds>(
                      std::chrono::steady_clock::now().time_since_epoch())
                      .count());
  }
  double since(double t0) const { return std::fmax(0.0, now_ns() - t0 - overhead_ns); }
};

template <bool On>
struct Probe;

template <>
struct Probe<false> {
  RenderStats& stats;
  static constexpr bool on = false;
  static constexpr std::string* trace = nullptr;
  static constexpr CostClock* cost = nullptr;
  constexpr bool tracing() const { return false; }
  constexpr bool timing() const { return false; }
};

template <>
struct Probe<true> {
  RenderStats& stats;
  std::string* trace = nullptr;  // the readable ray tree, when not null
  CostClock* cost = nullptr;     // the time of each ray by kind, when not null
  static constexpr bool on = true;
  bool tracing() const { return trace != nullptr; }
  bool timing() const { return cost != nullptr; }
};

}  // namespace snell::rt
