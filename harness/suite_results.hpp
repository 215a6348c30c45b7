// The results of a suite assembled from its items' records only (so a merge of shards assembles
// exactly what one unsharded run does): runs, sweeps, maps and the simulated time.
#pragma once

#include <map>
#include <string>
#include <utility>
#include <vector>

#include "harness/suite_plan.hpp"
#include "harness/worker_pool.hpp"
#include "input/suite_result.hpp"

namespace liftcheck {

/// The records of the items of one suite (or share), by item key.
using Records = std::map<std::string, RunResult>;

/// The records of the runs that judge the drive item `maker` made, by item index: from its record's
/// `shared` list, or error records saying what became of the maker where the list is missing.
std::vector<std::pair<size_t, RunResult>> shared_records(const SuitePlan& plan, size_t maker, const RunResult& record);
/// shared_records of every drive-maker in `records`, put under their own keys (the makers' `shared`
/// lists emptied).
void take_shared_records(const SuitePlan& plan, Records& records);

/// The part of the suite an item belongs to: "runs", "sweep/NAME", "outcomes" or "map/NAME".
std::string item_part(const SuiteItem& item);

/// The simulated time the suite steps (the budget of issue-free verdicts: what each part costs in
/// engine time is this times the configuration's cost per simulated second), from the records of
/// the items that ran (a duplicate runs once and counts once), summed in plan order and rounded to
/// the microsecond so that it is the same figure at any --jobs and for any sharding.
SimulatedBudget simulated_budget(const SuitePlan& plan, const Records& records);

/// The results of a whole suite (one unsharded run, or the merge of every share) from every item's
/// record: the duplicates filled in, the sweeps, the outcome grid and the map assembled. Throws
/// std::out_of_range when a record is missing.
SuiteResults suite_results(const SuitePlan& plan, Records& records, SuiteContext context);

/// Where a suite's time went, counted as its items end: engine seconds (the records' wall_s) and
/// the wall seconds each item held its worker (an outside engine's protocol included), in all, by
/// part of the suite and by configuration.
struct SuiteTiming {
  double wall_s = 0.0, runs_s = 0.0, points_s = 0.0, held_s = 0.0;
  std::map<std::string, double> cost_by_part, cost_by_config, held_by_part, held_by_config;
  void count(const SuiteItem& item, const RunResult& record, double held_s);
};

/// The context of a suite run in this process: the configurations (context_of), the timings, the
/// runner's limits, the --set values and which adapters the outside configurations ran.
SuiteContext suite_context(const std::vector<const EngineInfo*>& engines, const SuiteTiming& timing,
                           const RunnerDef& runner, const Overrides& set);

}  // namespace liftcheck
