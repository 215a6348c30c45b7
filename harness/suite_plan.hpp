// The validation suite as a plan of independent runs: every scenario x configuration, every sweep
// point, every outcome-sweep case and every map point is one item with a stable key. Items run in
// parallel (longest first), a shard runs a deterministic share of them, and the sweeps, the
// outcome sweep and the map are assembled from the items' records only, so a merge of shards
// assembles exactly what one unsharded run does.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engines/engine.hpp"
#include "harness/external.hpp"
#include "input/params.hpp"
#include "scenarios/scenario.hpp"
#include "harness/runner.hpp"
#include "harness/sweeps.hpp"

namespace liftcheck {

/// What validate runs.
struct SuiteDef {
  std::vector<const EngineInfo*> engines;  ///< configurations, in registry order as given
  std::vector<std::string> globs;          ///< scenario name globs (--filter): any may match
  Overrides set;                           ///< --set KEY=VALUE, applied where a run takes it
  bool sweeps = true;                      ///< the sweeps, the outcome sweep and the map
  /// The parameter sweeps and the outcome grid on every configuration, also those registered for
  /// fewer points (EngineInfo::points; validate --all-points).
  bool all_points = false;
  double timeout_s = 120.0;             ///< each item's wall-clock limit (a timed-out item is an error record)
  std::string external_name;            ///< --trace-dir: the outside simulator's name
  std::map<std::string, Trace> traces;  ///< its trace per scenario
};

/// The configurations of `def` that the parameter sweeps and the outcome grid run on.
std::vector<const EngineInfo*> sweep_engines(const SuiteDef& def);

struct SuiteItem {
  enum Kind { kRun, kPoint };
  Kind kind = kRun;
  std::string key;  ///< "run/SCENARIO/CONFIG" or the point run's key
  const Scenario* scenario = nullptr;
  const EngineInfo* engine = nullptr;
  std::shared_ptr<const EngineInfo> owned;  ///< a replaying configuration (--trace-dir)
  std::string trace_file;                   ///< its trace, read again by the worker process
  Overrides overrides;                      ///< the --set values and point values it was asked with
  /// Its run, resolved once when the item is made (planned_item): what the worker runs. None when
  /// a name or value could not be resolved: `resolve_error` says why (the run's error record).
  std::optional<ResolvedRun> run;
  std::string resolve_error;
  double cost = 1.0;  ///< scheduling estimate (engine steps), longest first
  /// The earlier item with the same scenario, configuration, parameters and settings (-1: none):
  /// its record is this item's too (same inputs, same numbers), so it runs once.
  long same_as = -1;
  /// The earlier run whose drive this run judges too (Scenario::shared_drive, the same configuration,
  /// parameters and settings; -1: none): that run's worker makes the drive once and returns this
  /// run's record with its own (take_shared_records), so this item is not handed out.
  long judges_drive_of = -1;
  /// The runs of the later items that judge this run's drive.
  std::vector<ResolvedRun> drive_judges;
  /// Its record keeps the traces as the scenario recorded them (`run --json`); otherwise the
  /// worker thins them to what results.json draws.
  bool full_traces = false;
  /// Run by a worker of its own: neither the same as an earlier item nor judging another's drive.
  bool runs_itself() const { return same_as < 0 && judges_drive_of < 0; }
};

/// An item of `kind` that runs `scenario` on `engine` with `overrides`, its run resolved now.
SuiteItem planned_item(SuiteItem::Kind kind, std::string key, const Scenario& scenario, const EngineInfo& engine,
                       Overrides overrides);

struct SuitePlan {
  SuiteDef def;
  std::vector<const Scenario*> scenarios;
  std::vector<const SweepDef*> sweeps;
  bool outcome_sweep = false;
  bool map = false;
  std::vector<SuiteItem> items;  ///< runs first (scenario-major), then the points

  /// What a shard records so that merge can refuse shards of different suites: configurations,
  /// filter, --set values and whether the sweeps run.
  nlohmann::json selection() const;
};

/// The key of the item that runs `scenario` on configuration `engine`: "run/SCENARIO/CONFIG".
std::string run_key(const std::string& scenario, const std::string& engine);

/// The plan; InputError when the filter matches nothing or a --set key is taken by no run.
SuitePlan plan_suite(const SuiteDef& def);

/// The items of share `index` (1-based) of `total`: every total-th item in plan order among those
/// that run (an item the same as an earlier one is not run; see fill_duplicates).
std::vector<size_t> shard_share(const SuitePlan& plan, int index, int total);

/// Gives each item that is the same as an earlier one that item's record (a point's without traces).
void fill_duplicates(const SuitePlan& plan, std::map<std::string, RunResult>& records);

}  // namespace liftcheck
