// liftcheck run: one scenario on one configuration, in a worker process like every validate run.
#include <fmt/format.h>
#include <iostream>

#include "cli/command.hpp"
#include "cli/interrupts.hpp"
#include "cli/lookup.hpp"
#include "engines/protocol/outside.hpp"

namespace liftcheck::cli {

namespace {

int cmd_run(const std::string& scenario, const std::string& engine, const std::vector<std::string>& sets, bool json,
            double timeout_s, double memory_limit_mib) {
  const Scenario& s = scenario_or_throw(scenario);
  const RunnerDef runner = runner_def(1, timeout_s, memory_limit_mib);
  const EngineInfo& e = engine_or_throw(engine);
  close_idle_children();  // its worker starts its own
  const Overrides ov = overrides_or_throw(sets, s, &e);
  SuitePlan plan;
  plan.items.push_back(planned_item(SuiteItem::kRun, "run", s, e, ov));
  plan.items.back().full_traces = true;  // --json prints the traces as the scenario recorded them
  // Bad names and values are input errors here, not error records.
  if (!plan.items.back().run) throw InputError(plan.items.back().resolve_error);
  // In a worker process, like every validate run: a hang or a crash of the engine is an error record.
  return run_one(plan, runner, json, "during the run");
}

}  // namespace

Command add_run(CLI::App& app) {
  struct Options {
    std::string scenario, engine = reference_engine().name;
    std::vector<std::string> sets;
    bool json = false;
    double timeout_s = 120.0;
    double memory_limit_mib = kDefaultRunMemoryMiB;
  };
  auto o = std::make_shared<Options>();
  auto* run = app.add_subcommand("run", "run one scenario on one engine");
  run->add_option("scenario", o->scenario, "scenario name (see 'liftcheck list')")->required();
  run->add_option("--engine", o->engine, "engine configuration (see 'liftcheck engines')")->capture_default_str();
  run->add_option("--set", o->sets, "override a parameter, KEY=VALUE (repeatable)")->allow_extra_args(false);
  run->add_flag("--json", o->json, "print the run record as one JSON object");
  run->add_option("--timeout", o->timeout_s,
                  "limit of the run's own CPU time in seconds: beyond it the engine is stopped and the run is an error")
      ->capture_default_str();
  run->add_option("--memory-limit", o->memory_limit_mib,
                  "limit of the worker process's address space in MiB: a run that needs more is an error")
      ->capture_default_str();
  return {run, [o] { return cmd_run(o->scenario, o->engine, o->sets, o->json, o->timeout_s, o->memory_limit_mib); }};
}

}  // namespace liftcheck::cli
