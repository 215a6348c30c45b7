// The figures of merit, computed once from the typed records and printed by every output (the
// index and scenario pages, summary.md, JUnit's messages, the console): a suite's counts, each
// configuration's standing (its counts and worst failure), the figure that decided each run, and
// a run's headline.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "input/suite_result.hpp"

namespace liftcheck {

/// The counts of a suite, by verdict, and what makes it not as expected.
struct Summary {
  int total = 0, pass = 0, known = 0, unexpected_pass = 0, fail = 0, error = 0, skip = 0;
  int runs_unexpected = 0;  ///< runs not as expected
  int sweep_gates = 0, sweep_gates_failed = 0;
  int baseline_problems = 0;  ///< regressions and metrics grown against the baseline
  /// Runs not as expected and gates failed: what makes validate exit 1 (with the baseline's).
  int unexpected() const { return runs_unexpected + sweep_gates_failed; }
  bool all_as_expected() const { return unexpected() == 0 && baseline_problems == 0; }
};
Summary summarize(const SuiteResults& results);

/// Every sweep's and the outcome grid's gate: (sweep name, configuration, gate).
struct GateRef {
  std::string sweep, engine;
  const Gate* gate;
};
std::vector<GateRef> gates_of(const SuiteResults& results);

/// The figure that decided a run: its failing counted metric furthest from tolerance (a finite
/// multiple before a zero tolerance's), and the largest finite multiple among its counted metrics.
struct Deciding {
  std::string metric;           ///< "" when no counted metric failed
  double ratio = 0.0;           ///< its multiple of tolerance (infinite: a zero tolerance, or no finite error)
  double error = NAN;           ///< its compared error
  std::string unit;             ///< its unit, for an absolute error ("" for a relative one)
  double finite = 0.0;          ///< the largest finite multiple of tolerance among the counted metrics
  bool zero_tolerance = false;  ///< a metric failed against a zero tolerance (or with no finite error)
  /// "249× (slide_accel)" or "87 against a zero tolerance (slide_shortfall)": how far off, in text.
  std::string text() const;
};
Deciding deciding_of(const RunResult& r);

/// A configuration's standing: its counts and its worst failure, negative controls aside.
struct Standing {
  std::string engine;
  bool reference = false;
  int pass = 0, known = 0, skip = 0, unexpected = 0, controls = 0, runs = 0;
  std::vector<std::string> unexpected_in;  ///< scenarios of its runs not as expected
  const RunResult* worst = nullptr;        ///< its known failure furthest off (none: none but controls)
  Deciding worst_figure;                   ///< what decided that run
  /// Its worst failure in text: "249× car.yawed-slide slide_accel", "an error (listed) in car.slope",
  /// "87 against a zero tolerance in car.beyond-grip slide_shortfall"; "" when it has none.
  std::string worst_text() const;
  /// The worst failure's multiple and scenario ("395× car.covariance"), where it has a finite one;
  /// worst_text() otherwise: the index row, which must fit its column.
  std::string worst_short_text() const;
  /// "19 pass, 3 known, 0 skip" and, when some are, "2 not as expected".
  std::string counts_text() const;
};
/// Each configuration's standing, in the context's order.
std::vector<Standing> standings(const SuiteResults& results);
/// The rank of a known failure among a configuration's: by its largest finite multiple; a run off
/// only against a zero tolerance, or a listed error, ranks last.
double standing_rank(const RunResult& r, const Deciding& d);

/// The figure a scenario is read by (its headline): the largest compared error among the metrics
/// its scenario names, scaled as declared, in its unit; none when the run measured none of them.
struct Figure {
  std::string metric;
  double value = 0.0;
  std::string unit;
  double ratio = 0.0;        ///< its compared error over its tolerance
  std::string text() const;  ///< "1.1e-7", "257 µm/s"
};
std::optional<Figure> headline_figure(const RunResult& r, const ScenarioInfo* scenario);
/// The counted metric out of tolerance by the largest ratio, its compared error in its unit.
std::optional<Figure> worst_failing(const RunResult& r);
/// A number in two significant digits, short: "0", "0.65", "21", "257", "6.8e-4", "1.5e9".
std::string short_number(double v);
/// "42×", "∞×" (a multiple of tolerance; UTF-8).
std::string times_text(double ratio);

}  // namespace liftcheck
