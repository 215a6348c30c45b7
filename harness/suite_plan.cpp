#include "harness/suite_plan.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <set>

#include "harness/results.hpp"
#include "harness/runner.hpp"
#include "input/glob.hpp"
#include "input/suggest.hpp"

namespace liftcheck {

namespace {

/// --set applies to a run whose scenario has the parameter or whose configuration has the
/// setting for the scenario's vehicle.
Overrides overrides_for(const Overrides& set, const Scenario& s, const EngineInfo& e) {
  Overrides ov;
  for (const auto& [key, value] : set)
    if (key_owner(s, e, key) != KeyOwner::kNeither) ov.emplace_back(key, value);
  return ov;
}

/// Engine steps the run asks for, roughly: the simulated time over dt (a car path is about ten
/// seconds long). Only the order of the schedule depends on it, never a result.
double cost_estimate(const ResolvedRun& run) {
  const Params& p = run.params;
  const double dt = p.has("dt") ? p.num("dt") : 1e-3;
  const double horizon = run.scenario->vehicle == Vehicle::kCar ? 10.0 : p.has("T") ? p.num("T") : 6.0;
  return dt > 0.0 && horizon > 0.0 ? horizon / dt : 1.0;
}

}  // namespace

nlohmann::json SuitePlan::selection() const {
  nlohmann::json j;
  j["engines"] = nlohmann::json::array();
  for (const EngineInfo* e : def.engines) j["engines"].push_back(e->name);
  j["filter"] = def.globs;
  j["set"] = nlohmann::json::array();
  for (const auto& [k, v] : def.set) j["set"].push_back(k + "=" + v);
  j["sweeps"] = def.sweeps;
  j["all_points"] = def.all_points;
  j["external"] = def.external_name;
  j["timeout_s"] = def.timeout_s;
  return j;
}

namespace {

/// Every --set key must be taken by some run: a parameter of a scenario or a setting of a
/// configuration run here.
void check_set_taken(const SuiteDef& def, const std::vector<const Scenario*>& scenarios) {
  for (const auto& [key, value] : def.set) {
    bool taken = false;
    for (const Scenario* s : scenarios)
      for (const EngineInfo* e : def.engines) taken = taken || key_owner(*s, *e, key) != KeyOwner::kNeither;
    if (!taken) {
      std::vector<std::string> names;
      for (const Scenario* s : scenarios)
        for (const ParamSpec& p : s->params) names.push_back(p.key);
      for (const EngineInfo* e : def.engines)
        for (const SettingSpec& k : e->knobs) names.push_back(k.key);
      throw InputError(fmt::format("--set {}: no scenario run here has a parameter or setting '{}'{}", printable(key),
                                   printable(key), did_you_mean(key, names)));
    }
  }
}

/// Every run that --set changes takes its values (a bad one is bad input, exit 2, before anything
/// runs; not an error record per run).
void check_set_values(const SuitePlan& plan) {
  for (const SuiteItem& it : plan.items) {
    if (it.kind != SuiteItem::kRun || it.owned || it.overrides.empty()) continue;
    try {
      if (!it.run) throw InputError(it.resolve_error);
      check_run_inputs(*it.run);
    } catch (const InputError& e) {
      throw InputError(fmt::format("--set: {} on {}: {}", it.scenario->name, it.engine->name, e.what()));
    }
  }
}

/// Every scenario on every configuration, then the outside simulator's traces.
void add_runs(SuitePlan& plan, const SuiteDef& def) {
  for (const Scenario* s : plan.scenarios)
    for (const EngineInfo* e : def.engines) {
      plan.items.push_back(
          planned_item(SuiteItem::kRun, run_key(s->name, e->name), *s, *e, overrides_for(def.set, *s, *e)));
    }
  for (const Scenario* s : plan.scenarios) {
    const auto t = def.traces.find(s->name);
    if (t == def.traces.end()) continue;
    auto owned = std::make_shared<const EngineInfo>(replay_engine(def.external_name, *s, t->second));
    SuiteItem it = planned_item(SuiteItem::kRun, run_key(s->name, def.external_name), *s, *owned, {});
    it.owned = std::move(owned);
    it.trace_file = t->second.file;
    it.cost = 1.0;
    plan.items.push_back(std::move(it));
  }
}

/// The points of the sweeps, the outcome sweep and the map whose scenarios the filter matches.
void add_points(SuitePlan& plan, const SuiteDef& def) {
  std::vector<PointRun> points;
  for (const SweepDef& sw : sweep_catalogue())
    if (matches_any(def.globs, sw.scenario)) {
      plan.sweeps.push_back(&sw);
      const auto runs = sweep_runs(sw, sweep_engines(def));
      points.insert(points.end(), runs.begin(), runs.end());
    }
  if (matches_any(def.globs, outcome_sweep_scenario())) {
    plan.outcome_sweep = true;
    const auto runs = outcome_runs(sweep_engines(def));
    points.insert(points.end(), runs.begin(), runs.end());
  }
  const MapDef& map = speed_accuracy_map();
  if (std::any_of(map.panels.begin(), map.panels.end(),
                  [&](const MapDef::Panel& p) { return matches_any(def.globs, p.scenario); })) {
    plan.map = true;
    const auto runs = map_runs(map, def.engines, def.all_points);
    points.insert(points.end(), runs.begin(), runs.end());
  }
  for (PointRun& p : points)
    plan.items.push_back(
        planned_item(SuiteItem::kPoint, std::move(p.key), *p.scenario, *p.engine, std::move(p.overrides)));
}

/// Keys are unique; each item's resolved run gives its cost and its identity; an item the same as
/// an earlier one is marked so it runs once.
void resolve_items(SuitePlan& plan) {
  std::set<std::string> keys;
  for (const SuiteItem& it : plan.items)
    if (!keys.insert(it.key).second) throw std::logic_error(fmt::format("two suite items share the key '{}'", it.key));
  // The same run asked for twice (the default run is a sweep's point and a map point too) runs once,
  // and runs that judge one drive (Scenario::shared_drive) make it once.
  std::map<std::string, long> first, drive_maker;
  for (size_t i = 0; i < plan.items.size(); ++i) {
    SuiteItem& it = plan.items[i];
    if (it.owned || !it.run) continue;  // a run not resolved is an error record of its own
    it.cost = cost_estimate(*it.run);
    const nlohmann::json identity{{"engine", it.engine->name},
                                  {"params", it.run->params.to_json()},
                                  {"settings", it.run->settings.exact_texts()}};
    const auto [where, inserted] =
        first.emplace(nlohmann::json{{"scenario", it.scenario->name}, {"run", identity}}.dump(), static_cast<long>(i));
    if (!inserted) it.same_as = where->second;
    if (!inserted || it.kind != SuiteItem::kRun || !it.scenario->shared_drive) continue;
    const auto [maker, first_judge] = drive_maker.emplace(
        nlohmann::json{{"drive", it.scenario->shared_drive->name}, {"run", identity}}.dump(), static_cast<long>(i));
    if (first_judge) continue;
    it.judges_drive_of = maker->second;
    plan.items[static_cast<size_t>(maker->second)].drive_judges.push_back(*it.run);
  }
}

}  // namespace

std::vector<const EngineInfo*> sweep_engines(const SuiteDef& def) {
  std::vector<const EngineInfo*> v;
  for (const EngineInfo* e : def.engines)
    if (e->points == SuitePoints::kAll || def.all_points) v.push_back(e);
  return v;
}

SuiteItem planned_item(SuiteItem::Kind kind, std::string key, const Scenario& scenario, const EngineInfo& engine,
                       Overrides overrides) {
  SuiteItem it;
  it.kind = kind;
  it.key = std::move(key);
  it.scenario = &scenario, it.engine = &engine, it.overrides = std::move(overrides);
  try {
    it.run = resolve_run(scenario, engine, it.overrides);
  } catch (const InputError& e) {
    it.resolve_error = e.what();
  }
  return it;
}

std::string run_key(const std::string& scenario, const std::string& engine) {
  return fmt::format("run/{}/{}", scenario, engine);
}

SuitePlan plan_suite(const SuiteDef& def) {
  SuitePlan plan;
  plan.def = def;
  if (def.engines.empty()) throw InputError("--engines names no engine");
  for (const auto& s : scenarios())
    if (matches_any(def.globs, s.name)) plan.scenarios.push_back(&s);
  if (plan.scenarios.empty()) {
    std::vector<std::string> names;
    for (const auto& s : scenarios()) names.push_back(s.name);
    const std::string hint = def.globs.size() == 1 ? did_you_mean(def.globs.front(), names) : "";
    throw InputError(fmt::format("no scenario matches '{}' (see 'liftcheck list'){}", fmt::join(def.globs, ","), hint));
  }
  check_set_taken(def, plan.scenarios);
  add_runs(plan, def);
  check_set_values(plan);
  if (def.sweeps) add_points(plan, def);
  resolve_items(plan);  // runs of different scenarios or configurations: only the points can be the same
  return plan;
}

std::vector<size_t> shard_share(const SuitePlan& plan, int index, int total) {
  if (total < 1 || index < 1 || index > total)
    throw InputError(
        fmt::format("shard {}/{}: the index must be 1 to {} and the count at least 1", index, total, total));
  std::vector<size_t> out;
  size_t k = 0;
  for (size_t i = 0; i < plan.items.size(); ++i)
    if (plan.items[i].runs_itself() && k++ % static_cast<size_t>(total) == static_cast<size_t>(index - 1))
      out.push_back(i);
  return out;
}

void fill_duplicates(const SuitePlan& plan, std::map<std::string, RunResult>& records) {
  for (const SuiteItem& it : plan.items) {
    if (it.same_as < 0) continue;
    RunResult rec = records.at(plan.items[static_cast<size_t>(it.same_as)].key);
    if (it.kind == SuiteItem::kPoint) trim_to_point(rec);
    records[it.key] = std::move(rec);
  }
}

}  // namespace liftcheck
