// The progress line of validate, on standard error (standard output carries the results).
#pragma once

#include <chrono>
#include <cstddef>
#include <fmt/format.h>
#include <iostream>
#include <unistd.h>

namespace liftcheck::cli {

/// A progress line on a terminal (rewritten in place), a plain line every tenth otherwise; both on
/// standard error, so that standard output holds the results alone.
struct Progress {
  bool tty = isatty(STDERR_FILENO) != 0;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  size_t last_tenth = 0;
  bool shown = false;
  void clear() {
    if (shown) std::cerr << "\r\033[K" << std::flush;
    shown = false;
  }
  void update(size_t done, size_t total) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (tty) {
      std::cerr << fmt::format("\r\033[K[{}/{}] {:.1f} s", done, total, s) << std::flush;
      shown = true;
    } else if (total > 0 && done * 10 / total > last_tenth) {
      last_tenth = done * 10 / total;
      std::cerr << fmt::format("progress {}/{} runs, {:.1f} s\n", done, total, s);
    }
  }
};

}  // namespace liftcheck::cli
