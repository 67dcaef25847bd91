// Render progress on stderr: a redrawn bar with ETA on a terminal, one line per
// 10 % when piped (log-friendly), nothing with --quiet. Thread-safe: the runtime
// calls it from its worker threads.
#pragma once

#include <chrono>
#include <cstdio>
#include <mutex>

namespace snell::cli {

class Progress {
 public:
  Progress(bool enabled, bool tty) : enabled_(enabled), tty_(tty), start_(Clock::now()) {}

  void update(double fraction) {
    if (!enabled_) return;
    std::lock_guard lock(mutex_);
    double elapsed = seconds();
    if (tty_) {
      if (fraction < 1 && elapsed - last_draw_ < 0.25) return;
      last_draw_ = elapsed;
      constexpr int kWidth = 30;
      int filled = static_cast<int>(fraction * kWidth);
      char bar[kWidth + 1];
      for (int i = 0; i < kWidth; ++i) bar[i] = i < filled ? '=' : ' ';
      bar[kWidth] = 0;
      double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
      std::fprintf(stderr, "\rRendering [%s] %5.1f%% (%.1fs, ETA %.1fs)", bar, 100 * fraction,
                   elapsed, eta);
      std::fflush(stderr);
    } else {
      int decile = static_cast<int>(fraction * 10 + 1e-9);
      if (decile <= last_decile_) return;
      last_decile_ = decile;
      double eta = fraction > 0 ? elapsed * (1 - fraction) / fraction : 0;
      std::fprintf(stderr, "progress %3d%% elapsed %.1fs eta %.1fs\n", decile * 10, elapsed, eta);
    }
  }

  void finish() {
    if (enabled_ && tty_) std::fprintf(stderr, "\n");
  }

  double seconds() const { return std::chrono::duration<double>(Clock::now() - start_).count(); }

 private:
  using Clock = std::chrono::steady_clock;
  bool enabled_, tty_;
  Clock::time_point start_;
  std::mutex mutex_;
  double last_draw_ = -1;
  int last_decile_ = 0;
};

}  // namespace snell::cli
