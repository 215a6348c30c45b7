#include "harness/runner.hpp"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace liftcheck {

Expectation expectation_of(const KnownFailure& k) {
  return {.ceilings = k.metrics, .error = k.error, .reason = k.reason, .measured = k.measured};
}

std::vector<Metric> score(const Scenario& scenario, TolRole role, const Outcome& outcome, double bookkeeping_factor) {
  std::vector<Metric> out;
  for (const MetricDef& def : scenario.metrics) {
    const auto it = outcome.values.find(def.name);
    if (it == outcome.values.end()) continue;  // a metric the scenario does not produce for these params
    const Measurement& v = it->second;
    Metric m;
    m.name = def.name, m.unit = def.unit, m.expected = v.expected, m.measured = v.measured, m.kind = def.kind;
    m.abs_error = std::abs(v.measured - v.expected);
    const double scale = v.scale > 0.0 ? v.scale : std::abs(v.expected);
    m.rel_error = scale > 0.0 ? m.abs_error / scale : (m.abs_error == 0.0 ? 0.0 : INFINITY);
    m.tolerance = def.tolerance_for(role) * v.tolerance_factor * (def.bookkeeping ? bookkeeping_factor : 1.0);
    const double err = m.compared_error();
    m.floor = def.kind == TolKind::kRelative ? def.floor_for(role) : 0.0;
    m.pass = (std::isfinite(err) && err <= m.tolerance) || (std::isfinite(m.abs_error) && m.abs_error <= m.floor);
    // A check of the paper's approximation measures the paper, not the engine: counted for the
    // reference alone.
    m.informational = v.informational || (def.reference_only && role != TolRole::kReference);
    out.push_back(m);
  }
  for (const auto& [name, v] : outcome.values)
    if (!scenario.metric(name))
      throw std::logic_error(fmt::format("scenario '{}' measured undeclared metric '{}'", scenario.name, name));
  return out;
}

KeyOwner key_owner(const Scenario& scenario, const EngineInfo& engine, const std::string& key) {
  if (std::any_of(scenario.params.begin(), scenario.params.end(), [&](const ParamSpec& p) { return p.key == key; }))
    return KeyOwner::kParameter;
  if (std::any_of(engine.knobs.begin(), engine.knobs.end(),
                  [&](const SettingSpec& k) { return k.key == key && k.vehicle == scenario.vehicle; }))
    return KeyOwner::kSetting;
  return KeyOwner::kNeither;
}

namespace {

/// Stands in for an engine: the scenario's checks before its first engine call have passed when
/// it is called.
struct ProbeStop {};

class ProbeCar final : public CarEngine {
 public:
  void reset(const CarSetup&, const car::Config&) override { throw ProbeStop{}; }
  std::vector<car::TimedConfig> drive(const car::BasePath&) override { throw ProbeStop{}; }
  std::vector<WheelSlip> slip() const override { throw ProbeStop{}; }
  double simulated_s() const override { return 0.0; }
};

class ProbeDisks final : public DiskEngine {
 public:
  DiskRun run(const DiskSetup&, const DiskProblem&) override { throw ProbeStop{}; }
  double simulated_s() const override { return 0.0; }
};

/// The InputError for `key`, a setting of other configurations but not of `engine` here.
[[noreturn]] void throw_not_a_setting(const Scenario& scenario, const EngineInfo& engine, const std::string& key,
                                      const std::vector<std::string>& owners) {
  std::vector<std::string> names;
  for (const SettingSpec& k : engine.knobs)
    if (k.vehicle == scenario.vehicle) names.push_back(k.key);
  throw InputError(
      fmt::format("engine '{}' has no setting '{}' for {} (its settings there: {}; '{}' is a setting of {})",
                  engine.name, key, scenario.vehicle == Vehicle::kCar ? "cars" : "disks",
                  names.empty() ? "none" : fmt::format("{}", fmt::join(names, ", ")), key, fmt::join(owners, ", ")));
}

/// What a run of `scenario` with these resolved parameters asks of a configuration.
Needs needs_of(const Scenario& scenario, const Params& params) {
  return {.vehicle = scenario.vehicle,
          .four_wheels = scenario.vehicle == Vehicle::kCar && params.has("wheels") && params.str("wheels") == "4",
          .contact_dynamics = scenario.needs_contact_dynamics,
          .brakes = scenario.needs_brakes};
}

}  // namespace

