// liftcheck tune: the cheapest settings of one configuration that pass one scenario (harness/tune.hpp
// searches; this prints the walk, the answer and writes them with a plot to --out).
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <thread>

#include "cli/command.hpp"
#include "cli/interrupts.hpp"
#include "cli/lookup.hpp"
#include "cli/staged_output.hpp"
#include "engines/protocol/outside.hpp"
#include "harness/expectations.hpp"
#include "harness/sweeps.hpp"
#include "harness/tune.hpp"
#include "input/atomic_file.hpp"
#include "input/trace.hpp"
#include "reports/plots.hpp"

namespace liftcheck::cli {

namespace {

/// Each batch of the walk as one plan, run in workers like every validate run (a hang or a crash
/// of the engine is an error record).
TuneRunner runner_for(const Scenario& s, const EngineInfo& e, const RunnerDef& runner) {
  return [&s, &e, runner](const std::vector<Overrides>& changes) {
    SuitePlan plan;
    for (const Overrides& c : changes)
      plan.items.push_back(
          planned_item(SuiteItem::kRun, fmt::format("tune/{}/{}/{}", s.name, e.name, change_text(c)), s, e, c));
    std::vector<size_t> all(plan.items.size());
    for (size_t i = 0; i < all.size(); ++i) all[i] = i;
    try {
      return run_items(plan, all, runner, [](size_t, const RunResult&, double) {});
    } catch (const RunnerStopped& x) {
      throw Interrupted(pending_signal(), x.what());
    }
  };
}

std::string worst_text(const TuneStep& st) {
  if (st.record.status == Status::kError) return "error";
  if (st.pass) return fmt::format("{:.2g}", st.worst_ratio);
  std::string worst;
  double w = -1.0;
  for (const Metric& m : st.record.metrics)
    if (!m.pass && m.counted() && m.ratio() > w) w = m.ratio(), worst = m.name;
  return fmt::format("{:.2g} {}", st.worst_ratio, worst);
}

void print_walk(const TuneResult& r) {
  const double base = r.walked.front().cost_ms_per_s;
  std::cout << fmt::format("{:>3}  {:<8} {:<44} {:<5} {:<30} {:>8} {:>10} {:>8}\n", "#", "phase", "settings", "pass",
                           "worst x tol", "model x", "ms per s", "x dflt");
  for (size_t i = 0; i < r.walked.size(); ++i) {
    const TuneStep& st = r.walked[i];
    std::cout << fmt::format("{:>3}  {:<8} {:<44} {:<5} {:<30} {:>8.3g} {:>10.3g} {:>8.2f}{}\n", i, st.phase,
                             printable(change_text(st.change), 200), st.pass ? "yes" : "no", worst_text(st),
                             st.model_cost, st.cost_ms_per_s, st.cost_ms_per_s / base,
                             r.answer && *r.answer == i ? "  <- cheapest pass" : "");
  }
}

std::string answer_text(const Scenario& s, const EngineInfo& e, const TuneResult& r) {
  if (r.stopped == "error")
    return fmt::format(
        "{} on {}: the default run is an error ({}); with no default verdict there is nothing to "
        "judge other settings against",
        s.name, printable(e.name), printable(r.walked.front().record.message, 300));
  const double base = r.walked.front().cost_ms_per_s;
  const std::string budget =
      r.unmade > 0 ? fmt::format(" (the budget of {} runs left {} planned runs unmade)", r.budget_runs, r.unmade) : "";
  if (r.answer) {
    const TuneStep& a = r.walked[*r.answer];
    return fmt::format(
        "{} on {} passes at {}: {:.3g} ms per simulated second measured, {:.2f} times the default's {:.3g} (cost "
        "model {:.3g} times){}",
        s.name, printable(e.name), printable(change_text(a.change), 300), a.cost_ms_per_s, a.cost_ms_per_s / base, base,
        a.model_cost, budget);
  }
  const TuneStep& c = r.walked[r.closest];
  return fmt::format(
      "{} on {}: nothing tried passes ({} runs){}; closest {}, its worst metric {:.3g} times the default run's "
      "tolerance, at {:.3g} ms per simulated second, {:.2f} times the default's {:.3g}",
      s.name, printable(e.name), r.walked.size(), budget, printable(change_text(c.change), 300), c.worst_ratio,
      c.cost_ms_per_s, c.cost_ms_per_s / base, base);
}

/// The car's masses are the scenario's, not settings: for each sweep that varies one on this
/// scenario, what its reviewed listing says of this configuration (where and why it fails), that it
/// lists nothing, or that the configuration does not join the sweeps.
std::vector<std::string> mass_notes(const Scenario& s, const EngineInfo& e) {
  std::vector<std::string> notes;
  for (const SweepDef& sw : sweep_catalogue()) {
    if (sw.scenario != s.name || sw.param.find("mass") == std::string::npos) continue;
    std::string listed;
    for (const ListedReason& l : listed_reasons())
      if (l.sweep && l.scenario == sw.name && l.engine == e.name) listed = l.reason;
    if (e.points == SuitePoints::kRuns)
      notes.push_back(
          fmt::format("{} varies {} on this scenario; {} joins no sweep, so whether its verdict depends "
                      "on the masses is not measured",
                      sw.name, sw.param, e.name));
    else if (listed.empty())
      notes.push_back(
          fmt::format("{} varies {} on this scenario and lists no failure of {}: its verdict holds over "
                      "the swept masses",
                      sw.name, sw.param, e.name));
    else
      notes.push_back(fmt::format("{} varies {} on this scenario and lists {} failing at some of its points: {}",
                                  sw.name, sw.param, e.name, listed));
  }
  return notes;
}

int cmd_tune(const std::string& scenario, const std::string& engine, int budget, int jobs, double timeout_s,
             const std::string& out_dir, bool json) {
  const Scenario& s = scenario_or_throw(scenario);
  const EngineInfo& e = engine_or_throw(engine);
  if (budget < 1 || budget > 1000) throw InputError(fmt::format("--budget {}: runs between 1 and 1000", budget));
  if ((s.vehicle == Vehicle::kCar && !e.make_car) || (s.vehicle == Vehicle::kDisks && !e.make_disks))
    throw InputError(fmt::format("{} does not build the vehicle {} drives", e.name, s.name));
  if (e.is_reference) throw InputError(fmt::format("{} is the exact reference: it has no settings to tune", e.name));
  const RunnerDef runner = runner_def(jobs, timeout_s);
  std::optional<StagedOutput> out;
  if (!out_dir.empty()) out.emplace(out_dir);
  std::vector<std::string> left_out;
  const std::vector<TuneDimension> dims = tune_dimensions(s, e, &left_out);
  std::string names;
  for (const auto& d : dims) names += (names.empty() ? "" : ", ") + d.key;
  if (!json)
    std::cout << fmt::format("tune: {} on {}, searching {} within at most {} runs\n", s.name, printable(e.name),
                             printable(names, 300), budget);
  for (const auto& l : left_out)
    if (!json) std::cout << "not searched: " << printable(l, 300) << "\n";
  close_idle_children();
  const TuneResult r = tune(dims, TuneDef{.budget_runs = budget}, runner_for(s, e, runner));
  throw_if_interrupted("during tune");
  if (r.stopped == "skip")
    throw InputError(fmt::format("{} does not apply to {}: {}", s.name, printable(e.name),
                                 printable(r.walked.front().record.message, 300)));
  nlohmann::json doc = r.to_json();  // tune.json, what leaves: the walk with every run's record
  const std::string answer = answer_text(s, e, r);
  const std::vector<std::string> notes = mass_notes(s, e);
  doc.update({{"scenario", s.name}, {"engine", e.name}, {"answer_text", answer}, {"mass_notes", notes}});
  if (out) {
    write_file_atomic(out->stage() / "tune.json", doc.dump(1));
    write_tune_plot(doc, out->stage());
    out->publish();
  }
  if (json) {
    std::cout << doc.dump() << "\n";
  } else {
    print_walk(r);
    for (const auto& note : notes) std::cout << "note: the car's masses are not searched; " << note << "\n";
    std::cout << answer << "\n";
  }
  return r.answer ? 0 : 1;
}

}  // namespace

Command add_tune(CLI::App& app) {
  struct Options {
    std::string scenario, engine, out;
    int budget = 40, jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
    double timeout_s = 120.0;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* tune = app.add_subcommand(
      "tune", "search a configuration's settings and dt for the cheapest that pass a scenario (exit 0: one passes)");
  tune->add_option("scenario", o->scenario, "scenario name (see 'liftcheck list')")->required();
  tune->add_option("--engine", o->engine, "engine configuration (see 'liftcheck engines')")->required();
  tune->add_option("--budget", o->budget, "runs at most, the default run's included")->capture_default_str();
  tune->add_option("--jobs", o->jobs, "runs at once (default: the number of cores)")->capture_default_str();
  tune->add_option("--timeout", o->timeout_s, "limit of each run's CPU time in seconds")->capture_default_str();
  tune->add_option("--out", o->out, "a folder for tune.json (every run's record) and plots/tune.svg");
  tune->add_flag("--json", o->json, "print the walk and the answer as one JSON object");
  return {tune, [o] { return cmd_tune(o->scenario, o->engine, o->budget, o->jobs, o->timeout_s, o->out, o->json); }};
}

}  // namespace liftcheck::cli
