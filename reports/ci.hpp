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
/// skips are skipped, and so is a listed known failure (an expected failure), with its reason as
/// the message; a sweep entry whose every failing point is a known failure likewise.
std::string junit_xml(const nlohmann::json& results);

/// summary.md, short enough for a pull-request comment: the verdict counts, the runs and sweep
/// gates not as expected first (with their figures), then the configuration x scenario matrix in
/// symbols, and a link to the report (`report_link`, empty: none; absolute for a pull-request
/// comment). Its first line is a marker by which CI finds and updates its own comment.
std::string summary_markdown(const nlohmann::json& results, const std::string& report_link);

}  // namespace liftcheck
