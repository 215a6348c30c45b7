// Parameter sweeps for the report: one scenario run over a grid of one parameter on each engine,
// stored as flat points in results.json ("sweeps"), with fitted slopes where the sweep asks.
#pragma once

#include <cmath>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engines/engine.hpp"
#include "harness/expectations.hpp"
#include "harness/params.hpp"
#include "harness/runner.hpp"

namespace liftcheck {

struct SweepDef {
  std::string name;
  std::string title;
  std::string scenario;
  std::string param;             ///< the swept parameter
  std::vector<double> values;
  Overrides fixed;               ///< other parameters held for the whole sweep
  /// What each point records: "metric:NAME" (expected, measured, errors) or "detail:KEY".
  std::vector<std::string> record;
  bool loglog_fit = false;       ///< fit log y against log x above the engine's noise floor
  std::string fit_y;             ///< the recorded quantity that is fitted ("detail:measured_size_m")
  std::string fit_noise;         ///< its error against the exact value, which defines the noise floor
  double marker = 0.0;           ///< an x value to mark on the plot (0: none)
  std::string marker_label;
  /// The gate on the fit: the fitted slope must lie within slope_band of slope_expected.
  double slope_expected = 0.0;
  double slope_band = 0.0;
  /// How the report plots it: "values" (the recorded metrics' measured values, front and rear, over
  /// the exact curves), "sizes" (measured against exact size, log-log) or "errors" (the first
  /// recorded metric's relative error, log y).
  std::string plot = "errors";
  std::string x_label, y_label;
  bool log_x = false;
  /// The scenario parameters the swept value sets (empty: `param` itself).
  std::vector<std::string> param_keys = {};
  /// Exact curves drawn under the points: a gnuplot expression in x and its title.
  std::vector<std::pair<std::string, std::string>> curves = {};
  /// Past the marker (the grip limit) a configuration with contact dynamics must slide: each point
  /// there must fail with the front circle opened by kSlideRadius or more, or a lateral contact
  /// slip of kSlideAcross_mps or more. A pass, or a failure in other metrics only, kept its grip.
  bool slide_past_marker = false;
  static constexpr double kSlideRadius = 0.01, kSlideAcross_mps = 0.1;
};

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
  std::string pattern;  ///< kError: part of the message; kFit: start of the fit problem
  int points_max = 0;   ///< kAnywhere
  int disagreements_max = 0;  ///< kAnywhere of the outcome sweep: outcome disagreements away from the boundary allowed
  std::string reason, measured;
};
const std::vector<KnownSweepFailure>& known_sweep_failures();

/// The gate of one sweep entry (one engine's points and fit): every point passes its tolerances
/// unless listed as a known failure (and then it must fail), no point is an error, and the fit
/// lies in its band. Adds "gate" {"pass", "problems", counts} to the entry and returns pass.
bool gate_sweep_entry(const SweepDef& sweep, nlohmann::json& entry);

const std::vector<SweepDef>& sweep_catalogue();
/// The scenario the outcome sweep (run_outcome_sweep) runs over its grid.
const std::string& outcome_sweep_scenario();

/// One run that a sweep, the outcome sweep or the map asks for: the unit validate schedules,
/// shards and merges. `key` names it uniquely and stably ("sweep/radius_vs_beta/ode/x=0.1").
struct PointRun {
  std::string key;
  const Scenario* scenario = nullptr;
  const EngineInfo* engine = nullptr;
  Overrides overrides;
};
/// A point run's record as stored (results.json "points"): the run record without its traces,
/// which is all the sweeps, the outcome sweep and the map read.
nlohmann::json point_record(const RunRecord& r);
/// The same from a stored run record: its traces left out.
nlohmann::json point_record(nlohmann::json record);
/// The stored record of a point run by its key (throws std::out_of_range when it is missing).
using RecordLookup = std::function<const nlohmann::json&(const std::string& key)>;

/// The runs of one sweep on the given engines (engines that cannot run the scenario are left
/// out), and the sweep assembled from their records: the points, the fit and each engine's gate.
std::vector<PointRun> sweep_runs(const SweepDef& sweep, const std::vector<const EngineInfo*>& engines);
nlohmann::json assemble_sweep(const SweepDef& sweep, const std::vector<const EngineInfo*>& engines, const RecordLookup& record);

/// disks.linear over a grid of (a, b) and N's paths: each engine's collision outcome against the
/// analytic one (a confusion matrix), contact-time errors in steps, and the cases near the boundary
/// of the collision domain (analytic closest approach within `near_m` of contact) labelled. The
/// runs include the reference's on every case, whether or not the reference is among `engines`.
std::vector<PointRun> outcome_runs(const std::vector<const EngineInfo*>& engines);
nlohmann::json assemble_outcome_sweep(const std::vector<const EngineInfo*>& engines, const RecordLookup& record, double near_m = 0.01);

/// The speed-accuracy map: scenarios run on every configuration over the engine step dt and, for
/// configurations with an iterative solver (a car setting "iterations"), over the iteration count;
/// each point's error against the exact reference and its cost in wall-clock seconds per simulated
/// second, with the Pareto front over all configurations marked. Exploration, not a gate.
struct MapDef {
  std::string name = "speed_accuracy";
  std::string title;
  struct Panel {
    std::string scenario;
    std::vector<std::string> error_metrics;  ///< the point's error: the largest relative error among these
    std::string error_label;
  };
  std::vector<Panel> panels;
  std::vector<double> dt_s;         ///< at each configuration's default settings
  std::vector<int> iterations;      ///< at the scenario's default dt
};
const MapDef& speed_accuracy_map();
std::vector<PointRun> map_runs(const MapDef& map, const std::vector<const EngineInfo*>& engines);
nlohmann::json assemble_map(const MapDef& map, const std::vector<const EngineInfo*>& engines, const RecordLookup& record);

}  // namespace liftcheck
