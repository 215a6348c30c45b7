// Known failures of the default suite, reviewed data (harness/expectations.json): each is a
// finding about a configuration, with the reason in one sentence, the measured figure, and for
// each metric that fails a ceiling on its error. A listed run must fail, only in its listed
// metrics and no worse than their ceilings (a known failure that gets worse is a regression); a
// listed run that passes is unexpected, so the file stays true. Negative controls are listed the
// same way.
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

namespace liftcheck {

/// Metric name -> the largest error a known failure may show: the error its tolerance is compared
/// with (relative for relative metrics, absolute otherwise), about twice the reviewed figure.
using Ceilings = std::map<std::string, double>;

/// "metrics": {NAME: CEILING, ...} of an expectations entry; std::logic_error if malformed.
Ceilings parse_ceilings(const nlohmann::json& metrics, const std::string& where);

/// The problems of a known failure's failing metrics (name, error) against its ceilings: a metric
/// not listed, or an error above its ceiling. Empty when the failure is as known.
std::vector<std::string> beyond_ceilings(const Ceilings& ceilings, const std::vector<std::pair<std::string, double>>& failed);

struct KnownFailure {
  std::string scenario, engine;
  /// The parameters the run changes from the scenario's defaults ("params": {"wheels": "4"}),
  /// as KEY=VALUE text; empty for the default run. Settings are always the defaults.
  std::vector<std::pair<std::string, std::string>> params;
  Ceilings metrics;  ///< the metrics that may fail (at least one must), each with its ceiling
  std::string reason, measured;
  /// A run the engine cannot finish ("error": the start of its error message, e.g. "car left the
  /// ground"): listed instead of metrics, it must end in an error record whose message starts so.
  std::string error = {};
};

/// The "runs" entries, one per scenario x configuration.
const std::vector<KnownFailure>& known_run_failures();
/// The entry for a default run of `scenario` on `engine` (no "params"), or null.
const KnownFailure* find_known_failure(const std::string& scenario, const std::string& engine);
/// Every entry for `scenario` on `engine`, default run or not (the runner matches their params).
std::vector<const KnownFailure*> known_failures_of(const std::string& scenario, const std::string& engine);

}  // namespace liftcheck