std::pair<Overrides, Settings> split_settings(const Scenario& scenario, const EngineInfo& engine,
                                              const Overrides& overrides) {
  Overrides params, knob_overrides;
  for (const auto& [key, value] : overrides) {
    switch (key_owner(scenario, engine, key)) {
      case KeyOwner::kParameter:
        params.emplace_back(key, value);
        break;
      case KeyOwner::kSetting:
        knob_overrides.emplace_back(key, value);
        break;
      case KeyOwner::kNeither: {
        std::vector<std::string> owners;  // the configurations that do have it, for this vehicle or another
        for (const EngineInfo& other : engines())
          for (const SettingSpec& k : other.knobs)
            if (k.key == key && std::find(owners.begin(), owners.end(), other.name) == owners.end())
              owners.push_back(other.name);
        if (!owners.empty()) throw_not_a_setting(scenario, engine, key, owners);
        params.emplace_back(key, value);  // unknown: Params::resolve names it
      }
    }
  }
  return {params, resolve_settings(engine, scenario.vehicle, knob_overrides, scenario.name)};
}

ResolvedRun resolve_run(const Scenario& scenario, const EngineInfo& engine, const Overrides& overrides) {
  auto [params, settings] = split_settings(scenario, engine, overrides);
  return {.scenario = &scenario,
          .engine = &engine,
          .params = Params::resolve(scenario.params, params, scenario.name),
          .settings = std::move(settings)};
}

nlohmann::json resolved_values(const ResolvedRun& run) {
  return {{"params", run.params.to_json()}, {"settings", run.settings.to_json()}};
}

ResolvedRun resolved_from_values(const Scenario& scenario, const EngineInfo& engine, const nlohmann::json& values) {
  return {.scenario = &scenario,
          .engine = &engine,
          .params = Params::from_json(values.at("params")),
          .settings = Settings::from_json(values.at("settings"))};
}

void check_run_inputs(const ResolvedRun& run) {
  const Scenario& scenario = *run.scenario;
  const EngineInfo& engine = *run.engine;
  const Needs needs = needs_of(scenario, run.params);
  const Lack lack = lacks(engine, needs);
  if (lack == Lack::kFourWheels)
    throw InputError(fmt::format("configuration '{}' {}", engine.name, lack_text(lack, needs)));
  if (lack != Lack::kNothing) return;  // skipped: nothing of it runs
  try {
    ProbeCar car;
    ProbeDisks disks;
    (void)drive_vehicle(scenario, run.params,
                        {[&]() -> CarEngine& { return car; }, [&]() -> DiskEngine& { return disks; }});
  } catch (const ProbeStop&) {
  } catch (const InputError&) {
    throw;
  } catch (const std::exception&) {
    // Anything else is the engine's or the run's to report, in its record.
  }
}

TolRole tolerance_role(const EngineInfo& engine) {
  return engine.is_reference ? TolRole::kReference : TolRole::kDefault;
}

RunRecord run_scenario(const Scenario& scenario, const EngineInfo& engine, const Overrides& overrides) {
  return run_scenario(resolve_run(scenario, engine, overrides));
}

