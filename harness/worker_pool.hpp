// The suite's items run in worker processes (`liftcheck worker`), `jobs` at once: an engine that
// hangs, crashes or ends its process is an error record, never the suite's end.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <vector>

#include "harness/suite_plan.hpp"

namespace liftcheck {

/// Runs one item: the full run record for a run, point_record for a point (its drawn traces
/// thinned: what results.json keeps). An engine's or a scenario's exception becomes an error record.
RunResult run_item(const SuiteItem& item);

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
  std::string exe;  ///< the liftcheck executable (empty: /proc/self/exe)
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
std::vector<RunResult> run_items(const SuitePlan& plan, const std::vector<size_t>& which, const RunnerDef& runner,
                                 const std::function<void(size_t, const RunResult&, double)>& done,
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

/// Writes all of `text` to `fd` (a request to a worker, a record from one); false when it cannot.
bool write_all(int fd, const std::string& text);

/// The error record of `item` (a run's or a point's) saying `message`.
RunResult error_record(const SuiteItem& item, const std::string& message);

}  // namespace liftcheck
