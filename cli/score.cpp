// liftcheck score: a simulator's trace of a scenario scored exactly as an engine run.
#include <fmt/format.h>
#include <iostream>

#include "cli/command.hpp"
#include "cli/interrupts.hpp"
#include "cli/lookup.hpp"

namespace liftcheck::cli {

namespace {

int cmd_score(const std::string& scenario, const std::string& trace_file, const std::vector<std::string>& sets,
              const std::string& name, bool json) {
  const Scenario& s = scenario_or_throw(scenario);
  if (name.empty() || find_engine(name))
    throw InputError(fmt::format("--name '{}' must be new (not a built-in configuration)", printable(name)));
  const Overrides ov = overrides_or_throw(sets, s, nullptr);
  // Read and checked here (a bad trace is exit 2 at once), scored in a worker like every run: an
  // interruption stops it, the time limit holds.
  SuitePlan plan;
  auto owned = std::make_shared<const EngineInfo>(replay_engine(name, s, read_trace(trace_file, s.vehicle)));
  SuiteItem item = planned_item(SuiteItem::kRun, "score", s, *owned, ov);
  item.owned = std::move(owned);
  item.trace_file = trace_file;  // the worker reads it again, from the same working folder
  item.full_traces = true;
  plan.items.push_back(std::move(item));
  return run_one(plan, runner_def(1, 120.0), json, "during the score");
}

}  // namespace

Command add_score(CLI::App& app) {
  struct Options {
    std::string scenario, trace_file, name = "external";
    std::vector<std::string> sets;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* score = app.add_subcommand("score", "score a simulator's trace of a scenario exactly as an engine run");
  score->add_option("scenario", o->scenario, "scenario name (see 'liftcheck list')")->required();
  score
      ->add_option("--trace", o->trace_file,
                   "CSV with a header t,alpha,beta,x,y,phi (cars) or t,cMx,cMy,cNx,cNy (disks), or JSON")
      ->required();
  score->add_option("--set", o->sets, "override a parameter, KEY=VALUE (repeatable), as given to 'liftcheck path'")
      ->allow_extra_args(false);
  score->add_option("--name", o->name, "the configuration name in the record")->capture_default_str();
  score->add_flag("--json", o->json, "print the run record as one JSON object");
  return {score, [o] { return cmd_score(o->scenario, o->trace_file, o->sets, o->name, o->json); }};
}

}  // namespace liftcheck::cli
