// CI outputs built from the typed results: JUnit XML and summary.md (the diff of two results files
// and the baseline: input/results_diff.hpp).
#pragma once

#include <string>

#include "input/results_diff.hpp"  // the diff, for the callers of these outputs
#include "input/suite_result.hpp"

namespace liftcheck {

/// One <testsuite> per scenario, one <testcase> per configuration's run, valid against Jenkins'
/// junit-10.xsd (tests/junit-10.xsd): each case's system-out carries its metrics (expected,
/// measured, error, tolerance); a failure's message names the failing metrics with their figures;
/// skips are skipped, and so is a listed known failure (an expected failure), with its reason as
/// the message; a sweep entry whose every failing point is a known failure likewise. A suite per
/// configuration's standing ("standing.CONFIG") names its counts and worst failure, as every output does.
std::string junit_xml(const SuiteResults& results);

/// summary.md, short enough for a pull-request comment: the verdict counts, the runs and sweep
/// gates not as expected first (with their figures), then a table of each configuration's
/// standing, and a link to the report (`report_link`, empty: none; absolute for a pull-request
/// comment). Its first line is a marker by which CI finds and updates its own comment.
std::string summary_markdown(const SuiteResults& results, const std::string& report_link);

/// A failure's message: its verdict and message, then each counted metric out of tolerance,
/// worst first, with its figures (what JUnit, summary.md and the console say of it).
std::string failure_text(const RunResult& r);

}  // namespace liftcheck
