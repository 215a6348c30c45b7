// liftcheck explain: a known failure's reason is a claim, and its evidence is an experiment (the
// run as listed, and the same run with one change). This re-runs every experiment of the chosen
// listings and says whether each still holds (harness/expectations.hpp, Evidence::holds).
#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <map>

#include "cli/command.hpp"
#include "cli/interrupts.hpp"
#include "cli/lookup.hpp"
#include "harness/sweeps.hpp"
#include "input/read_file.hpp"
#include "input/suggest.hpp"

namespace liftcheck::cli {

namespace {

/// One experiment: the listing, its evidence, and the plan items of its two runs.
struct Experiment {
  const ListedReason* listing = nullptr;
  const Evidence* evidence = nullptr;
  size_t base = 0, changed = 0;
};

/// The run a listing describes (a sweep listing: its point at the evidence's x).
std::pair<const Scenario*, Overrides> listed_run(const ListedReason& l, const Evidence& ev) {
  if (!l.sweep) return {&scenario_or_throw(l.scenario), l.params};
  for (const SweepDef& s : sweep_catalogue())
    if (s.name == l.scenario) return {&scenario_or_throw(s.scenario), point_overrides(s, ev.x)};
  // The outcome sweep's listings (the grid over cases, not a parameter): its scenario's default run.
  return {&scenario_or_throw(outcome_sweep_scenario()), {}};
}

/// The plan's item for this run, added once (two experiments on one listing share its run).
size_t item_for(SuitePlan& plan, std::map<std::string, size_t>& index, const Scenario& s, const EngineInfo& e,
                const Overrides& ov) {
  std::string key = fmt::format("explain/{}/{}", s.name, e.name);
  for (const auto& [k, v] : ov) key += fmt::format("/{}={}", k, v);
  if (const auto it = index.find(key); it != index.end()) return it->second;
  plan.items.push_back(planned_item(SuiteItem::kRun, key, s, e, ov));
  return index[key] = plan.items.size() - 1;
}

/// The metric's compared error and tolerance in a record; NaN where the run has no such figure.
std::pair<double, double> figure(const RunResult& record, const std::string& metric) {
  const Metric* m = record.metric(metric);
  if (!m) return {NAN, NAN};
  return {m->compared_error(), m->tolerance};
}

bool selected(const ListedReason& l, const std::vector<std::string>& names, const std::vector<std::string>& engines) {
  const auto in = [](const std::vector<std::string>& v, const std::string& x) {
    return v.empty() || std::find(v.begin(), v.end(), x) != v.end();
  };
  return in(names, (l.sweep ? "sweep:" : "") + l.scenario) && in(engines, l.engine);
}

/// One line per experiment; returns whether it holds.
bool report(const Experiment& x, const RunResult& base, const RunResult& changed, bool json) {
  const auto [from, tol] = figure(base, x.evidence->metric);
  const auto [to, to_tol] = figure(changed, x.evidence->metric);
  const bool measuring =
      std::isnan(x.evidence->from) && !x.evidence->from_error;  // --measure: nothing recorded to hold
  const bool errs = base.status == Status::kError;
  const bool holds = measuring || (x.evidence->from_error ? x.evidence->holds_from_error(errs, to, to_tol)
                                                          : x.evidence->holds(from, to, tol, to_tol));
  const ListedReason& l = *x.listing;
  const std::string where = l.sweep ? fmt::format("sweep {} at x = {} on {}", l.scenario, x.evidence->x, l.engine)
                                    : fmt::format("{} on {}", l.scenario, l.engine);
  if (json) {
    std::cout << nlohmann::json{{"listing", where},
                                {"scenario", l.scenario},
                                {"sweep", l.sweep},
                                {"engine", l.engine},
                                {"x", x.evidence->x},
                                {"from_error", errs},
                                {"params", l.params},
                                {"change", x.evidence->change},
                                {"metric", x.evidence->metric},
                                {"from", from},
                                {"to", to},
                                {"recorded_from", x.evidence->from},
                                {"recorded_to", x.evidence->to},
                                {"tolerance", tol},
                                {"holds", holds}}
                     .dump()
              << "\n";
    return holds;
  }
  std::cout << fmt::format("{}: {} moves {} {:.3g} -> {:.3g} (recorded {:.3g} -> {:.3g}, tolerance {:.3g}): {}\n",
                           where, x.evidence->change_text(), x.evidence->metric, from, to, x.evidence->from,
                           x.evidence->to, tol, holds ? "holds" : "DOES NOT HOLD");
  for (const RunResult* r : {&base, &changed})
    if (r->status == Status::kError) std::cout << "  error: " << printable(r->message, 300) << "\n";
  return holds;
}

/// The configurations asked for: those named, or every one (compiled-in ones only with
/// `compiled_in`, which starts no outside engine).
std::vector<std::string> configurations(const std::string& names, bool compiled_in) {
  std::vector<std::string> v = split_list(names);
  if (v.empty())
    for (const EngineInfo& e : engines())
      if (!compiled_in || !e.is_outside()) v.push_back(e.name);
  return v;
}

/// --measure PLAN: experiments not yet recorded ([{"scenario" or "sweep", "engine", "params",
/// "x", "change", "metric"}]), each a listing of its own whose figures are measured, not checked.
std::vector<ListedReason> read_plan(const std::string& path) {
  const nlohmann::json plan = nlohmann::json::parse(read_text_file(path, 16 << 20, "the plan"), nullptr, false);
  if (!plan.is_array()) throw InputError(fmt::format("{}: a plan is a JSON list of experiments", path));
  std::vector<ListedReason> v;
  for (const auto& e : plan) {
    if (!e.is_object() || !e.contains("engine"))
      throw InputError(fmt::format("{}: each experiment names its \"engine\"", path));
    const bool sweep = e.contains("sweep");
    ListedReason l{e.value(sweep ? "sweep" : "scenario", ""), sweep, e.at("engine"), {}, "", {}};
    const nlohmann::json params = e.value("params", nlohmann::json::object());
    for (const auto& [k, val] : params.items()) l.params.emplace_back(k, val.get<std::string>());
    nlohmann::json ev = {{"change", e.value("change", nlohmann::json::object())},
                         {"metric", e.value("metric", "")},
                         {"from", 0.0},
                         {"to", 1.0}};
    if (sweep) ev["x"] = e.value("x", 0.0);
    try {
      l.evidence = parse_evidence(nlohmann::json{{"evidence", {ev}}}, path);
    } catch (const std::logic_error& x) {
      throw InputError(x.what());
    }
    l.evidence[0].from = l.evidence[0].to = NAN;  // to be measured
    v.push_back(std::move(l));
  }
  return v;
}

/// A name given to explain is a scenario or sweep:NAME; a mistyped one is refused with the nearest
/// name, and a configuration's name in its place with the --engine that was meant.
void check_name(const std::string& name) {
  if (name.rfind("sweep:", 0) == 0) {
    std::vector<std::string> sweeps;
    for (const SweepDef& d : sweep_catalogue()) sweeps.push_back("sweep:" + d.name);
    if (std::find(sweeps.begin(), sweeps.end(), name) == sweeps.end())
      throw InputError(fmt::format("unknown sweep '{}' (see 'liftcheck list'){}", printable(name.substr(6)),
                                   did_you_mean(name, sweeps)));
    return;
  }
  if (find_scenario(name)) return;
  std::vector<std::string> configs;
  for (const auto& e : engines()) configs.push_back(e.name);
  const std::string engine = nearest_name(name, configs);
  if (!engine.empty())
    throw InputError(fmt::format("unknown scenario '{}' (see 'liftcheck list'); did you mean '--engine {}'?",
                                 printable(name), engine));
  (void)scenario_or_throw(name);
}

int cmd_explain(const std::vector<std::string>& names, const std::string& engine_names, bool compiled_in,
                const std::string& plan_file, int jobs, double timeout_s, bool json) {
  const std::vector<std::string> configs = configurations(engine_names, compiled_in);
  for (const auto& name : names) check_name(name);
  for (const auto& c : configs) (void)engine_or_throw(c);
  static std::vector<ListedReason> planned;  // the experiments point into it
  if (!plan_file.empty()) planned = read_plan(plan_file);
  SuitePlan plan;
  std::map<std::string, size_t> index;
  std::vector<Experiment> experiments;
  int unexplained = 0, not_shown = 0;
  for (const ListedReason& l : plan_file.empty() ? listed_reasons() : planned) {
    if (!selected(l, names, configs)) continue;
    if (l.evidence.empty() && !l.negative_control) {
      if (!l.cause_not_shown.empty())
        ++not_shown;
      else
        ++unexplained;
      if (!json)
        std::cout << fmt::format("{}{} on {}: {}\n", l.sweep ? "sweep " : "", l.scenario, l.engine,
                                 l.cause_not_shown.empty() ? "its reason names no experiment"
                                                           : "cause not shown; tried: " + l.cause_not_shown);
    }
    for (const Evidence& ev : l.evidence) {
      const auto [s, ov] = listed_run(l, ev);
      Overrides with_change = ov;
      for (const auto& [key, value] : ev.change) {
        if (std::any_of(ov.begin(), ov.end(), [&](const auto& kv) { return kv.first == key; }))
          throw InputError(fmt::format("{} on {}: the experiment changes '{}', which the listed run sets already",
                                       l.scenario, l.engine, key));
        with_change.emplace_back(key, value);
      }
      const EngineInfo& e = engine_or_throw(l.engine);
      experiments.push_back({&l, &ev, item_for(plan, index, *s, e, ov), item_for(plan, index, *s, e, with_change)});
    }
  }
  if (experiments.empty() && unexplained == 0 && not_shown == 0)
    throw InputError(
        "no listing of harness/expectations.json with evidence matches the names and configurations given");
  std::vector<size_t> all(plan.items.size());
  for (size_t i = 0; i < all.size(); ++i) all[i] = i;
  std::vector<RunResult> records;
  try {
    records = run_items(plan, all, runner_def(jobs, timeout_s), [](size_t, const RunResult&, double) {});
  } catch (const RunnerStopped& e) {
    throw Interrupted(pending_signal(), e.what());
  }
  throw_if_interrupted("during explain");
  int failing = 0;
  for (const Experiment& x : experiments) failing += report(x, records.at(x.base), records.at(x.changed), json) ? 0 : 1;
  if (!json)
    std::cout << fmt::format(
        "{} experiments: {} hold, {} do not; {} listings name no cause (none of the experiments tried moved their "
        "figure), {} name one without an experiment\n",
        experiments.size(), experiments.size() - failing, failing, not_shown, unexplained);
  return failing == 0 && unexplained == 0 ? 0 : 1;
}

}  // namespace

Command add_explain(CLI::App& app) {
  struct Options {
    std::vector<std::string> names;
    std::string engines;
    bool compiled_in = false;
    int jobs = 1;
    double timeout_s = 120.0;
    bool json = false;
    std::string plan;
  };
  auto o = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "explain", "re-run the experiments behind the known failures' reasons and say whether each still holds");
  cmd->add_option("names", o->names, "scenarios, or sweep:NAME for a sweep's listings (default: every listing)");
  cmd->add_option("--engine,--engines", o->engines, "configurations, comma-separated (default: every listed one)");
  cmd->add_flag("--compiled-in", o->compiled_in,
                "only the compiled-in configurations' listings (no outside engine is started)");
  cmd->add_option("--jobs", o->jobs, "runs at once")->capture_default_str();
  cmd->add_option("--timeout", o->timeout_s, "limit of each run's CPU time in seconds")->capture_default_str();
  cmd->add_flag("--json", o->json, "one JSON object per experiment");
  cmd->add_option("--measure", o->plan,
                  "measure the experiments of a plan file instead of the listed ones (tests/tools/write_evidence.py)");
  return {cmd,
          [o] { return cmd_explain(o->names, o->engines, o->compiled_in, o->plan, o->jobs, o->timeout_s, o->json); }};
}

}  // namespace liftcheck::cli
