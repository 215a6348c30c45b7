// The progress line of validate, on standard error (standard output carries the results).
#pragma once

#include <chrono>
#include <cstddef>
#include <fmt/format.h>
#include <iostream>
#include <unistd.h>

namespace liftcheck::cli {

/// A progress line on a terminal (rewritten in place), a plain line every 10 s otherwise (as the
/// items end); both on standard error, so that standard output holds the results alone. It counts
/// the plan's items: its runs and the sweeps' and map's points, one unit.
struct Progress {
  static constexpr double kPlainEvery_s = 10.0;
  bool tty = isatty(STDERR_FILENO) != 0;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  double last_s = 0.0;
  bool shown = false;
  void clear() {
    if (shown) std::cerr << "\r\033[K" << std::flush;
    shown = false;
  }
  void update(size_t done, size_t total) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (tty) {
      std::cerr << fmt::format("\r\033[K[{}/{} runs and points] {:.1f} s", done, total, s) << std::flush;
      shown = true;
    } else if (s - last_s >= kPlainEvery_s || done == total) {
      last_s = s;
      std::cerr << fmt::format("progress {}/{} runs and points, {:.1f} s\n", done, total, s);
    }
  }
};

}  // namespace liftcheck::cli
