// What validate and merge write once a suite's records are assembled: the sweeps' gates, the
// baseline comparison, results.json, junit.xml, summary.md and the report, and the exit status.
#pragma once

#include <CLI/CLI.hpp>
#include <optional>
#include <string>

#include "cli/staged_output.hpp"
#include "input/results_diff.hpp"  // kDefaultWorseFactor
#include "input/suite_result.hpp"

namespace liftcheck::cli {

/// Where and what validate and merge write.
struct OutputOptions {
  std::string out_dir;
  bool report = true;
  std::string baseline_path;  ///< compare with it (or rewrite it)
  bool update_baseline = false;
  double worse_factor = kDefaultWorseFactor;  ///< the regression gate's factor (--worse-factor)
  bool snapshots = true;                      ///< the report's snapshots (off: the pages and plots only)
  int threads = 2;  ///< the report's rendering threads (validate: its --jobs, the cores it may use)
  double report_memory_limit_mib = kDefaultReportMemoryMiB;  ///< the renderer's address space (RLIMIT_AS)
  static constexpr double kDefaultReportMemoryMiB = 4096.0;
};

/// --report-memory-limit MIB on `cmd`, into `o`.
void add_report_memory_option(CLI::App* cmd, OutputOptions& o);
/// --worse-factor F on `cmd`, into `o`.
void add_worse_factor_option(CLI::App* cmd, OutputOptions& o);

/// The sweeps' gates, the baseline comparison (of the runs made only: a filtered or sharded run
/// compares its share), then results.json, junit.xml, summary.md and the report; the exit status.
int finish_suite(SuiteResults& results, const OutputOptions& o, const std::optional<SuiteResults>& baseline,
                 StagedOutput& staged);

/// A results file's outputs written again (report, junit.xml, summary.md, results.json) with
/// this liftcheck's report code; nothing is run or judged again. The exit status is the file's.
int render_again(SuiteResults& results, const OutputOptions& o, StagedOutput& staged);

}  // namespace liftcheck::cli
