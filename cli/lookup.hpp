// What the commands share: scenarios, configurations and --set values looked up by the user's
// names (an unknown one is an input error with the nearest names), the runner's limits, a record
// printed for a reader.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "harness/suite_plan.hpp"
#include "harness/suite_results.hpp"
#include "harness/worker_pool.hpp"

namespace liftcheck::cli {

/// "a,b,,c" -> {"a", "b", "c"}.
std::vector<std::string> split_list(const std::string& s);

const Scenario& scenario_or_throw(const std::string& name);
const EngineInfo& engine_or_throw(const std::string& name);

/// --set KEY=VALUE arguments for `s` (run on `e`, if given): a key that is no parameter of the
/// scenario and no setting of any configuration is refused with the nearest of the scenario's
/// parameters and the configuration's settings (the runner words a setting of another engine).
Overrides overrides_or_throw(const std::vector<std::string>& sets, const Scenario& s, const EngineInfo* e);

/// --jobs and --timeout checked; the runner stops at a signal.
RunnerDef runner_def(int jobs, double timeout_s, double memory_limit_mib = kDefaultRunMemoryMiB);

/// A run record as a table of its metrics.
void print_record(const nlohmann::json& r);

/// Runs the plan's one item in a worker (a hang or a crash of the engine is an error record),
/// prints its record (JSON or a table) and returns the exit status: 0 as expected, 1 otherwise.
int run_one(const SuitePlan& plan, const RunnerDef& runner, bool json, const std::string& during);

}  // namespace liftcheck::cli
