// The results of a suite assembled from its items' records only (so a merge of shards assembles
// exactly what one unsharded run does): runs, sweeps, maps and the simulated time.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "harness/suite_plan.hpp"
#include "harness/worker_pool.hpp"

namespace liftcheck {

/// The records of the runs that judge the drive item `maker` made, by item index: from its record's
/// "shared" list, or error records saying what became of the maker where the list is missing.
std::vector<std::pair<size_t, nlohmann::json>> shared_records(const SuitePlan& plan, size_t maker,
                                                              const nlohmann::json& record);
/// shared_records of every drive-maker in `records`, put under their own keys (the makers' "shared"
/// lists removed).
void take_shared_records(const SuitePlan& plan, std::map<std::string, nlohmann::json>& records);

/// {"runs", "sweeps", "maps"} assembled from every item's record (by key): std::out_of_range when
/// one is missing.
nlohmann::json assemble_suite(const SuitePlan& plan, const std::map<std::string, nlohmann::json>& records);

/// The part of the suite an item belongs to: "runs", "sweep/NAME", "outcomes" or "map/NAME".
std::string item_part(const SuiteItem& item);

/// The simulated time the suite steps (the budget of issue-free verdicts: what each part costs in
/// engine time is this times the configuration's cost per simulated second), from the records of
/// the items that ran (a duplicate runs once and counts once), summed in plan order and rounded to
/// the microsecond so that it is the same figure at any --jobs and for any sharding:
/// {"total_s", "by_part": {PART: s}, "by_configuration": {CONFIG: {"total_s", "by_part"}}}.
nlohmann::json simulated_budget(const SuitePlan& plan, const std::map<std::string, nlohmann::json>& records);

/// The results of a whole suite (one unsharded run, or the merge of every share) from every item's
/// record: the duplicates filled in, then {"context", "summary", "simulated", "runs", "sweeps",
/// "maps", "scenarios"}.
nlohmann::json suite_results(const SuitePlan& plan, std::map<std::string, nlohmann::json>& records,
                             const nlohmann::json& context);

/// Where a suite's time went, counted as its items end: engine seconds (the records' wall_s) and
/// the wall seconds each item held its worker (an outside engine's protocol included), in all, by
/// part of the suite and by configuration.
struct SuiteTiming {
  double wall_s = 0.0, runs_s = 0.0, points_s = 0.0, held_s = 0.0;
  std::map<std::string, double> cost_by_part, cost_by_config, held_by_part, held_by_config;
  void count(const SuiteItem& item, const nlohmann::json& record, double held_s);
};

/// The results' "context" of a suite run in this process: the configurations (context_json), the
/// timings, the runner's limits, the --set values and which adapters the outside configurations ran.
nlohmann::json suite_context(const std::vector<const EngineInfo*>& engines, const SuiteTiming& timing,
                             const RunnerDef& runner, const Overrides& set);

}  // namespace liftcheck
