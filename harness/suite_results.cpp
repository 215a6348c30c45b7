#include "harness/suite_results.hpp"

#include <algorithm>
#include <cmath>

#include "harness/results.hpp"
#include "harness/runner.hpp"
#include "harness/worker_pool.hpp"
#include "engines/protocol/outside.hpp"

namespace liftcheck {

std::vector<std::pair<size_t, nlohmann::json>> shared_records(const SuitePlan& plan, size_t maker,
                                                              const nlohmann::json& record) {
  std::vector<std::pair<size_t, nlohmann::json>> out;
  const nlohmann::json shared = record.contains("shared") ? record["shared"] : nlohmann::json::array();
  for (size_t i = 0; i < plan.items.size(); ++i) {
    const SuiteItem& it = plan.items[i];
    if (it.judges_drive_of != static_cast<long>(maker)) continue;
    const auto mine = std::find_if(shared.begin(), shared.end(), [&](const nlohmann::json& r) {
      return r.value("scenario", "") == it.scenario->name;
    });
    // A maker that ended without recording the others (its worker died, its time ran out): theirs say so.
    out.emplace_back(
        i, mine != shared.end() ? *mine : error_record(it, record.value("message", "no record of the shared drive")));
  }
  return out;
}

void take_shared_records(const SuitePlan& plan, std::map<std::string, nlohmann::json>& records) {
  for (size_t m = 0; m < plan.items.size(); ++m) {
    if (plan.items[m].drive_judges.empty()) continue;
    const auto maker = records.find(plan.items[m].key);
    if (maker == records.end()) continue;
    for (auto& [i, rec] : shared_records(plan, m, maker->second)) records[plan.items[i].key] = std::move(rec);
    maker->second.erase("shared");
  }
}

nlohmann::json assemble_suite(const SuitePlan& plan, const std::map<std::string, nlohmann::json>& records) {
  const RecordLookup lookup = [&](const std::string& key) -> const nlohmann::json& { return records.at(key); };
  nlohmann::json out;
  out["runs"] = nlohmann::json::array();
  for (const SuiteItem& it : plan.items)
    if (it.kind == SuiteItem::kRun) out["runs"].push_back(records.at(it.key));
  out["sweeps"] = nlohmann::json::array();
  const std::vector<const EngineInfo*> swept = sweep_engines(plan.def);
  for (const SweepDef* sw : plan.sweeps) out["sweeps"].push_back(assemble_sweep(*sw, swept, lookup));
  if (plan.outcome_sweep) out["sweeps"].push_back(assemble_outcome_sweep(swept, lookup));
  out["maps"] = nlohmann::json::array();
  if (plan.map)
    out["maps"].push_back(assemble_map(speed_accuracy_map(), plan.def.engines, lookup, plan.def.all_points));
  return out;
}

std::string item_part(const SuiteItem& item) {
  if (item.kind == SuiteItem::kRun) return "runs";
  if (item.key.rfind("outcomes/", 0) == 0) return "outcomes";
  return item.key.substr(0, item.key.find('/', item.key.find('/') + 1));
}

nlohmann::json simulated_budget(const SuitePlan& plan, const std::map<std::string, nlohmann::json>& records) {
  double total_s = 0.0;
  std::map<std::string, double> by_part;
  std::map<std::string, std::map<std::string, double>> by_config;
  for (const SuiteItem& it : plan.items) {
    const auto rec = records.find(it.key);
    if (!it.runs_itself() || rec == records.end()) continue;
    const double s = rec->second.value("simulated_s", 0.0);
    total_s += s;
    by_part[item_part(it)] += s;
    by_config[it.engine->name][item_part(it)] += s;
  }
  const auto us = [](double s) { return std::round(s * 1e6) / 1e6; };
  nlohmann::json out{
      {"total_s", us(total_s)}, {"by_part", nlohmann::json::object()}, {"by_configuration", nlohmann::json::object()}};
  for (const auto& [part, s] : by_part) out["by_part"][part] = us(s);
  for (const auto& [config, parts] : by_config) {
    double sum_s = 0.0;
    nlohmann::json c{{"by_part", nlohmann::json::object()}};
    for (const auto& [part, s] : parts) sum_s += s, c["by_part"][part] = us(s);
    c["total_s"] = us(sum_s);
    out["by_configuration"][config] = c;
  }
  return out;
}

nlohmann::json suite_results(const SuitePlan& plan, std::map<std::string, nlohmann::json>& records,
                             const nlohmann::json& context) {
  const nlohmann::json simulated = simulated_budget(plan, records);
  fill_duplicates(plan, records);
  const nlohmann::json assembled = assemble_suite(plan, records);
  nlohmann::json results = results_from_records(assembled["runs"], context);
  results["sweeps"] = assembled["sweeps"];
  results["maps"] = assembled["maps"];
  results["simulated"] = simulated;
  results["scenarios"] = nlohmann::json::array();
  for (const Scenario* s : plan.scenarios) results["scenarios"].push_back(s->to_json());
  return results;
}

void SuiteTiming::count(const SuiteItem& it, const nlohmann::json& record, double held) {
  const double engine_s = record["wall_s"].get<double>();
  (it.kind == SuiteItem::kRun ? runs_s : points_s) += engine_s;
  cost_by_part[item_part(it)] += engine_s;
  cost_by_config[it.engine->name] += engine_s;
  held_s += held;
  held_by_part[item_part(it)] += held;
  held_by_config[it.engine->name] += held;
}

nlohmann::json suite_context(const std::vector<const EngineInfo*>& engines, const SuiteTiming& t,
                             const RunnerDef& runner, const Overrides& set) {
  nlohmann::json context = context_json(engines, t.wall_s);
  context["runs_s"] = t.runs_s;
  context["points_s"] = t.points_s;
  context["engine_s_by_part"] = t.cost_by_part;
  context["engine_s_by_configuration"] = t.cost_by_config;
  context["worker_s_by_part"] = t.held_by_part;
  context["worker_s_by_configuration"] = t.held_by_config;
  context["worker_s"] = t.held_s;
  context["jobs"] = runner.jobs;
  context["timeout_s"] = runner.timeout_s;
  context["memory_limit_mib"] = runner.memory_limit_mib;
  // Which adapters the outside configurations ran: those beside this binary, or the source tree's.
  context["outside_suite"] = {{"folder", default_suite_dir()}, {"beside_binary", default_suite_is_beside_binary()}};
  context["set"] = nlohmann::json::object();
  for (const auto& [key, value] : set) context["set"][key] = value;
  return context;
}

}  // namespace liftcheck
