// liftcheck tune: the cheapest settings of a configuration that pass a scenario. The search walks
// the configuration's declared settings for the scenario's vehicle and the step dt (never the
// scenario's other parameters: the car and the path stay as they are), one at a time on a
// log-spaced ladder around each default, then refines between a passing and a failing neighbour,
// then, where nothing passed, combines the settings that came closest. Every run is judged against
// the default run's tolerances. Which runs it makes and which pass it answers depend only on the
// verdicts, the errors and a cost model of the settings (deterministic); the costs shown beside
// are measured.
#pragma once

#include <cmath>
#include <functional>
#include <limits>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "engines/engine.hpp"
#include "input/run_result.hpp"
#include "scenarios/scenario.hpp"

namespace liftcheck {

struct TuneDef {
  int budget_runs = 40;  ///< runs at most, the default's included
};

/// One searched quantity: the step dt (a scenario parameter) or one of the engine's settings.
struct TuneDimension {
  std::string key;
  ParamKind kind = ParamKind::kNumber;
  std::string default_text;
  double default_value = 0.0;       ///< numbers
  std::vector<std::string> ladder;  ///< the values tried in the first phase, nearest the default first
  double min = 0.0, max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  /// How the engine's cost moves with the value, where it is known: -1 for dt (fewer steps), +1 for
  /// a solver iteration count (SettingRole::kSolverIterations), 0 otherwise. Along such a
  /// dimension the cheapest pass is known from the verdicts alone (the longest step, the fewest
  /// iterations that pass), not from measured costs.
  int cost_direction = 0;
};

/// The dimensions searched for `s` on `e`, and a line for each declared setting left out (why).
std::vector<TuneDimension> tune_dimensions(const Scenario& s, const EngineInfo& e, std::vector<std::string>* left_out);

/// One run of the walk and what it showed.
struct TuneStep {
  std::string phase;  ///< "default", "ladder", "refine", "combine"
  Overrides change;   ///< against the defaults (empty: the default run)
  RunResult record;
  bool pass = false;
  double worst_ratio = std::numeric_limits<double>::infinity();  ///< largest error over its tolerance
  /// Judged against the default run's tolerances (a longer step loosens those that scale with dt).
  double cost_ms_per_s = NAN;  ///< measured: the engine's own time (or the run's wall time) per simulated second
  /// The cost model against the default's: (dt0 / dt) x (iterations / iterations0) for a declared
  /// iteration count; what ranks the passes (measured costs move by 10 to 20% between runs).
  double model_cost = 1.0;
};

struct TuneResult {
  std::vector<TuneStep> walked;  ///< in walk order; walked[0] is the default run
  std::optional<size_t> answer;  ///< the cheapest passing step
  size_t closest = 0;            ///< the smallest worst_ratio
  int budget_runs = 0;
  int unmade = 0;  ///< runs the search planned and the budget did not allow
  /// The default run's status where it is not judged ("error", "skip"): the search stops there,
  /// since there are no default tolerances to judge other settings against. Empty otherwise.
  std::string stopped = {};
  nlohmann::json to_json() const;
};

/// Runs a batch of changes (each a run of the scenario on the engine) and returns their records,
/// in order.
using TuneRunner = std::function<std::vector<RunResult>(const std::vector<Overrides>&)>;

TuneResult tune(const std::vector<TuneDimension>& dims, const TuneDef& def, const TuneRunner& run);

/// "dt=0.002, iterations=80", or "defaults".
std::string change_text(const Overrides& change);

}  // namespace liftcheck
