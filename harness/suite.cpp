#include "harness/suite.hpp"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <fmt/format.h>
#include <fnmatch.h>
#include <mutex>
#include <set>
#include <thread>

#include "harness/runner.hpp"

namespace liftcheck {

namespace {

bool matches(const std::vector<std::string>& globs, const std::string& name) {
  for (const auto& g : globs)
    if (fnmatch(g.c_str(), name.c_str(), 0) == 0) return true;
  return false;
}

/// --set applies to a run whose scenario has the parameter or whose configuration has the
/// setting for the scenario's vehicle.
Overrides overrides_for(const Overrides& set, const Scenario& s, const EngineInfo& e) {
  Overrides ov;
  for (const auto& [key, value] : set) {
    const bool param = std::any_of(s.params.begin(), s.params.end(), [&](const ParamSpec& p) { return p.key == key; });
    const bool knob = std::any_of(e.knobs.begin(), e.knobs.end(), [&](const SettingSpec& k) { return k.key == key && k.vehicle == s.vehicle; });
    if (param || knob) ov.emplace_back(key, value);
  }
  return ov;
}

/// Engine steps the item asks for, roughly: the simulated time over dt (a car path is about ten
/// seconds long). Only the order of the schedule depends on it, never a result.
double cost_estimate(const Scenario& s, const Overrides& ov) {
  const auto value = [&](const std::string& key, double fallback) {
    for (auto it = ov.rbegin(); it != ov.rend(); ++it)
      if (it->first == key) return std::strtod(it->second.c_str(), nullptr);
    for (const ParamSpec& p : s.params)
      if (p.key == key) return std::strtod(p.default_text.c_str(), nullptr);
    return fallback;
  };
  const double dt = value("dt", 1e-3), horizon = s.vehicle == "car" ? 10.0 : value("T", 6.0);
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
  j["external"] = def.external_name;
  return j;
}

SuitePlan plan_suite(const SuiteDef& def) {
  SuitePlan plan;
  plan.def = def;
  if (def.engines.empty()) throw InputError("--engines names no engine");
  for (const auto& s : scenarios())
    if (matches(def.globs, s.name)) plan.scenarios.push_back(&s);
  if (plan.scenarios.empty()) throw InputError(fmt::format("no scenario matches '{}'", fmt::join(def.globs, ",")));
  for (const auto& [key, value] : def.set) {
    bool taken = false;
    for (const Scenario* s : plan.scenarios)
      for (const EngineInfo* e : def.engines)
        for (const auto& kv : overrides_for(def.set, *s, *e)) taken = taken || kv.first == key;
    if (!taken) throw InputError(fmt::format("--set {}: no scenario run here has a parameter or setting '{}'", key, key));
  }
  for (const Scenario* s : plan.scenarios)
    for (const EngineInfo* e : def.engines) {
      SuiteItem it;
      it.key = fmt::format("run/{}/{}", s->name, e->name);
      it.scenario = s, it.engine = e, it.overrides = overrides_for(def.set, *s, *e);
      it.cost = cost_estimate(*s, it.overrides);
      plan.items.push_back(std::move(it));
    }
  for (const Scenario* s : plan.scenarios) {
    const auto t = def.traces.find(s->name);
    if (t == def.traces.end()) continue;
    SuiteItem it;
    it.key = fmt::format("run/{}/{}", s->name, def.external_name);
    it.owned = std::make_shared<const EngineInfo>(replay_engine(def.external_name, *s, t->second));
    it.scenario = s, it.engine = it.owned.get(), it.cost = 1.0;
    plan.items.push_back(std::move(it));
  }
  if (!def.sweeps) return plan;
  std::vector<PointRun> points;
  for (const SweepDef& sw : sweep_catalogue())
    if (matches(def.globs, sw.scenario)) {
      plan.sweeps.push_back(&sw);
      const auto runs = sweep_runs(sw, def.engines);
      points.insert(points.end(), runs.begin(), runs.end());
    }
  if (matches(def.globs, outcome_sweep_scenario())) {
    plan.outcome_sweep = true;
    const auto runs = outcome_runs(def.engines);
    points.insert(points.end(), runs.begin(), runs.end());
  }
  const MapDef& map = speed_accuracy_map();
  if (std::any_of(map.panels.begin(), map.panels.end(), [&](const MapDef::Panel& p) { return matches(def.globs, p.scenario); })) {
    plan.map = true;
    const auto runs = map_runs(map, def.engines);
    points.insert(points.end(), runs.begin(), runs.end());
  }
  for (PointRun& p : points) {
    SuiteItem it;
    it.kind = SuiteItem::kPoint;
    it.key = std::move(p.key);
    it.scenario = p.scenario, it.engine = p.engine, it.overrides = std::move(p.overrides);
    it.cost = cost_estimate(*it.scenario, it.overrides);
    plan.items.push_back(std::move(it));
  }
  std::set<std::string> keys;
  for (const SuiteItem& it : plan.items)
    if (!keys.insert(it.key).second) throw std::logic_error(fmt::format("two suite items share the key '{}'", it.key));
  return plan;
}

std::vector<size_t> shard_share(const SuitePlan& plan, int index, int total) {
  if (total < 1 || index < 1 || index > total) throw InputError(fmt::format("shard {}/{}: the index must be 1 to {} and the count at least 1", index, total, total));
  std::vector<size_t> out;
  for (size_t i = static_cast<size_t>(index - 1); i < plan.items.size(); i += static_cast<size_t>(total)) out.push_back(i);
  return out;
}

nlohmann::json run_item(const SuiteItem& item) {
  RunRecord r;
  try {
    r = run_scenario(*item.scenario, *item.engine, item.overrides);
  } catch (const std::exception& err) {  // values rejected by the scenario (a defect at the defaults): reported per run
    r = RunRecord{};
    r.scenario = item.scenario->name;
    r.engine = item.engine->name;
    r.vehicle = item.scenario->vehicle;
    r.status = Status::kError;
    r.message = err.what();
  }
  const nlohmann::json j = item.kind == SuiteItem::kRun ? r.to_json() : point_record(r);
  return nlohmann::json::parse(j.dump());  // as results.json stores it: no infinities, no NaN
}

std::vector<nlohmann::json> run_items(const SuitePlan& plan, const std::vector<size_t>& which, int jobs,
                                      const std::function<void(size_t, const nlohmann::json&)>& done,
                                      const std::function<void(size_t, size_t)>& progress) {
  const size_t n = which.size();
  std::vector<nlohmann::json> records(n);
  std::vector<char> ready(n, 0);
  // The runs first, so their lines appear early, then the points; each longest first, ties in
  // plan order. Workers never wait between the two.
  std::vector<size_t> order(n);
  for (size_t k = 0; k < n; ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const SuiteItem &x = plan.items[which[a]], &y = plan.items[which[b]];
    return x.kind != y.kind ? x.kind == SuiteItem::kRun : x.cost > y.cost;
  });
  std::atomic<size_t> next{0};
  std::mutex mu;
  std::condition_variable cv;
  size_t finished = 0;
  const auto worker = [&] {
    for (size_t k; (k = next.fetch_add(1)) < n;) {
      const size_t slot = order[k];
      nlohmann::json rec = run_item(plan.items[which[slot]]);
      std::lock_guard<std::mutex> lock(mu);
      records[slot] = std::move(rec);
      ready[slot] = 1;
      ++finished;
      cv.notify_one();
    }
  };
  const int threads = std::max(1, std::min<int>(jobs, static_cast<int>(n)));
  std::vector<std::thread> pool;
  for (int t = 0; t < threads; ++t) pool.emplace_back(worker);
  size_t printed = 0;
  while (printed < n) {
    std::unique_lock<std::mutex> lock(mu);
    cv.wait_for(lock, std::chrono::milliseconds(250), [&] { return ready[printed] != 0; });
    const size_t count = finished;
    std::vector<size_t> now;
    while (printed < n && ready[printed]) now.push_back(printed++);
    lock.unlock();
    for (size_t k : now) done(which[k], records[k]);
    if (progress) progress(count, n);
  }
  for (auto& t : pool) t.join();
  return records;
}

nlohmann::json assemble_suite(const SuitePlan& plan, const std::map<std::string, nlohmann::json>& records) {
  const RecordLookup lookup = [&](const std::string& key) -> const nlohmann::json& { return records.at(key); };
  nlohmann::json out;
  out["runs"] = nlohmann::json::array();
  for (const SuiteItem& it : plan.items)
    if (it.kind == SuiteItem::kRun) out["runs"].push_back(records.at(it.key));
  out["sweeps"] = nlohmann::json::array();
  for (const SweepDef* sw : plan.sweeps) out["sweeps"].push_back(assemble_sweep(*sw, plan.def.engines, lookup));
  if (plan.outcome_sweep) out["sweeps"].push_back(assemble_outcome_sweep(plan.def.engines, lookup));
  out["maps"] = nlohmann::json::array();
  if (plan.map) out["maps"].push_back(assemble_map(speed_accuracy_map(), plan.def.engines, lookup));
  return out;
}

}  // namespace liftcheck
