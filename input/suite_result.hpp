// A suite's results, typed: its context, its runs (input/run_result.hpp), the sweeps, the outcome
// grid and the speed-accuracy map assembled from their points, the report's files and the
// comparison with a baseline. results.json is this encoded (input/results_codec.hpp); every page,
// summary and diff is built from it and recomputes what it shows (input/standing.hpp).
#pragma once

#include <cmath>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "input/params.hpp"
#include "input/run_result.hpp"

namespace liftcheck {

/// A setting a configuration declares (--set), as the record shows it.
struct KnobInfo {
  std::string key;
  Vehicle vehicle = Vehicle::kCar;
  std::string default_text, help, kind;  ///< kind: "integer", "real" or "choice"
  std::string role;                      ///< "", "solver_iterations" or "damping"
  double min = NAN, max = NAN;           ///< numeric knobs
  bool min_exclusive = false;
  std::vector<std::string> choices;  ///< choices
};

/// A configuration as the suite ran it.
struct EngineContext {
  std::string name, library, version, description, color;
  bool is_reference = false;
  std::vector<Vehicle> vehicles;
  std::vector<std::string> features;  ///< what it declares it has (engines/features.hpp names)
  /// Its fixed settings and its knobs with their defaults, as text, in name order.
  std::vector<std::pair<std::string, std::string>> settings;
  std::vector<KnobInfo> knobs;
  std::string registration, adapter;  ///< an outside engine's registration file and adapter ("" in process)
};

/// liftcheck tune's committed answer for one scenario and configuration (data/tune/table.json).
struct TuneEntry {
  std::vector<std::pair<std::string, std::string>> change;  ///< the settings changed from the defaults
  bool passes = false, default_passes = false;
  double cost_ratio = NAN, worst_ratio = NAN, cost_ms_per_s = NAN, default_cost_ms_per_s = NAN, model_cost = NAN;
  int runs = 0, budget = 0, unmade = 0;
  std::string fingerprint;
};

struct Machine {
  std::string host, os, compiler;
  int cpus = 0;
};

/// Who ran the suite, on what, and where its time went.
struct SuiteContext {
  std::string version, commit, date;
  Machine machine;
  std::vector<EngineContext> engines;  ///< in the suite's order
  double wall_s = 0.0, runs_s = 0.0, points_s = 0.0, worker_s = 0.0;
  /// Seconds inside the engines' own step calls (compiled in: around the step; outside: the
  /// adapter's own timing); NaN where not measured.
  double stepping_s = NAN;
  std::map<std::string, double> engine_s_by_part, engine_s_by_configuration, worker_s_by_part,
      worker_s_by_configuration, stepping_s_by_configuration;
  int jobs = 1;
  double timeout_s = 0.0, memory_limit_mib = 0.0;
  std::string outside_folder;
  bool outside_beside_binary = false;
  Overrides set;  ///< --set KEY=VALUE of the suite
  int merged_shards = 0;
  std::string errata;                           ///< models/ERRATA.md
  std::map<std::string, TuneEntry> tune_table;  ///< "SCENARIO CONFIG" -> answer

