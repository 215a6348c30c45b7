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

#include "input/run_result.hpp"  // Ceilings, beyond_ceilings

namespace liftcheck {

/// "metrics": {NAME: CEILING, ...} of an expectations entry; std::logic_error if malformed.
Ceilings parse_ceilings(const nlohmann::json& metrics, const std::string& where);

/// The experiment behind a reason that names a cause (a reason is a claim): the run as listed, and
/// the same run with `change` (settings or scenario parameters, as --set takes them). The listed
/// failing figure, `metric`'s compared error, moves from `from` to `to`: the cause the reason names
/// is what the change removes (or strengthens). `liftcheck explain` re-runs both.
struct Evidence {
  std::vector<std::pair<std::string, std::string>> change;
  std::string metric;
  double from = 0.0, to = 0.0;  ///< the compared errors when the evidence was written
  /// "from": "error": the listed run ends in an error (a known error listing), and the change lets
  /// it finish with `metric` at `to`.
  bool from_error = false;
  double x = 0.0;  ///< a sweep listing's point: the swept value the experiment runs at
  /// Holds when the runs made now reproduce it: the listed run still fails the metric (beyond
  /// `tolerance`, its own), each figure within kReproduce of its recorded value (a recorded `to`
  /// within the changed run's tolerance `to_tolerance`: within it again), and the change moving
  /// the figure the recorded way by at least kMove.
  static constexpr double kReproduce = 2.0, kMove = 2.0;
  bool holds(double from_now, double to_now, double tolerance, double to_tolerance) const;
  /// from_error: the listed run ended in an error now too, and the changed run gives `to` again.
  bool holds_from_error(bool errs_now, double to_now, double tolerance) const;
  /// "velocity_steps=100, slop=0.001"
  std::string change_text() const;
};
/// "evidence": [{"change": {KEY: VALUE}, "metric", "from", "to"[, "x"]}]; std::logic_error if malformed.
std::vector<Evidence> parse_evidence(const nlohmann::json& listing, const std::string& where);
/// A negative control's reason starts so: its cause is the scenario's physics, not the engine's.

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
  std::vector<Evidence> evidence = {};  ///< the experiments behind a reason that names a cause
};

/// A listing of harness/expectations.json as reviewed: a run's ("runs") or a sweep's
/// ("sweep_points"), with the reason it gives and the experiments behind it, once per configuration.
/// How the reason of a listing without evidence begins: it states the measured failure, no cause.
inline constexpr const char* kCauseNotShown = "cause not shown: ";

struct ListedReason {
  std::string scenario;  ///< a run's scenario, or the sweep's name for a sweep listing
  bool sweep = false;
  std::string engine;
  std::vector<std::pair<std::string, std::string>> params;  ///< a run listing's "params"
  std::string reason;
  std::vector<Evidence> evidence;
  /// "cause_not_shown": the experiments tried, none of which moved a listed figure twofold. Such a
  /// listing's reason says what is measured and names no cause; it begins with
  /// kCauseNotShown. explain names each; a listing has evidence, this, or a negative control's reason.
  std::string cause_not_shown = {};
  /// "negative_control": the listed run is one (the scenario declares it, or the listing's params
  /// make a variant that cannot pass, such as parallel steering): its failure is the scenario's
  /// physics, not a finding about the engine, so it needs no experiment. Data, never read from
  /// the reason's words.
  bool negative_control = false;
};
const std::vector<ListedReason>& listed_reasons();

/// The "runs" entries, one per scenario x configuration.
const std::vector<KnownFailure>& known_run_failures();
/// The entry for a default run of `scenario` on `engine` (no "params"), or null.
const KnownFailure* find_known_failure(const std::string& scenario, const std::string& engine);
/// Every entry for `scenario` on `engine`, default run or not (the runner matches their params).
std::vector<const KnownFailure*> known_failures_of(const std::string& scenario, const std::string& engine);

}  // namespace liftcheck
