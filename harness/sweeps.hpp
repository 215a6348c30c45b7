// Parameter sweeps for the report: one scenario run over a grid of one parameter on each engine,
// stored as flat points in results.json ("sweeps"), with fitted slopes where the sweep asks.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engines/engine.hpp"
#include "harness/params.hpp"

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
};

/// A sweep point known to fail on an engine, reviewed data (harness/expectations.json): the
/// reason in one sentence and the measured figure. A listed point that passes is unexpected.
struct KnownSweepFailure {
  std::string sweep, engine;
  double x;                          ///< the point (when every_x is false)
  std::vector<std::string> metrics;  ///< the metrics that fail; a point failing any other is unexpected
  std::string reason, measured;
  /// No "x" in the file: any point may fail in `metrics`, and at least one must.
  bool every_x = false;
  /// "fit_fails": the fitted slope misses its band (or has too few points), and must.
  bool fit_fails = false;
  /// "error": the listed points end as errors (the engine blows up there), and must.
  bool error = false;
};
const std::vector<KnownSweepFailure>& known_sweep_failures();

/// The gate of one sweep entry (one engine's points and fit): every point passes its tolerances
/// unless listed as a known failure (and then it must fail), no point is an error, and the fit
/// lies in its band. Adds "gate" {"pass", "problems", counts} to the entry and returns pass.
bool gate_sweep_entry(const SweepDef& sweep, nlohmann::json& entry);

const std::vector<SweepDef>& sweep_catalogue();

/// Runs one sweep on the given engines. Engines that cannot run the scenario are left out.
nlohmann::json run_sweep(const SweepDef& sweep, const std::vector<const EngineInfo*>& engines);

/// disks.linear over a grid of (a, b) and N's paths: each engine's collision outcome against the
/// analytic one (a confusion matrix), contact-time errors in steps, and the cases near the boundary
/// of the collision domain (analytic closest approach within `near_m` of contact) labelled.
nlohmann::json run_outcome_sweep(const std::vector<const EngineInfo*>& engines, double near_m = 0.01);

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
nlohmann::json run_map(const MapDef& map, const std::vector<const EngineInfo*>& engines);

}  // namespace liftcheck
