// Runs one scenario on one engine and scores it against the scenario's tolerance data.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "engines/engine.hpp"
#include "harness/expectations.hpp"
#include "input/run_result.hpp"
#include "scenarios/scenario.hpp"

namespace liftcheck {

/// A run's record: input/run_result.hpp (one typed value from the worker to every page).
using RunRecord = RunResult;

/// The listing a known failure gives a run (its ceilings or its error, reason and figure).
Expectation expectation_of(const KnownFailure& k);

/// What a --set key is to a run of `scenario` on `engine`: a parameter of the scenario (first), a
/// setting of the engine for the scenario's vehicle, or neither. The one place that decides it.
enum class KeyOwner { kParameter, kSetting, kNeither };
KeyOwner key_owner(const Scenario& scenario, const EngineInfo& engine, const std::string& key);

/// A run with everything it takes resolved once: the scenario's parameters and the engine's
/// settings, typed and validated (what the worker runs).
struct ResolvedRun {
  const Scenario* scenario = nullptr;
  const EngineInfo* engine = nullptr;
  Params params;
  Settings settings;
};

/// Resolves a run: splits `overrides` (split_settings), then the parameters over the scenario's
/// defaults. InputError on a bad name or value, with the messages of split_settings and
/// Params::resolve.
ResolvedRun resolve_run(const Scenario& scenario, const EngineInfo& engine, const Overrides& overrides);

/// A resolved run as the suite sends it to a worker: its parameters and settings by value.
nlohmann::json resolved_values(const ResolvedRun& run);
/// The run `values` (resolved_values) describe, on `scenario` and `engine`, read back as they are:
/// nothing is resolved or checked by key again.
ResolvedRun resolved_from_values(const Scenario& scenario, const EngineInfo& engine, const nlohmann::json& values);

/// Runs a resolved run and scores it. Engine failures become an error record; InputError raised by
/// the scenario for non-physical combinations propagates. A run whose parameters and settings are
/// the defaults carries its known failure, if the expectations list one.
RunRecord run_scenario(const ResolvedRun& run);
/// run_scenario(resolve_run(scenario, engine, overrides)).
RunRecord run_scenario(const Scenario& scenario, const EngineInfo& engine, const Overrides& overrides = {});
/// Runs of scenarios that judge one drive (Scenario::shared_drive of the same name, the same
/// configuration, parameters and settings): the drive is made once, by the first run's scenario,
/// and each record is its own scenario's judgement of it, as run_scenario would give it (the drive's
/// simulated and engine seconds in each). Engine failures make every record an error.
std::vector<RunRecord> run_shared_drive(const std::vector<ResolvedRun>& runs);

/// The checks of run_scenario that come before the engine works, without running it, on a run
/// resolved (its parameters and settings checked): the configuration's wheels, and the scenario's own checks up to its
/// first engine call (dt and sample_dt against the steps and samples a run may take,
/// check_run_budget). InputError as run_scenario would raise it; validate calls it for every run a
/// --set changes, so that a bad value is exit 2 before the suite runs, not an error record per run.
void check_run_inputs(const ResolvedRun& run);

/// Splits `overrides` into the scenario's parameters and the engine's settings for the scenario's
/// vehicle, validates the settings and fills in their defaults. A key that is neither a parameter
/// of the scenario nor a setting of this engine is an InputError (naming the engine's settings when
/// another engine has it).
std::pair<Overrides, Settings> split_settings(const Scenario& scenario, const EngineInfo& engine,
                                              const Overrides& overrides);

/// Scores an outcome against the metric definitions' tolerances of `role` (a configuration's is
/// tolerance_role()). Bookkeeping metrics' tolerances are multiplied by `bookkeeping_factor` (the
/// engine's precision).
std::vector<Metric> score(const Scenario& scenario, TolRole role, const Outcome& outcome,
                          double bookkeeping_factor = 1.0);

/// The reference's role for the exact model; every other configuration is held to the same default
/// tolerances.
TolRole tolerance_role(const EngineInfo& engine);

}  // namespace liftcheck
