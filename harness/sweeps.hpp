// Parameter sweeps for the report: one scenario run over a grid of one parameter on each engine,
// stored as flat points in results.json ("sweeps"), with fitted slopes where the sweep asks.
#pragma once

#include <cmath>
#include <functional>
#include <string>
#include <vector>

#include "engines/engine.hpp"
#include "harness/expectations.hpp"
#include "input/params.hpp"
#include "harness/runner.hpp"
#include "input/suite_result.hpp"
#include "scenarios/sweep_catalogue.hpp"

namespace liftcheck {

/// A sweep's known failure, reviewed data (harness/expectations.json "sweep_points"): the reason
/// in one sentence and the measured figure. Every kind must still fail as listed, so the file stays
/// true, and no worse than listed, so a regression of a known failure is caught.
struct KnownSweepFailure {
  enum Kind {
    kPoint,     ///< "points": [{"x", "metrics"}]: each point fails, only in its metrics, no worse than their ceilings
    kError,     ///< "x" with "error_contains": these points end in an error whose message contains it
    kFit,       ///< "fit_problem": the slope gate fails with a problem starting with it
    kAnywhere,  ///< no "x": up to "points_max" points may fail in "metrics" (ceilings), at least one must
  };
  std::string sweep, engine;
  Kind kind = kPoint;
  double x = NAN;
  Ceilings metrics;
  std::string pattern;        ///< kError: part of the message; kFit: start of the fit problem
  int points_max = 0;         ///< kAnywhere
  int disagreements_max = 0;  ///< kAnywhere of the outcome sweep: outcome disagreements away from the boundary allowed
  std::string reason, measured;
};
const std::vector<KnownSweepFailure>& known_sweep_failures();

/// The gate of one sweep entry (one engine's points and fit): every point passes its tolerances
/// unless listed as a known failure (and then it must fail), no point is an error, and the fit
/// lies in its band. Sets the entry's gate (and each listed point's reason) and returns its pass.
bool gate_sweep_entry(const SweepDef& sweep, SweepEngine& entry);

/// The parameters of `s`'s point at x: its fixed ones, the swept one (the cycle scenario's eps
/// sets eps_alpha and eps_beta) and those scaled with x.
Overrides point_overrides(const SweepDef& s, double x);

/// One run that a sweep, the outcome sweep or the map asks for: the unit validate schedules,
/// shards and merges. `key` names it uniquely and stably ("sweep/radius_vs_beta/ode/x=0.1").
struct PointRun {
  std::string key;
  const Scenario* scenario = nullptr;
  const EngineInfo* engine = nullptr;
  Overrides overrides;
};
/// A point run's record as stored (results.json "points"): the run record with its scalar details only,
/// which is all the sweeps, the outcome sweep and the map read.
void trim_to_point(RunResult& r);
/// The stored record of a point run by its key (throws std::out_of_range when it is missing).
using RecordLookup = std::function<const RunResult&(const std::string& key)>;

/// The runs of one sweep on the given engines (engines that cannot run the scenario are left
/// out), and the sweep assembled from their records: the points, the fit and each engine's gate.
std::vector<PointRun> sweep_runs(const SweepDef& sweep, const std::vector<const EngineInfo*>& engines);
Sweep assemble_sweep(const SweepDef& sweep, const std::vector<const EngineInfo*>& engines, const RecordLookup& record);

/// disks.linear over a grid of (a, b) and N's paths: each engine's collision outcome against the
/// analytic one (a confusion matrix), contact-time errors in steps, and the cases near the boundary
/// of the collision domain (analytic closest approach within `near_m` of contact) labelled. The
/// runs include the reference's on every case, whether or not the reference is among `engines`.
std::vector<PointRun> outcome_runs(const std::vector<const EngineInfo*>& engines);
/// The outcome grid's horizon (linear_outcome_horizon_s): every case may run t_max_s (the last exact
/// contact of the grid starts at 7.5 s); a case stops after_s after the exact motion ((43), then
/// the contact response after a contact) last keeps the disks within clearance_m of touching, and
/// runs at least t_min_s; a contact that lasts to t_max_s keeps it. An engine that could touch N
/// after the horizon fails its run inside it: before a first contact its M must stay within 1e-2 m
/// of (43) (path_error; 0.5 m is 50 times that), after one within a few steps' travel of the exact
/// response (contact_path_error), and a contact that does not release when the exact one does
/// fails contact_duration by the 0.5 s left after the release at least.
struct OutcomeHorizon {
  double t_max_s = 8.0, clearance_m = 0.5, after_s = 0.5, t_min_s = 1.0;
};
inline constexpr OutcomeHorizon kOutcomeHorizon{};
OutcomeSweep assemble_outcome_sweep(const std::vector<const EngineInfo*>& engines, const RecordLookup& record,
                                    double near_m = 0.01);

/// The speed-accuracy map's runs (configurations with an iterative solver also over the iteration
/// count) and the map assembled from their records, with the Pareto front marked.
/// `all_points`: validate --all-points (a configuration registered for its runs only gets the map's
/// axes too; without it, its default run is its one point).
std::vector<PointRun> map_runs(const MapDef& map, const std::vector<const EngineInfo*>& engines, bool all_points);
SpeedMap assemble_map(const MapDef& map, const std::vector<const EngineInfo*>& engines, const RecordLookup& record,
                      bool all_points);

}  // namespace liftcheck
