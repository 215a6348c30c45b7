// One run's result, typed, from the worker to every page (google/benchmark's `Run`): what ran, its
// metrics, the listing it is judged against and its verdict. The verdict, whether the run is as
// expected and how it exceeds its listing are decided by one function, `decide`, from the run's
// own fields; every reader (the suite, the sweeps, the pages, CI's files, the console) reads them
// from here. JSON is only where bytes enter or leave (input/results_codec.hpp).
#pragma once

#include <cmath>
#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "input/params.hpp"
#include "input/vehicle.hpp"

namespace liftcheck {

/// How a run ended: every counted metric within tolerance, one or more out of it, no outcome (the
/// engine failed, or the run could not be made), or not run (the configuration lacks what it needs).
enum class Status { kPass, kFail, kError, kSkip };
const char* to_string(Status s);  ///< "pass", "fail", "error", "skip"
std::optional<Status> parse_status(std::string_view text);

/// A run judged against its listing: a pass, a reviewed known failure (a listed failure within its
/// ceilings, or a negative control failing as it must), a listed failure that passes, a failure or
/// error that is not as expected, a skip.
enum class Verdict { kPass, kKnownFailure, kUnexpectedPass, kFail, kError, kSkip };
/// "pass", "known failure", "unexpected pass", "fail", "error", "skip"
const char* to_string(Verdict v);
std::optional<Verdict> parse_verdict(std::string_view text);

/// A metric's tolerance compares its relative or its absolute error.
enum class TolKind { kRelative, kAbsolute };
/// "rel" or "abs", as results.json writes it.
inline const char* to_string(TolKind k) { return k == TolKind::kRelative ? "rel" : "abs"; }

/// Error over tolerance: `error` / `tolerance` (a zero tolerance: infinite for any error); with a
/// floor above 0, at most abs_error / floor. NaN figures count as infinite.
double metric_ratio(double error, double tolerance, double abs_error, double floor);

/// A scored metric of a run.
struct Metric {
  std::string name, unit;
  double expected = NAN, measured = NAN, abs_error = NAN, rel_error = NAN, tolerance = NAN;
  TolKind kind = TolKind::kAbsolute;
  bool pass = false;
  double floor = 0.0;          ///< absolute floor of a relative metric (0: none)
  bool informational = false;  ///< shown only: not a pass, not a fail

  /// The error its tolerance is compared with: relative or absolute, by kind.
  double compared_error() const { return kind == TolKind::kRelative ? rel_error : abs_error; }
  /// The compared error over the tolerance (metric_ratio).
  double ratio() const { return metric_ratio(compared_error(), tolerance, abs_error, floor); }
  bool counted() const { return !informational; }
  /// What `pass` must be for these figures: the compared error within the tolerance, or the
  /// absolute error within the floor (score() decides it so; a file is checked against it).
  bool passes_by_figures() const;
  bool operator==(const Metric&) const;
};

/// Metric name -> the largest error its listed failure may show (the compared error).
using Ceilings = std::map<std::string, double>;

/// The listing a run is judged against, as the run carries it (harness/expectations.json, or a
/// registration's own file): the metrics that may fail with their ceilings, or the start of the
/// error message a run that cannot finish ends with; its reason and figure when reviewed.
struct Expectation {
  Ceilings ceilings;
  std::string error;  ///< a listed error: the start of its message ("" for a listing of metrics)
  std::string reason, measured;
  bool operator==(const Expectation&) const = default;
};

/// What a verdict is decided from, and nothing else: the run's end, its metrics, its listing and
/// whether its scenario is a negative control.
struct VerdictInputs {
  struct Figure {
    std::string_view name;
    double compared_error;  ///< NaN when not finite
    bool pass, counted;
  };
  Status status = Status::kError;
  std::string_view message;
  std::vector<Figure> metrics;
  const Expectation* expectation = nullptr;
  bool negative_control = false;
};

/// A verdict decided.
struct Decision {
  Verdict verdict = Verdict::kError;
  bool as_expected = false;
  /// How the run's failures exceed its listing (a metric not listed, an error above its ceiling, a
  /// listed metric not measured); empty without a listing.
  std::vector<std::string> beyond;
};

/// The one function that decides a run's verdict. A skip is as expected. A negative control with
/// no listing is as expected when it fails (its comparison is meant to fail) and not when it passes
/// or errs. A run with no listing is as expected when it passes. A listed error is as expected
/// when the run ends in an error whose message starts with it. A listing of metrics is as expected
/// when the run fails in at least one of them and only in them, each within its ceiling.
Decision decide(const VerdictInputs& in);

/// The problems of failing metrics (name, error) against ceilings: a metric not listed, or an
/// error above its ceiling. Empty when within them.
std::vector<std::string> beyond_ceilings(const Ceilings& ceilings,
                                         const std::vector<std::pair<std::string, double>>& failed);

struct RunResult {
  std::string scenario, engine;
  Vehicle vehicle = Vehicle::kCar;
  Params params;                                ///< the scenario's parameters as run
  std::map<std::string, std::string> settings;  ///< the configuration's settings as applied, as text
  Status status = Status::kError;
  std::string message;
  std::vector<Metric> metrics;  ///< in the scenario's order
  std::optional<Expectation> expectation;
  /// Its scenario is a negative control (Scenario::negative_control): its comparison must fail.
  bool negative_control = false;
  Decision decision;  ///< decide() of the fields above (judge())
  /// Free-form details the scenario recorded for the reports and sweeps (traces, fits), under the
  /// keys of scenarios/details.hpp.
  nlohmann::json details = nlohmann::json::object();
  double wall_s = 0.0;
  double simulated_s = 0.0;  ///< simulated time the engine stepped
  double engine_s = NAN;     ///< an outside engine's own stepping time as it reports it (NaN: in process)
  /// The worker's pipe only: the run's parameters were rejected by its scenario (`run` exits 2).
  bool input_error = false;
  /// The worker's pipe only: the records of the runs that judged this run's drive.
  std::vector<RunResult> shared;

  /// Decides the verdict (decision) from the fields: call after changing them.
  void judge();
  VerdictInputs verdict_inputs() const;
  Verdict verdict() const { return decision.verdict; }
  bool as_expected() const { return decision.as_expected; }
  /// The counted metrics out of tolerance, in the record's order.
  std::vector<std::string> failed_metrics() const;
  const Metric* metric(std::string_view name) const;
  /// Its metrics, worst first (the largest ratio to tolerance), in name order on ties.
  std::vector<const Metric*> metrics_worst_first() const;
  /// Largest error relative to its tolerance over the counted metrics (<= 1 when all pass).
  double worst_ratio() const;
  /// Largest relative error over the metrics compared relatively (NaN if there are none).
  double worst_rel_error() const;
};

/// A run's identity in every file liftcheck reads: scenario, configuration, parameters and
/// settings ("car.circle on ode (wheels=4, iterations=20)" names it in messages).
std::string run_identity(const RunResult& r);
/// The same as a key that orders and compares runs.
std::string run_key_of(const RunResult& r);

/// An error record for `scenario` on `engine`.
RunResult error_result(const std::string& scenario, const std::string& engine, Vehicle vehicle,
                       const std::string& message);

}  // namespace liftcheck
