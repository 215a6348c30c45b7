#include "scenarios/scenario.hpp"

#include <cmath>
#include <fmt/format.h>

namespace liftcheck {

void check_run_budget(double duration_s, double dt_s, double sample_dt_s) {
  const auto check = [&](const char* key, double step, double limit, const char* what) {
    if (!(duration_s / step <= limit))
      throw InputError(fmt::format(
          "parameter '{}' = {:g} s asks for {:.3g} {} over the run's {:g} s: at most {:g} ({} >= {:.3g} s here)", key,
          step, duration_s / step, what, duration_s, limit, key, duration_s / limit));
  };
  check("dt", dt_s, kMaxRunSteps, "engine steps");
  check("sample_dt", sample_dt_s, kMaxRunSamples, "recorded samples");
}

const char* to_string(TolRole role) { return role == TolRole::kReference ? "reference" : "default"; }

double MetricDef::tolerance_for(TolRole role) const {
  if (auto it = tolerance.find(role); it != tolerance.end()) return it->second;
  if (auto it = tolerance.find(TolRole::kDefault); it != tolerance.end()) return it->second;
  throw std::logic_error(fmt::format("metric '{}' has no tolerance for the role '{}'", name, to_string(role)));
}

double MetricDef::floor_for(TolRole role) const {
  if (auto it = floor.find(role); it != floor.end()) return it->second;
  if (auto it = floor.find(TolRole::kDefault); it != floor.end()) return it->second;
  return 0.0;
}

const MetricDef* Scenario::metric(const std::string& n) const {
  for (const auto& m : metrics)
    if (m.name == n) return &m;
  return nullptr;
}

namespace {

std::map<std::string, double> by_role(const std::map<TolRole, double>& values) {
  std::map<std::string, double> out;
  for (const auto& [role, v] : values) out[to_string(role)] = v;
  return out;
}

}  // namespace

ScenarioInfo Scenario::info() const {
  ScenarioInfo s;
  s.name = name;
  s.vehicle = vehicle;
  s.summary = summary;
  s.equations = equations;
  static const char* kinds[] = {"number", "integer", "vec2", "choice"};
  for (const auto& p : params)
    s.params.push_back({p.key, kinds[static_cast<int>(p.kind)], p.default_text, p.unit, p.help,
                        std::isfinite(p.min) ? p.min : NAN, std::isfinite(p.max) ? p.max : NAN, p.min_exclusive});
  for (const auto& m : metrics)
    s.metrics.push_back({m.name, m.unit, m.help, m.kind, by_role(m.tolerance), by_role(m.floor), m.reference_only});
  if (needs_contact_dynamics) s.needs.push_back("contact_dynamics");
  if (needs_brakes) s.needs.push_back("brakes");
  s.negative_control = negative_control;
  s.headline_metrics = headline.metrics;
  s.headline_label = headline.label;
  s.headline_unit = headline.unit;
  s.headline_scale = headline.scale;
  s.headline_per_step = headline.per_step;
  return s;
}

const Scenario* find_scenario(const std::string& name) {
  for (const auto& s : scenarios())
    if (s.name == name) return &s;
  return nullptr;
}

Driven drive_vehicle(const Scenario& scenario, const Params& params, const VehicleMakers& make) {
  if (scenario.vehicle == Vehicle::kDisks) {
    DiskEngine& disks = make.disks();
    Outcome outcome = scenario.run_disks(params, disks);
    return {std::move(outcome), disks.simulated_s(), disks.reported_engine_s()};
  }
  CarEngine& car = make.car();
  Outcome outcome = scenario.run_car(params, car);
  return {std::move(outcome), car.simulated_s(), car.reported_engine_s()};
}

}  // namespace liftcheck
