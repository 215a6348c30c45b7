#include "harness/suite_results.hpp"

#include <algorithm>
#include <cmath>

#include "engines/protocol/outside.hpp"
#include "harness/results.hpp"
#include "harness/runner.hpp"
#include "harness/worker_pool.hpp"

namespace liftcheck {

std::vector<std::pair<size_t, RunResult>> shared_records(const SuitePlan& plan, size_t maker, const RunResult& record) {
  std::vector<std::pair<size_t, RunResult>> out;
  for (size_t i = 0; i < plan.items.size(); ++i) {
    const SuiteItem& it = plan.items[i];
    if (it.judges_drive_of != static_cast<long>(maker)) continue;
    const auto mine = std::find_if(record.shared.begin(), record.shared.end(),
                                   [&](const RunResult& r) { return r.scenario == it.scenario->name; });
    // A maker that ended without recording the others (its worker died, its time ran out): theirs say so.
    out.emplace_back(i,
                     mine != record.shared.end()
                         ? *mine
                         : error_record(it, record.message.empty() ? "no record of the shared drive" : record.message));
  }
  return out;
}

void take_shared_records(const SuitePlan& plan, Records& records) {
  for (size_t m = 0; m < plan.items.size(); ++m) {
    if (plan.items[m].drive_judges.empty()) continue;
    const auto maker = records.find(plan.items[m].key);
    if (maker == records.end()) continue;
    for (auto& [i, rec] : shared_records(plan, m, maker->second)) records[plan.items[i].key] = std::move(rec);
    maker->second.shared.clear();
  }
}

std::string item_part(const SuiteItem& item) {
  if (item.kind == SuiteItem::kRun) return "runs";
  if (item.key.rfind("outcomes/", 0) == 0) return "outcomes";
  return item.key.substr(0, item.key.find('/', item.key.find('/') + 1));
}

SimulatedBudget simulated_budget(const SuitePlan& plan, const Records& records) {
  SimulatedBudget b;
  double total_s = 0.0;
  for (const SuiteItem& it : plan.items) {
    const auto rec = records.find(it.key);
    if (!it.runs_itself() || rec == records.end()) continue;
    const double s = rec->second.simulated_s;
    total_s += s;
    b.by_part[item_part(it)] += s;
    b.by_configuration[it.engine->name][item_part(it)] += s;
  }
  const auto us = [](double s) { return std::round(s * 1e6) / 1e6; };
  b.total_s = us(total_s);
  for (auto& [part, s] : b.by_part) s = us(s);
  for (auto& [config, parts] : b.by_configuration) {
    double sum_s = 0.0;
    for (auto& [part, s] : parts) sum_s += s, s = us(s);
    b.configuration_total_s[config] = us(sum_s);
  }
  return b;
}

SuiteResults suite_results(const SuitePlan& plan, Records& records, SuiteContext context) {
  SuiteResults out;
  out.simulated = simulated_budget(plan, records);
  fill_duplicates(plan, records);
  const RecordLookup lookup = [&](const std::string& key) -> const RunResult& { return records.at(key); };
  for (const SuiteItem& it : plan.items)
    if (it.kind == SuiteItem::kRun)
      out.runs.push_back(records.at(it.key));
    else
      out.points.emplace(it.key, records.at(it.key));
  const std::vector<const EngineInfo*> swept = sweep_engines(plan.def);
  for (const SweepDef* sw : plan.sweeps) out.sweeps.push_back(assemble_sweep(*sw, swept, lookup));
  if (plan.outcome_sweep) out.outcomes = assemble_outcome_sweep(swept, lookup);
  if (plan.map) out.maps.push_back(assemble_map(speed_accuracy_map(), plan.def.engines, lookup, plan.def.all_points));
  for (const Scenario* s : plan.scenarios) out.scenarios.push_back(s->info());
  out.context = std::move(context);
  return out;
}

void SuiteTiming::count(const SuiteItem& it, const RunResult& record, double held) {
  const double engine_s = record.wall_s;
  (it.kind == SuiteItem::kRun ? runs_s : points_s) += engine_s;
  cost_by_part[item_part(it)] += engine_s;
  cost_by_config[it.engine->name] += engine_s;
  held_s += held;
  held_by_part[item_part(it)] += held;
  held_by_config[it.engine->name] += held;
}

SuiteContext suite_context(const std::vector<const EngineInfo*>& engines, const SuiteTiming& t, const RunnerDef& runner,
                           const Overrides& set) {
  SuiteContext c = context_of(engines, t.wall_s);
  c.runs_s = t.runs_s;
  c.points_s = t.points_s;
  c.engine_s_by_part = t.cost_by_part;
  c.engine_s_by_configuration = t.cost_by_config;
  c.worker_s_by_part = t.held_by_part;
  c.worker_s_by_configuration = t.held_by_config;
  c.worker_s = t.held_s;
  c.jobs = runner.jobs;
  c.timeout_s = runner.timeout_s;
  c.memory_limit_mib = runner.memory_limit_mib;
  // Which adapters the outside configurations ran: those beside this binary, or the source tree's.
  c.outside_folder = default_suite_dir();
  c.outside_beside_binary = default_suite_is_beside_binary();
  c.set = set;
  return c;
}

}  // namespace liftcheck
