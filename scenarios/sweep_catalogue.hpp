// The sweeps' catalogue: which scenario each parameter sweep, the outcome sweep and the
// speed-accuracy map run, over which grid, and what they record and plot. The runs, the fits and
// the gates over these definitions are harness/sweeps.hpp.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "input/params.hpp"

namespace liftcheck {

/// What a sweep point records of its run, named in SweepDef::record as "metric:NAME" (the metric's
/// expected and measured values and errors) or "detail:KEY" (a value of the run's details).
struct RecordedField {
  enum Kind { kMetric, kDetail };
  Kind kind = kMetric;
  std::string name;
};
inline constexpr const char* kMetricPrefix = "metric:";
inline constexpr const char* kDetailPrefix = "detail:";
/// "metric:NAME" and "detail:KEY": a field's name in a sweep's record.
std::string metric_field(const std::string& name);
std::string detail_field(const std::string& key);
/// The field named `field` ("metric:NAME" or "detail:KEY"); std::logic_error for another name.
RecordedField recorded_field(const std::string& field);

/// One scenario run over a grid of one parameter on each engine.
struct SweepDef {
  std::string name;
  std::string title;
  std::string scenario;
  std::string param;  ///< the swept parameter
  std::vector<double> values;
  Overrides fixed;  ///< other parameters held for the whole sweep
  /// What each point records: metric_field(NAME) or detail_field(KEY) (RecordedField).
  std::vector<std::string> record;
  bool loglog_fit = false;  ///< fit log y against log x above the engine's noise floor
  std::string fit_y;        ///< the recorded quantity that is fitted ("detail:measured_size_m")
  std::string fit_noise;    ///< its error against the exact value, which defines the noise floor
  double marker = 0.0;      ///< an x value to mark on the plot (0: none)
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
  /// A parameter set to a multiple of the swept value at each point, and at least `min` (the speed
  /// sweep's drive: the same seconds of arc at every speed, not the same metres).
  struct Scaled {
    std::string key;
    double per_x = 1.0, min = 0.0;
  };
  std::vector<Scaled> times_x = {};
  /// Exact curves drawn under the points: a gnuplot expression in x and its title.
  std::vector<std::pair<std::string, std::string>> curves = {};
  /// Past the marker (the grip limit) a configuration with contact dynamics must slide: each point
  /// there must fail with the front circle opened by kSlideRadius or more, or a lateral contact
  /// slip of kSlideAcross_mps or more. A pass, or a failure in other metrics only, kept its grip.
  bool slide_past_marker = false;
  static constexpr double kSlideRadius = 0.01, kSlideAcross_mps = 0.1;
};

const std::vector<SweepDef>& sweep_catalogue();
/// The scenario the outcome sweep (harness/sweeps.hpp: outcome_runs) runs over its grid.
const std::string& outcome_sweep_scenario();

/// What a map point varies, as its record names it ("knob"): nothing (the exact model), dt, or the
/// solver's iteration count (the setting with SettingRole::kSolverIterations, whatever its key).
inline constexpr const char* kMapDefault = "default";
inline constexpr const char* kMapDt = "dt";
inline constexpr const char* kMapIterations = "iterations";

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
  std::vector<double> dt_s;     ///< at each configuration's default settings
  std::vector<int> iterations;  ///< at the scenario's default dt
};
const MapDef& speed_accuracy_map();

}  // namespace liftcheck
