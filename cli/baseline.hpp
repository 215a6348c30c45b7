// validate --baseline FILE and merge --baseline FILE: the runs made compared with a reviewed
// baseline (a filtered or sharded run compares its share).
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace liftcheck::cli {

/// Reads the baseline before anything runs: a malformed one stops at once. Null when there is
/// none to compare with (no --baseline, or --update-baseline).
nlohmann::json read_baseline(const std::string& path, bool update_baseline);

/// Compares the runs of `results` with the baseline's runs of the same scenario and configuration,
/// prints the diff and stores it as results["baseline"]; returns the regressions and metrics grown.
int compare_with_baseline(nlohmann::json& results, const std::string& path, const nlohmann::json& baseline);

}  // namespace liftcheck::cli
