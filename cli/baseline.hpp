// validate --baseline FILE and merge --baseline FILE: the runs made compared with a reviewed
// baseline (a filtered or sharded run compares its share).
#pragma once

#include <optional>
#include <string>

#include "input/suite_result.hpp"

namespace liftcheck::cli {

/// Reads the baseline before anything runs: a malformed one stops at once. None when there is
/// none to compare with (no --baseline, or --update-baseline).
std::optional<SuiteResults> read_baseline(const std::string& path, bool update_baseline);

/// Compares the runs and points of `results` with the baseline's of the same runs and points (and
/// the outcome grid's cases), prints the diff and stores it in results.baseline; returns the
/// regressions and the metrics whose error grew by more than `worse_factor`.
int compare_with_baseline(SuiteResults& results, const std::string& path, const SuiteResults& baseline,
                          double worse_factor);

}  // namespace liftcheck::cli
