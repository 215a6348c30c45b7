// A scenario is data (parameters, metric definitions with per-engine tolerances) plus one function.
#pragma once

#include <cmath>
#include <functional>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engines/vehicle.hpp"
#include "input/params.hpp"
#include "input/run_result.hpp"    // Metric, TolKind
#include "input/suite_result.hpp"  // ScenarioInfo
#include "input/vehicle.hpp"
#include "scenarios/details.hpp"

namespace liftcheck {

/// Whose tolerance a metric's definition gives: the exact model's (the reference configuration) or
/// every engine's.
enum class TolRole { kReference, kDefault };
/// "reference" or "default", as results.json names the role.
const char* to_string(TolRole role);

/// A metric's definition: what it measures and how close each engine must come.
struct MetricDef {
  std::string name;
  std::string unit;
  TolKind kind = TolKind::kRelative;
  /// Tolerance by role: the exact model's, every engine's.
  std::map<TolRole, double> tolerance;
  std::string help;
  /// Absolute floor by role (relative metrics only): an absolute error at or below it
  /// passes, for quantities that can be tiny (round-off of a 1e-9 m holonomy is not an error).
  std::map<TolRole, double> floor = {};
  /// A tolerance that is the round-off floor of the engine's own numbers: its bookkeeping against
  /// itself (where it put N, what its contacts report against its bodies) or a free step against
  /// its command: it scales with the precision the engine declares (bookkeeping_factor in
  /// engines/engine.hpp). Physics tolerances do not.
  bool bookkeeping = false;
  /// A check of a paper's approximation (a leading-order formula against the exact model): the
  /// reference's business, shown for the other engines but not counted for them.
  bool reference_only = false;

  /// The tolerance (floor) of `role`, the default's where the role has none (a floor: 0 without one).
  double tolerance_for(TolRole role) const;
  double floor_for(TolRole role) const;
};

/// One value a scenario function measured, with the value the theory expects.
struct Measurement {
  double expected = 0.0;
  double measured = 0.0;
  /// Relative errors are abs_error / scale; 0 means |expected|.
  double scale = 0.0;
  /// The engine's tolerance is multiplied by this (for leading-order predictions whose error
  /// shrinks with eps, the multiplier is eps).
  double tolerance_factor = 1.0;
  /// Expected and measured come from the same computation (e.g. a model that reports the
  /// commanded shape as its realized one): shown, never counted as a pass.
  bool informational = false;
};

/// What a scenario function returns: measurements by metric name, plus details (traces, fitted
/// values) kept in the record; those the reports and sweeps read are under the keys of
/// scenarios/details.hpp (detail_key).
struct Outcome {
  std::map<std::string, Measurement> values;
  nlohmann::json details = nlohmann::json::object();
};

/// The figure a scenario is read by at a glance: the engine's own error on the quantity the
/// scenario is about (a radius, a holonomy against the exact one, a creep, a contact time, a
/// penetration), never a check of the paper's leading-order approximation. The shown value is the
/// largest compared error (relative or absolute, by the metric's kind) among `metrics`, times
/// `scale`, or, with `per_step`, the absolute error over the run's dt.
struct Headline {
  std::vector<std::string> metrics;
  std::string label;  ///< "radius error", "holonomy error", "creep", ...
  std::string unit;   ///< unit of the shown figure: "" (a ratio), "mm", "µm/s", "steps"
  double scale = 1.0;
  bool per_step = false;
};

/// One car drive that more than one scenario judges (car.slip and car.beyond-grip judge the same
/// circle past the grip limit): `drive` makes it and gives its full outcome, `judge` this
/// scenario's outcome from that. A scenario with one runs `judge(drive)` when it runs alone; a
/// suite that runs several scenarios judging the same drive (same name, configuration, parameters
/// and settings) makes it once.
struct SharedDrive {
  std::string name;
  std::function<Outcome(const Params&, CarEngine&)> drive;
  std::function<Outcome(const Params&, const Outcome&)> judge;
};

struct Scenario {
  std::string name;
  Vehicle vehicle = Vehicle::kCar;  ///< the engine must offer make_car or make_disks
  std::string summary;              ///< what it checks
  std::string equations;            ///< the paper's equations it exercises
  std::vector<ParamSpec> params;
  std::vector<MetricDef> metrics;
  std::function<Outcome(const Params&, CarEngine&)> run_car;
  std::function<Outcome(const Params&, DiskEngine&)> run_disks;
  /// Set where run_car is a judgement of a drive other scenarios judge too.
  std::optional<SharedDrive> shared_drive;
  /// Runs only on engines with contact dynamics (skipped elsewhere).
  bool needs_contact_dynamics = false;
  /// Runs only on engines that brake the rear wheels (EngineInfo::brakes; skipped elsewhere).
  bool needs_brakes = false;
  /// A negative control: its comparison is meant to fail; validation counts a fail as expected.
  bool negative_control = false;
  /// What the summary shows for this scenario (every metric named in it is one of `metrics`).
  Headline headline = {};

  const MetricDef* metric(const std::string& name) const;
  /// The scenario as the results record it.
  ScenarioInfo info() const;
};

/// The vehicles a run may drive, owned by whoever runs it; only the one of the scenario's kind is
/// made (an engine's car, a probe, a recorder).
struct VehicleMakers {
  std::function<CarEngine&()> car;
  std::function<DiskEngine&()> disks;
};

/// A scenario's outcome on its vehicle, with the vehicle's clocks.
struct Driven {
  Outcome outcome;
  double simulated_s = 0.0;  ///< simulated time the vehicle stepped, s
  double engine_s = NAN;     ///< the engine's own stepping time as it reports it, s
};

/// Runs `scenario` on the vehicle of its kind, made by `make`: the one place that dispatches on a
/// scenario's vehicle (the runner, the probe of a run's inputs and `liftcheck path` go through it).
Driven drive_vehicle(const Scenario& scenario, const Params& params, const VehicleMakers& make);

// kMaxRunSteps and kMaxRunSamples, what one run may ask for: engines/vehicle.hpp.

/// InputError naming dt or sample_dt, the count it asks for and its lower bound for this
/// duration, when duration_s / dt_s > kMaxRunSteps or duration_s / sample_dt_s > kMaxRunSamples.
void check_run_budget(double duration_s, double dt_s, double sample_dt_s);

/// The catalogue, in a fixed order.
const std::vector<Scenario>& scenarios();
const Scenario* find_scenario(const std::string& name);

}  // namespace liftcheck
