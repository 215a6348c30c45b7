// CI outputs built from results.json: JUnit XML and summary.md (the diff of two results files and
// the baseline: input/results_diff.hpp).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "input/results_diff.hpp"  // record_as_expected, and the diff for the callers of these outputs

namespace liftcheck {

/// One <testsuite> per scenario, one <testcase> per configuration's run, valid against Jenkins'
/// junit-10.xsd (tests/junit-10.xsd): each suite's properties carry every run's metrics (expected,
/// measured, error, tolerance); a failure's message names the failing metrics with their figures;
/// skips are skipped; a listed known failure passes with its reason on system-out.
std::string junit_xml(const nlohmann::json& results);

/// summary.md, short enough for a pull-request comment: the verdict counts, the runs and sweep
/// gates not as expected first (with their figures), then the configuration x scenario matrix in
/// symbols, and a link to the report (`report_link`, empty: none).
std::string summary_markdown(const nlohmann::json& results, const std::string& report_link);

}  // namespace liftcheck
