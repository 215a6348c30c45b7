// results.json: a context block (who, what, where) and flat run records, the source of truth for
// every report.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "input/atomic_file.hpp"   // write_file_atomic
#include "input/results_file.hpp"  // read_results: results and baselines read back, checked
#include "harness/runner.hpp"

namespace liftcheck {

/// liftcheck version and commit, engines, machine, date, wall time.
nlohmann::json context_json(const std::vector<const EngineInfo*>& engines, double wall_s);

/// {"context", "summary", "runs"}.
nlohmann::json results_json(const std::vector<RunRecord>& runs, const nlohmann::json& context);
/// The same from run records as results.json stores them (RunRecord::to_json).
nlohmann::json results_from_records(const nlohmann::json& runs, const nlohmann::json& context);

}  // namespace liftcheck
