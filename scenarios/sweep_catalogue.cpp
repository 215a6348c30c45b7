#include "scenarios/sweep_catalogue.hpp"

#include "scenarios/details.hpp"

#include <cmath>
#include <stdexcept>

namespace liftcheck {

std::string metric_field(const std::string& name) { return kMetricPrefix + name; }
std::string detail_field(const std::string& key) { return kDetailPrefix + key; }

RecordedField recorded_field(const std::string& field) {
  for (const auto& [prefix, kind] : {std::pair{std::string(kMetricPrefix), RecordedField::kMetric},
                                     std::pair{std::string(kDetailPrefix), RecordedField::kDetail}})
    if (field.rfind(prefix, 0) == 0) return {kind, field.substr(prefix.size())};
  throw std::logic_error("a sweep records '" + field + "': neither a metric_field nor a detail_field");
}

namespace {

/// The circle against its steering angle, the time step and the speed.
std::vector<SweepDef> circle_sweeps() {
  return {
      {.name = "radius_vs_beta",
       .title = "Circle radius error against steering angle (exact: appendix D, l/sin beta0 and l/tan beta0)",
       .scenario = "car.circle",
       .param = "beta",
       .values = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8},
       .record = {metric_field("front_radius"), metric_field("rear_radius")},
       .plot = "values",
       .x_label = "beta_0 [rad]",
       .y_label = "relative radius error (front solid, rear dashed)",
       .curves = {{"1.0/sin(x)", "l/sin(beta_0)"}, {"1.0/tan(x)", "l/tan(beta_0)"}}},
      {.name = "error_vs_dt",
       .title = "Front circle radius error against the engine time step",
       .scenario = "car.circle",
       .param = "dt",
       .values = {0.0005, 0.001, 0.002, 0.005, 0.01},
       .record = {metric_field("front_radius"), metric_field("final_offset")},
       .x_label = "dt [s]",
       .y_label = "relative error of the front radius",
       .log_x = true},
      // mu = 0.3 on the 3.38 m circle: v^2/(r g) reaches mu at sqrt(0.3 * 9.81 * 3.3839) = 3.155 m/s.
      // Each point drives 6 s of the cruise speed's travel, and at least car.circle's 10 m (10 m at 1
      // m/s, 24 m at 4 m/s; after a ramp of v / (1 m/s^2)): the time for a creep or a slide to show
      // at every speed, not the same 40 m (80 s at 0.5 m/s). Shorter drives let the start weigh on
      // the fitted radius (4 m at 0.5 m/s: mujoco's error 9.4e-4 against 1.5e-4 at 40 m); at 6 s
      // every compiled-in configuration's car slides at 3.5 m/s (front radius +4.9% or more, lateral
      // slip 0.16 m/s or more), where at 5 s with ramps of 5.5 s the quick step's fell under the slide
      // gate. From 1 m/s, then every 0.5 m/s from car.circle's 2 m/s (0.5 and 1.5 m/s, far below the
      // grip limit as 1 m/s is, took 31 s of the sweep's 112 per configuration). The ramps stay at
      // 1 m/s^2: mu = 0.3 holds the front wheel's 24 kg share of the car to 70 N, short of the 92 N
      // that car.circle's 2 m/s^2 would ask of it.
      {.name = "error_vs_speed",
       .title = "Front circle radius error against speed (mu = 0.3)",
       .scenario = "car.circle",
       .param = "speed",
       .values = {1.0, 2.0, 2.5, 3.0, 3.5, 4.0},
       .fixed = {{"mu", "0.3"}, {"accel", "1.0"}},
       .record = {metric_field("front_radius"), metric_field("slip_across_max"), detail_field(detail_key::kGripUse)},
       .marker = std::sqrt(0.3 * 9.81 / std::sin(0.3)),
       .marker_label = "v^2/(r g) = mu",
       .x_label = "speed [m/s]",
       .y_label = "relative error of the front radius",
       .times_x = {{.key = "drive", .per_x = 6.0, .min = 10.0}},
       .slide_past_marker = true},
  };
}

/// The parking cycles' holonomy against their size (its order in eps).
std::vector<SweepDef> holonomy_sweeps() {
  return {
      {.name = "holonomy_vs_eps",
       .title = "Simple parking cycle: holonomy against eps (slope 2)",
       .scenario = "car.cycle",
       .param = "eps",
       .values = {0.01, 0.02, 0.05, 0.1, 0.2, 0.4},
       .record = {detail_field(detail_key::kHolonomySize), detail_field(detail_key::kMeasuredSize),
                  detail_field(detail_key::kHolonomyError)},
       .loglog_fit = true,
       .fit_y = detail_field(detail_key::kMeasuredSize),
       .fit_noise = detail_field(detail_key::kHolonomyError),
       .slope_expected = 2.0,
       .slope_band = 0.05,
       .plot = "sizes",
       .x_label = "eps [rad]",
       .y_label = "net shift of the tie rod [m]",
       .param_keys = {"eps_alpha", "eps_beta"}},  // the simple cycle takes its two steps separately
      {.name = "holonomy_iterated_vs_eps",
       .title = "Iterated cycle (5.8): holonomy against eps (slope 4)",
       .scenario = "car.iterated",
       .param = "eps",
       .values = {0.05, 0.1, 0.2, 0.3, 0.5, 0.7},
       .record = {detail_field(detail_key::kHolonomySize), detail_field(detail_key::kMeasuredSize),
                  detail_field(detail_key::kHolonomyError)},
       .loglog_fit = true,
       .fit_y = detail_field(detail_key::kMeasuredSize),
       .fit_noise = detail_field(detail_key::kHolonomyError),
       .slope_expected = 4.0,
       .slope_band = 0.1,
       .plot = "sizes",
       .x_label = "eps [rad]",
       .y_label = "net shift of the tie rod [m]"},
  };
}

/// The circle against the masses of the bodies the chassis carries.
std::vector<SweepDef> mass_sweeps() {
  return {
      // The steering knuckle's mass between the 40 kg chassis and the 2 kg wheel: from a real car's
      // proportions (as heavy as the wheel, the default) down to the 0.05 kg liftcheck built before,
      // mass ratios of 40 and 800 along the chain, which iterative solvers are known to struggle with.
      {.name = "knuckle_mass",
       .title = "Circle against the steering knuckle's mass (chassis 40 kg, wheels 2 kg)",
       .scenario = "car.circle",
       .param = "knuckle_mass",
       .values = {0.05, 0.2, 0.5, 2.0},
       .record = {metric_field("front_radius"), metric_field("heading_residual"), metric_field("slip_across_max")},
       .x_label = "knuckle mass [kg]",
       .y_label = "relative error of the front radius",
       .log_x = true},
      // Every wheel and knuckle together against the 40 kg chassis: from 0.5 kg (a chassis 80 times
      // each light body, the heavy-on-light chain iterative solvers are known to find hard) through
      // the default 2 kg to 20 kg (a ratio of 2). The exact lift depends on no mass, so every point
      // has the same reference: what moves is the engine's solver.
      {.name = "mass_ratio",
       .title = "Circle against the wheels' and knuckles' mass (chassis 40 kg)",
       .scenario = "car.circle",
       .param = "wheel_mass",
       .values = {0.5, 2.0, 5.0, 10.0, 20.0},
       .record = {metric_field("front_radius"), metric_field("rear_radius"), metric_field("slip_along_max"),
                  metric_field("slip_across_max"), metric_field("realized_lift_error")},
       .x_label = "mass of each wheel and each knuckle [kg]",
       .y_label = "relative error of the front radius",
       .log_x = true,
       .param_keys = {"wheel_mass", "knuckle_mass"}},
  };
}

}  // namespace