  const EngineContext* engine(const std::string& name) const;
};

/// A sweep point's figures of a metric it records ("metric:NAME").
struct PointFigures {
  double expected = NAN, measured = NAN, rel_error = NAN, abs_error = NAN;
  bool pass = false;
};

/// One point of a parameter sweep.
struct SweepPoint {
  double x = 0.0;
  Status status = Status::kError;
  std::string message;
  std::vector<std::string> failed;                ///< its counted metrics out of tolerance
  std::map<std::string, double> errors;           ///< their compared errors (NaN: not finite)
  std::map<std::string, PointFigures> metrics;    ///< the metrics the sweep records, by name
  std::map<std::string, nlohmann::json> details;  ///< the details the sweep records, by key
  bool fitted = false;                            ///< above the noise floor: in the slope's fit
  std::string known_failure;                      ///< its listing's reason ("" when not listed)
  /// The ratio of its worst counted metric to its tolerance (NaN for an error point).
  double worst_ratio = NAN;
};

/// A sweep's or the outcome grid's gate for one configuration.
struct Gate {
  bool pass = true;
  std::vector<std::string> problems;
  int points_pass = 0, points_known_failure = 0, points_error = 0, points_unexpected = 0;
  std::optional<std::pair<double, double>> slope_band;
};

struct SweepFit {
  double slope = NAN;  ///< NaN: too few points above the noise floor
  int points = 0;
  std::string known_failure;
};

struct SweepEngine {
  std::string engine;
  std::vector<SweepPoint> points;
  std::optional<SweepFit> fit;
  Gate gate;
};

/// A parameter sweep assembled from its points, with how it is plotted.
struct Sweep {
  std::string name, title, scenario, param;
  Overrides fixed;
  std::vector<std::string> record;  ///< "metric:NAME" or "detail:KEY"
  std::vector<SweepEngine> engines;
  std::string plot_kind = "errors", x_label, y_label;
  bool log_x = false;
  std::vector<std::pair<std::string, std::string>> curves;  ///< gnuplot expression, title
  std::optional<std::pair<double, std::string>> marker;     ///< x, label
  struct TimesX {
    std::string key;
    double per_x = 0.0, min = 0.0;
  };
  std::vector<TimesX> times_x;
  std::vector<std::string> unswept;  ///< configurations of the suite not in it, with why ("cannon: ...")
};

/// One case of the outcome grid on one configuration.
struct OutcomeCase {
  double a = 0.0, b = 0.0, T_s = 0.0;
  std::string path;
  bool reference = false;      ///< the reference's outcome: a collision
  std::optional<bool> engine;  ///< the configuration's (none: its run ended in an error)
  Status status = Status::kError;
  std::string message;
  double reference_t_contact_s = NAN, t_error_steps = NAN, reference_min_distance = NAN;
  bool near_boundary = false, known_failure = false;
  std::map<std::string, double> errors;
};

struct OutcomeEngine {
  std::string engine;
  int both_collide = 0, neither = 0, engine_only = 0, reference_only = 0;
  int errors = 0, runs_out_of_tolerance = 0, runs_known_failure = 0, near_boundary_cases = 0,
      unexplained_disagreements = 0;
  std::string known_failure;
  double worst_t_error_steps = 0.0;
  std::vector<OutcomeCase> cases;
  Gate gate;
};

/// The outcome grid: disks.linear over (a, b) and N's paths against the reference.
struct OutcomeSweep {
  std::string name, title, scenario;
  std::vector<double> grid_a, grid_b;
  std::vector<std::string> grid_path;
  std::vector<std::pair<std::string, std::string>> fixed;
  double T_max_s = 0.0, clearance_m = 0.0, after_s = 0.0, T_min_s = 0.0, near_boundary_m = 0.0;
  std::vector<OutcomeEngine> engines;
};

struct MapPoint {
  std::string knob;
  double value = 0.0;
  Status status = Status::kError;
  std::string message;
  double error = NAN, wall_s = 0.0, simulated_s = 0.0, cost_s_per_s = NAN;
  bool pareto = false;
  /// Whether the run passes the panel's scenario (every counted metric within tolerance).
  bool passes = false;
};

struct MapCurve {
  std::string engine;
  std::vector<MapPoint> points;
};

struct MapPanel {
  std::string scenario, error_label;
  std::vector<std::string> error_metrics;
  std::vector<MapCurve> curves;
};

/// The speed-accuracy map.
struct SpeedMap {
  std::string name, title;
  std::vector<double> dt_s;
  std::vector<int> iterations;
  std::vector<MapPanel> panels;
};

/// A scenario as the catalogue declares it, as much as the reports need.
struct ScenarioInfo {
  struct Param {
    std::string key, kind, default_text, unit, help;
    double min = NAN, max = NAN;  ///< a number's bounds where it has them (NaN: none)
    bool min_exclusive = false;
  };
  struct MetricInfo {
    std::string name, unit, help;
    TolKind kind = TolKind::kAbsolute;
    std::map<std::string, double> tolerance, floor;  ///< by role: "default", "reference"
    bool reference_only = false;
  };
  std::string name, summary, equations;
  Vehicle vehicle = Vehicle::kCar;
  std::vector<Param> params;
  std::vector<MetricInfo> metrics;
  std::vector<std::string> needs;  ///< the features it needs of a configuration
  bool negative_control = false;
  /// What the summary shows for it (Headline in scenarios/scenario.hpp).
  std::vector<std::string> headline_metrics;
  std::string headline_label, headline_unit;
  double headline_scale = 1.0;
  bool headline_per_step = false;
};

/// The simulated seconds the suite stepped, in all, by part and by configuration.
struct SimulatedBudget {
  double total_s = 0.0;
  std::map<std::string, double> by_part;
  std::map<std::string, std::map<std::string, double>> by_configuration;  ///< config -> part -> s
  std::map<std::string, double> configuration_total_s;                    ///< config -> s
};

/// A picture the report drew.
struct ReportFile {
  std::string group;  ///< a plot's group: a scenario or "sweeps"
  std::string scenario, engine, tag;
  std::string file, caption, alt;
};

/// What the report wrote and where its time went.
struct ReportInfo {
  std::vector<ReportFile> snapshots, strips, plots;
  std::vector<std::string> errors;
  std::string gl_version;
  double snapshots_s = 0.0, plots_s = 0.0, report_s = 0.0;
};

/// One finding of a comparison with a baseline.
struct DiffFinding {
  std::string scenario, engine;
  std::vector<std::string> settings_differ;
  std::string metric;             ///< worse, better, moved
  std::string from, to, message;  ///< regressions and fixes: the verdicts
  double base_ratio = NAN, head_ratio = NAN;
  nlohmann::json base_measured, head_measured;  ///< as written: a number or null
  std::string sweep;                            ///< a sweep point's or outcome case's finding: its sweep
};

struct ResultsDiff {
  std::vector<DiffFinding> regressions, fixed, worse, better, moved, added, removed;
  /// What fails the regression gate: regressions and worsened metrics.
  int problems() const { return static_cast<int>(regressions.size() + worse.size()); }
};

struct BaselineComparison {
  std::string file;
  double worse_factor = 0.0;
  ResultsDiff diff;
};

/// A share of a sharded suite: which share, of which plan.
struct ShardInfo {
  int index = 0, total = 0;
  std::size_t items = 0;
  nlohmann::json selection;  ///< SuitePlan::selection(), compared between shares as written
  std::vector<std::string> keys;
};

/// "ENGINE/PATH/a=A/b=B": a case of the outcome grid on one configuration.
std::string outcome_case_key(const std::string& engine, const OutcomeCase& c);
/// Each case's outcome on each configuration, by outcome_case_key.
std::map<std::string, std::optional<bool>> outcome_flags(const OutcomeSweep& o);

struct SuiteResults {
  SuiteContext context;
  std::vector<ScenarioInfo> scenarios;
  std::vector<RunResult> runs;
  /// The records of every sweep point, outcome case and map point, by item key (a point's record
  /// holds no traces): what the sweeps were assembled from, and what a baseline compares.
  std::map<std::string, RunResult> points;
  std::vector<Sweep> sweeps;
  std::optional<OutcomeSweep> outcomes;
  std::vector<SpeedMap> maps;
  SimulatedBudget simulated;
  std::optional<ReportInfo> report;
  std::optional<BaselineComparison> baseline;
  std::optional<ShardInfo> shard;
  /// Read from a baseline (its runs' decisive fields only): compared with, never rendered.
  bool is_baseline = false;
  /// A baseline's outcome grid: each case's collision outcome on each configuration, by
  /// outcome_case_key (none: the run ended in an error). A suite's own is in `outcomes`.
  std::map<std::string, std::optional<bool>> baseline_outcomes;

  const ScenarioInfo* scenario(const std::string& name) const;
  const RunResult* run(const std::string& scenario, const std::string& engine) const;
  /// The scenarios of its runs, in run order.
  std::vector<std::string> scenario_order() const;
};

}  // namespace liftcheck
