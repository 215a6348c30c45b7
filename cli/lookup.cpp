#include "cli/lookup.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <sstream>

#include "cli/interrupts.hpp"
#include "cli/terminal.hpp"
#include "engines/protocol/outside.hpp"
#include "input/results_codec.hpp"
#include "input/standing.hpp"  // short_number
#include "input/suggest.hpp"

namespace liftcheck::cli {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

const Scenario& scenario_or_throw(const std::string& name) {
  if (const Scenario* s = find_scenario(name)) return *s;
  std::vector<std::string> names;
  for (const auto& s : scenarios()) names.push_back(s.name);
  throw InputError(
      fmt::format("unknown scenario '{}' (see 'liftcheck list'){}", printable(name), did_you_mean(name, names)));
}

const EngineInfo& engine_or_throw(const std::string& name) {
  if (const EngineInfo* e = find_engine(name)) return *e;
  std::vector<std::string> names;
  for (const auto& e : engines()) names.push_back(e.name);
  throw InputError(fmt::format("unknown engine configuration '{}' (available: {}){}", printable(name),
                               fmt::join(names, ", "), did_you_mean(name, names)));
}

Overrides overrides_or_throw(const std::vector<std::string>& sets, const Scenario& s, const EngineInfo* e) {
  Overrides ov;
  for (const auto& a : sets) ov.push_back(split_assignment(a));
  for (const auto& [key, value] : ov) {
    // A key some configuration takes for this scenario (the run then names the one it lacks).
    if (std::any_of(engines().begin(), engines().end(),
                    [&](const EngineInfo& x) { return key_owner(s, x, key) != KeyOwner::kNeither; }))
      continue;
    std::vector<std::string> own;
    for (const auto& p : s.params) own.push_back(p.key);
    for (const auto& engine : engines())
      for (const SettingSpec& k : engine.knobs)
        if (k.vehicle == s.vehicle && (!e || e == &engine)) own.push_back(k.key);
    throw InputError(
        fmt::format("unknown parameter '{}' for scenario '{}'{}", printable(key), s.name, did_you_mean(key, own)));
  }
  return ov;
}

RunnerDef runner_def(int jobs, double timeout_s, double memory_limit_mib) {
  if (jobs < 1) throw InputError(fmt::format("--jobs {} must be at least 1", jobs));
  if (!(timeout_s > 0.0) || !std::isfinite(timeout_s))
    throw InputError(fmt::format("--timeout {} must be a positive number of seconds", timeout_s));
  if (!(memory_limit_mib >= 256.0) || !std::isfinite(memory_limit_mib))
    throw InputError(fmt::format(
        "--memory-limit {} must be at least 256 MiB (a worker with every engine loaded takes about 250 MiB)",
        memory_limit_mib));
  RunnerDef r;
  r.memory_limit_mib = memory_limit_mib;
  r.jobs = std::min(jobs, usable_cores());  // more would only queue for the same cores
  if (r.jobs < jobs)
    std::cerr << fmt::format("liftcheck: note: --jobs {} runs {} at once: this machine lets it use {} core{}\n", jobs,
                             r.jobs, r.jobs, r.jobs == 1 ? "" : "s");
  r.timeout_s = timeout_s;
  r.stop = [] { return pending_signal() != 0; };
  // Outside engines' replies are bounded by the run's limit, here and in the worker processes.
  set_protocol_timeout(timeout_s);
  setenv("LIFTCHECK_RUN_TIMEOUT_S", fmt::format("{}", timeout_s).c_str(), 1);
  return r;
}

void print_record(const RunResult& r) {
  std::cout << fmt::format("{} on {}: {}{}\n", r.scenario, printable(r.engine, 200),
                           coloured_verdict(to_string(r.verdict())),
                           r.message.empty() ? "" : " (" + printable(r.message, 1000) + ")");
  if (r.expectation)
    std::cout << fmt::format(
        "  {}: {}\n  measured when reviewed: {}\n",
        r.as_expected() ? "known failure" : "listed as a known failure (harness/expectations.json)",
        r.expectation->reason, r.expectation->measured);
  // The headline's metrics first, then the rest from the worst ratio to its tolerance down.
  const Scenario* scenario = find_scenario(r.scenario);
  const std::vector<std::string> head = scenario ? scenario->headline.metrics : std::vector<std::string>{};
  std::vector<std::pair<double, const Metric*>> order;
  for (const Metric& m : r.metrics) {
    const double err = m.compared_error(), tol = m.tolerance;
    const auto it = std::find(head.begin(), head.end(), m.name);
    double key = it != head.end() ? 1e300 - static_cast<double>(it - head.begin()) : tol > 0 ? err / tol : 0.0;
    order.emplace_back(std::isfinite(key) ? key : 1e299, &m);
  }
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::cout << fmt::format("  {:<22} {:>14} {:>14} {:>13} {:>10} {:<5} {:>9}  {}\n", "metric", "expected", "measured",
                           "error", "tolerance", "unit", "err/tol", "result");
  for (const auto& [key, mp] : order) {
    const Metric& m = *mp;
    const bool rel = m.kind == TolKind::kRelative;
    const double err = m.compared_error(), tol = m.tolerance;
    const std::string verdict = !m.counted() ? "info" : m.pass ? "ok" : "FAIL";
    const bool is_head = std::find(head.begin(), head.end(), m.name) != head.end();
    std::cout << fmt::format("  {:<22} {:>14.8g} {:>14.8g} {:>9.3g} {:<3} {:>10.3g} {:<5} {:>9}  {}\n",
                             is_head ? m.name + " *" : m.name, m.expected, m.measured, err, rel ? "rel" : "abs", tol,
                             rel ? "1" : m.unit, tol > 0 ? short_number(err / tol) : "-",
                             paint(verdict == "ok"     ? "pass"
                                   : verdict == "info" ? "skip"
                                                       : "fail",
                                   verdict));
  }
  if (!head.empty()) std::cout << fmt::format("  * the headline: {}\n", scenario->headline.label);
}

int run_one(const SuitePlan& plan, const RunnerDef& runner, bool json, const std::string& during) {
  std::vector<RunResult> records;
  try {
    records = run_items(plan, {0}, runner, [](size_t, const RunResult&, double) {});
  } catch (const RunnerStopped& e) {
    throw Interrupted(pending_signal(), e.what());
  }
  throw_if_interrupted(during);
  const RunResult& r = records.at(0);
  if (r.input_error) throw InputError(r.message);
  if (json)
    std::cout << encode_run(r).dump() << "\n";
  else
    print_record(r);
  return r.as_expected() ? 0 : 1;
}

}  // namespace liftcheck::cli
