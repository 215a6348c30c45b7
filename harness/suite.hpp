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
#include <string>
#include <vector>

#include "engines/engine.hpp"
#include "harness/external.hpp"
#include "input/params.hpp"
#include "scenarios/scenario.hpp"
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
  double timeout_s = 120.0;                ///< each item's wall-clock limit (a timed-out item is an error record)
  std::string external_name;               ///< --trace-dir: the outside simulator's name
  std::map<std::string, Trace> traces;     ///< its trace per scenario
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
  std::string trace_file;                    ///< its trace, read again by the worker process
  Overrides overrides;
  double cost = 1.0;  ///< scheduling estimate (engine steps), longest first
  /// The earlier item with the same scenario, configuration, parameters and settings (-1: none):
  /// its record is this item's too (same inputs, same numbers), so it runs once.
  long same_as = -1;
  /// The earlier run whose drive this run judges too (Scenario::shared_drive, the same configuration,
  /// parameters and settings; -1: none): that run's worker makes the drive once and returns this
  /// run's record with its own (take_shared_records), so this item is not handed out.
  long judges_drive_of = -1;
  /// The scenarios of the later runs that judge this run's drive.
  std::vector<const Scenario*> drive_judges;
  /// Run by a worker of its own: neither the same as an earlier item nor judging another's drive.
  bool runs_itself() const { return same_as < 0 && judges_drive_of < 0; }
};

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

/// Runs one item: the full run record for a run, point_record for a point. An engine's or a
/// scenario's exception becomes an error record; records are normalised through JSON text, so a
/// record read back from results.json is identical to one just made.
nlohmann::json run_item(const SuiteItem& item);

/// The default memory limit of a worker process (--memory-limit), in MiB: a worker takes about 250 MiB
/// of address space with every engine loaded, a default run far less than 1 GiB more.
constexpr double kDefaultRunMemoryMiB = 4096;

/// How items are run: each in a worker process (`liftcheck worker`), `jobs` at once, so an engine
/// that hangs, crashes or ends the process is an error record and never takes the suite with it.
struct RunnerDef {
  int jobs = 1;              ///< at most usable_cores() run at once
  double timeout_s = 120.0;  ///< CPU-time limit of one item, counted by its worker from the item's start; a run that
                             ///< waits is stopped after 4 times as long (at least 30 s more) of wall-clock time
  /// Limit of one worker's address space in MiB (RLIMIT_AS; 0: none): an allocation beyond it fails
  /// and the run is an error record saying so, the suite goes on. Not applied under AddressSanitizer.
  double memory_limit_mib = kDefaultRunMemoryMiB;
  std::string exe;           ///< the liftcheck executable (empty: /proc/self/exe)
  /// Polled between events; true stops the runner (killing its workers) with RunnerStopped.
  std::function<bool()> stop = {};
};
/// The cores this process may run on (its CPU affinity): --jobs is capped at it.
int usable_cores();

struct RunnerStopped : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Runs `which` in worker processes, the runs first and each group longest first; `done(i,
/// record, held_s)` is called in plan order, `progress(done, total)` between; held_s is the wall
/// time the item held its worker (from its request to its record: an outside engine's protocol and
/// waits included, which the record's engine seconds are not). Returns the records in the order of
/// `which`. An item past its time limit, or whose worker dies, gets an error record saying so (with
/// the end of the worker's stderr).
std::vector<nlohmann::json> run_items(const SuitePlan& plan, const std::vector<size_t>& which, const RunnerDef& runner,
                                      const std::function<void(size_t, const nlohmann::json&, double)>& done,
                                      const std::function<void(size_t, size_t)>& progress = {});

/// Limits this process's address space to `mib` MiB (RLIMIT_AS, the soft limit; 0: no change): the
/// worker's memory limit. Does nothing under AddressSanitizer, whose shadow memory needs terabytes.
void set_memory_limit(double mib);

/// The request a worker reads for an item (one JSON line), and the item it describes.
nlohmann::json item_request(const SuiteItem& item);
SuiteItem item_from_request(const nlohmann::json& request);
/// `liftcheck worker`: reads requests from stdin, writes one record per line; stray output of the
/// engines goes to stderr.
int worker_main();

/// Gives each item that is the same as an earlier one that item's record (a point's without traces).
void fill_duplicates(const SuitePlan& plan, std::map<std::string, nlohmann::json>& records);

/// The records of the runs that judge the drive item `maker` made, by item index: from its record's
/// "shared" list, or error records saying what became of the maker where the list is missing.
std::vector<std::pair<size_t, nlohmann::json>> shared_records(const SuitePlan& plan, size_t maker, const nlohmann::json& record);
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
nlohmann::json suite_results(const SuitePlan& plan, std::map<std::string, nlohmann::json>& records, const nlohmann::json& context);

/// Whether `name` matches any of the globs (--filter).
bool matches_any(const std::vector<std::string>& globs, const std::string& name);

}  // namespace liftcheck
