// CI outputs built from results.json: JUnit XML, and a regression diff between two results files.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace liftcheck {

/// One <testsuite> per scenario, one <testcase> per configuration's run, valid against Jenkins'
/// junit-10.xsd (tests/junit-10.xsd): each suite's properties carry every run's metrics (expected,
/// measured, error, tolerance); a failure's message names the failing metrics with their figures;
/// skips are skipped; a listed known failure passes with its reason on system-out.
std::string junit_xml(const nlohmann::json& results);

/// A baseline of a results file: its runs' records only (scenario, configuration, parameters,
/// settings, status, verdict, metrics), without traces, details or timings, so it stays small and
/// reviewable in a diff; `diff_results` compares a results file with it.
nlohmann::json baseline_json(const nlohmann::json& results);

/// summary.md, short enough for a pull-request comment: the verdict counts, the runs and sweep
/// gates not as expected first (with their figures), then the configuration x scenario matrix in
/// symbols, and a link to the report (`report_link`, empty: none).
std::string summary_markdown(const nlohmann::json& results, const std::string& report_link);

struct DiffDef {
  /// A metric counts as worse when its error grows by more than this factor and ends above
  /// `floor` of its tolerance (changes deep inside the tolerance are noise, not regressions).
  double growth = 10.0;
  double floor = 0.01;
};

/// Compares two results files run by run: status changes (a run that was as expected and is no
/// longer is a regression), runs added or removed, and metrics whose errors grew.
/// Returns {"regressions": [...], "worse": [...], "better": [...], "added": [...], "removed": [...]}.
nlohmann::json diff_results(const nlohmann::json& base, const nlohmann::json& head, const DiffDef& def = {});

/// The diff as plain text, one line per finding.
std::string diff_text(const nlohmann::json& diff);

}  // namespace liftcheck