const std::vector<SweepDef>& sweep_catalogue() {
  static const std::vector<SweepDef> all = [] {
    std::vector<SweepDef> v;
    for (auto family : {circle_sweeps, holonomy_sweeps, mass_sweeps})
      for (SweepDef& d : family()) v.push_back(std::move(d));
    return v;
  }();
  return all;
}

const std::string& outcome_sweep_scenario() {
  static const std::string s = "disks.linear";
  return s;
}

const MapDef& speed_accuracy_map() {
  static const MapDef m = {
      .title =
          "Speed against accuracy: error against the exact reference and wall-clock cost per simulated second, "
          "over dt (0.5 to 10 ms) and solver iterations (5 to 200)",
      .panels = {{.scenario = "car.circle",
                  .error_metrics = {"front_radius", "rear_radius"},
                  .error_label = "relative error of the circle radii"},
                 {.scenario = "car.cycle",
                  .error_metrics = {"dx", "dy", "dphi"},
                  .error_label = "relative error of the holonomy"}},
      // From 0.5 ms: a 0.25 ms point cost as much as the other five together (280 of 590 worker
      // seconds of the map with the npm engines) and no verdict reads the map.
      .dt_s = {0.0005, 0.001, 0.002, 0.005, 0.01},
      .iterations = {5, 10, 20, 50, 100, 200},
  };
  return m;
}

}  // namespace liftcheck
