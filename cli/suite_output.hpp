// What validate and merge write once a suite's records are assembled: the sweeps' gates, the
// baseline comparison, results.json, junit.xml, summary.md and the report, and the exit status.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "cli/staged_output.hpp"

namespace liftcheck::cli {

/// Where and what validate and merge write.
struct OutputOptions {
  std::string out_dir;
  bool report = true;
  std::string baseline_path;  ///< compare with it (or rewrite it)
  bool update_baseline = false;
  bool snapshots = true;  ///< the report's snapshots (off: the pages and plots only)
  int threads = 2;        ///< the report's rendering threads (validate: its --jobs, the cores it may use)
};

/// The sweeps' gates, the baseline comparison (of the runs made only: a filtered or sharded run
/// compares its share), then results.json, junit.xml, summary.md and the report; the exit status.
int finish_suite(nlohmann::json& results, const OutputOptions& o, const nlohmann::json& baseline, StagedOutput& staged);

/// A results file's outputs written again (report, junit.xml, summary.md, results.json) with
/// this liftcheck's report code; nothing is run or judged again. The exit status is the file's.
int render_again(nlohmann::json& results, const OutputOptions& o, StagedOutput& staged);

}  // namespace liftcheck::cli
