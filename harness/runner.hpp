// Runs one scenario on one engine and scores it against the scenario's tolerance data.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "engines/engine.hpp"
#include "harness/scenario.hpp"

namespace liftcheck {

enum class Status { kPass, kFail, kError, kSkip };
const char* to_string(Status s);

struct RunRecord {
  std::string scenario, engine;
  nlohmann::json params = nlohmann::json::object();
  nlohmann::json settings = nlohmann::json::object();  ///< the engine's knobs as applied
  Status status = Status::kError;
  std::string message;
  std::vector<Metric> metrics;
  nlohmann::json details = nlohmann::json::object();
  double wall_s = 0.0;
  bool negative_control = false;  ///< the scenario is meant to fail

  /// Pass, skip, or the expected fail of a negative control.
  bool as_expected() const;

  /// Largest error relative to its tolerance over all metrics (<= 1 when all pass).
  double worst_ratio() const;
  /// Largest relative error over the metrics compared relatively (NaN if there are none).
  double worst_rel_error() const;
  nlohmann::json to_json() const;
};

/// Resolves parameters (InputError on bad ones), runs, scores. Engine failures become an error
/// record; InputError raised by the scenario for non-physical combinations propagates.
RunRecord run_scenario(const Scenario& scenario, const EngineInfo& engine, const Overrides& overrides = {});

/// Splits `overrides` into the scenario's parameters and the engine's settings for the scenario's
/// vehicle, validates the settings and fills in their defaults. A key that is neither a parameter
/// of the scenario nor a setting of this engine is an InputError (naming the engine's settings when
/// another engine has it).
std::pair<Overrides, Settings> split_settings(const Scenario& scenario, const EngineInfo& engine, const Overrides& overrides);

/// Scores an outcome against the metric definitions for `engine`.
std::vector<Metric> score(const Scenario& scenario, const std::string& engine, const Outcome& outcome);

}  // namespace liftcheck