namespace {

/// A run's record before the engine works: what it runs, its known failure, and a skip where the
/// configuration lacks what the scenario needs (`skipped`). InputError for a four-wheel car on a
/// configuration without one.
RunRecord begin_record(const ResolvedRun& run, bool& skipped) {
  const Scenario& scenario = *run.scenario;
  const EngineInfo& engine = *run.engine;
  RunRecord r;
  r.scenario = scenario.name;
  r.engine = engine.name;
  r.vehicle = scenario.vehicle;
  r.params = run.params;
  r.settings = run.settings.texts();
  r.negative_control = scenario.negative_control;
  const Needs needs = needs_of(scenario, run.params);
  const Lack lack = lacks(engine, needs);
  // A car with four wheels needs a configuration that builds one: never a tricycle instead.
  if (lack == Lack::kFourWheels)
    throw InputError(fmt::format("configuration '{}' {}", engine.name, lack_text(lack, needs)));
  // The expectations describe the default suite and the runs they name with changed parameters
  // ("params"); a run with anything else changed, or any setting, is judged on its own.
  if (run.settings == engine.defaults(scenario.vehicle))
    for (const KnownFailure* k : known_failures_of(scenario.name, engine.name))
      if (r.params == Params::resolve(scenario.params, k->params, scenario.name)) r.expectation = expectation_of(*k);
  skipped = lack != Lack::kNothing;
  if (skipped) {
    r.status = Status::kSkip;
    r.message = fmt::format("engine '{}' {}", engine.name, lack_text(lack, needs));
  }
  r.judge();
  return r;
}

/// Scores the outcome into the record and gives it its status.
void finish_record(RunRecord& r, const ResolvedRun& run, const Outcome& outcome) {
  r.metrics =
      score(*run.scenario, tolerance_role(*run.engine), outcome, liftcheck::bookkeeping_factor(run.engine->precision));
  r.details = outcome.details;
  // A pass needs at least one counted metric; informational ones neither pass nor fail a run.
  bool finite = true, pass = false, any_fail = false;
  for (const auto& m : r.metrics) {
    if (m.informational) continue;
    finite = finite && std::isfinite(m.measured);
    pass = true;
    any_fail = any_fail || !m.pass;
  }
  pass = pass && !any_fail;
  if (!finite) {
    r.status = Status::kError;
    r.message = "engine produced a non-finite measurement";
  } else if (std::none_of(r.metrics.begin(), r.metrics.end(), [](const Metric& m) { return !m.informational; })) {
    r.status = Status::kError;
    r.message = "no metric measured the engine (every one is informational)";
  } else {
    r.status = pass ? Status::kPass : Status::kFail;
    if (!pass) r.message = fmt::format("out of tolerance: {}", fmt::join(r.failed_metrics(), ", "));
  }
  r.judge();
  if (r.status == Status::kFail && r.expectation && !r.decision.beyond.empty()) {
    r.message += fmt::format("; worse than its known failure: {}", fmt::join(r.decision.beyond, "; "));
    r.judge();
  }
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

RunRecord run_scenario(const ResolvedRun& run) {
  const Scenario& scenario = *run.scenario;
  const EngineInfo& engine = *run.engine;
  bool skipped = false;
  RunRecord r = begin_record(run, skipped);
  if (skipped) return r;
  const auto t0 = std::chrono::steady_clock::now();
  try {
    std::unique_ptr<CarEngine> car;
    std::unique_ptr<DiskEngine> disks;
    const Driven d = drive_vehicle(scenario, run.params,
                                   {[&]() -> CarEngine& { return *(car = engine.make_car(run.settings)); },
                                    [&]() -> DiskEngine& { return *(disks = engine.make_disks(run.settings)); }});
    r.simulated_s = d.simulated_s;
    r.engine_s = d.engine_s;
    finish_record(r, run, d.outcome);
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    r.status = Status::kError;
    r.message = e.what();
    r.judge();
  }
  r.wall_s = seconds_since(t0);
  return r;
}

std::vector<RunRecord> run_shared_drive(const std::vector<ResolvedRun>& runs) {
  std::vector<RunRecord> records;
  bool skipped = false;
  for (const ResolvedRun& run : runs) records.push_back(begin_record(run, skipped));
  if (skipped || runs.empty()) return records;  // the same configuration and needs: all skip alike
  const ResolvedRun& first = runs.front();
  const auto t0 = std::chrono::steady_clock::now();
  try {
    auto car = first.engine->make_car(first.settings);
    const Outcome drive = first.scenario->shared_drive->drive(first.params, *car);
    for (size_t i = 0; i < runs.size(); ++i) {
      records[i].simulated_s = car->simulated_s();
      records[i].engine_s = car->reported_engine_s();
      try {  // a judgement that fails is its own run's error, as it would be alone
        finish_record(records[i], runs[i], runs[i].scenario->shared_drive->judge(runs[i].params, drive));
      } catch (const InputError&) {
        throw;
      } catch (const std::exception& e) {
        records[i].status = Status::kError, records[i].message = e.what();
        records[i].judge();
      }
    }
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    for (RunRecord& r : records) r.status = Status::kError, r.message = e.what(), r.judge();
  }
  for (RunRecord& r : records) r.wall_s = seconds_since(t0);
  return records;
}

}  // namespace liftcheck
