#include "scenarios/scenario.hpp"

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

namespace {

nlohmann::json by_role(const std::map<TolRole, double>& values) {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [role, v] : values) j[to_string(role)] = v;
  return j;
}

}  // namespace

nlohmann::json Metric::to_json() const {
  nlohmann::json j = {{"expected", expected},   {"measured", measured},
                      {"abs_error", abs_error}, {"rel_error", rel_error},
                      {"tolerance", tolerance}, {"tolerance_kind", kind == TolKind::kRelative ? "rel" : "abs"},
                      {"unit", unit},           {"pass", pass}};
  if (floor > 0.0) j["floor"] = floor;
  if (informational) j["informational"] = true;
  return j;
}

nlohmann::json Headline::to_json() const {
  return {{"metrics", metrics}, {"label", label}, {"unit", unit}, {"scale", scale}, {"per_step", per_step}};
}

const MetricDef* Scenario::metric(const std::string& n) const {
  for (const auto& m : metrics)
    if (m.name == n) return &m;
  return nullptr;
}

nlohmann::json Scenario::to_json() const {
  nlohmann::json ps = nlohmann::json::array();
  for (const auto& p : params) ps.push_back(p.to_json());
  nlohmann::json ms = nlohmann::json::array();
  for (const auto& m : metrics)
    ms.push_back({{"name", m.name},
                  {"unit", m.unit},
                  {"tolerance_kind", m.kind == TolKind::kRelative ? "rel" : "abs"},
                  {"tolerance", by_role(m.tolerance)},
                  {"floor", by_role(m.floor)},
                  {"help", m.help},
                  {"reference_only", m.reference_only}});
  return {{"name", name},
          {"vehicle", vehicle},
          {"summary", summary},
          {"equations", equations},
          {"params", ps},
          {"metrics", ms},
          {"needs_contact_dynamics", needs_contact_dynamics},
          {"needs_brakes", needs_brakes},
          {"negative_control", negative_control},
          {"headline", headline.to_json()}};
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
