// Typed results made by hand for the tests of the readers and the pages: metrics with their
// figures, runs of every kind (pass, known failure, a listed error, a zero tolerance, a negative
// control, a true skip, not as expected) and a suite holding them.
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "input/results_codec.hpp"
#include "input/suite_result.hpp"

namespace liftcheck::fixture {

/// A metric scored as score() scores one: its errors from expected and measured, pass by its figures.
inline Metric metric(const std::string& name, TolKind kind, double expected, double measured, double tolerance,
                     const std::string& unit = "m", bool informational = false) {
  Metric m;
  m.name = name, m.unit = unit, m.kind = kind, m.expected = expected, m.measured = measured;
  m.tolerance = tolerance, m.informational = informational;
  m.abs_error = std::abs(measured - expected);
  m.rel_error = expected != 0.0 ? m.abs_error / std::abs(expected) : (m.abs_error == 0.0 ? 0.0 : INFINITY);
  if (kind == TolKind::kAbsolute && expected == 0.0) m.rel_error = NAN;
  m.pass = m.passes_by_figures();
  return m;
}

/// A run ending with its metrics' status (or `status` when given), judged.
inline RunResult run(const std::string& scenario, const std::string& engine, std::vector<Metric> metrics,
                     std::optional<Expectation> expectation = std::nullopt, bool negative_control = false,
                     std::optional<Status> status = std::nullopt, const std::string& message = "") {
  RunResult r;
  r.scenario = scenario, r.engine = engine, r.vehicle = Vehicle::kCar;
  r.params = Params::from_json({{"dt", 0.001}, {"wheels", "3"}});
  r.metrics = std::move(metrics);
  bool fails = false;
  for (const Metric& m : r.metrics) fails = fails || (!m.pass && m.counted());
  r.status = status ? *status : fails ? Status::kFail : Status::kPass;
  r.message = message;
  r.expectation = std::move(expectation);
  r.negative_control = negative_control;
  r.wall_s = 0.01, r.simulated_s = 1.0;
  r.judge();
  return r;
}

inline Expectation listing(Ceilings ceilings, const std::string& reason = "cause not shown: it fails") {
  return {std::move(ceilings), "", reason, "measured when reviewed"};
}

inline ScenarioInfo scenario(const std::string& name, const std::string& headline_metric, bool control = false) {
  ScenarioInfo s;
  s.name = name;
  s.summary = "what " + name + " checks";
  s.equations = "(4.1)";
  s.negative_control = control;
  s.headline_metrics = {headline_metric};
  s.headline_label = headline_metric;
  return s;
}

inline EngineContext engine(const std::string& name, bool reference = false) {
  EngineContext e;
  e.name = name, e.library = name, e.version = "1", e.description = name + " as shipped";
  e.color = reference ? "#000000" : "#1f77b4";
  e.is_reference = reference;
  e.vehicles = {Vehicle::kCar};
  return e;
}

/// A suite with one run of every kind on three configurations: "ref" passes all; "alpha" has a
/// known failure at 40x in s.two (its worst), one at 3x in s.one, a zero-tolerance known failure
/// in s.three, a listed error in s.four and the negative control failing unlisted; "beta" has a
/// true skip, a failure not as expected in s.one (12x), an unexpected pass in s.two and a listed
/// error that ended otherwise.
inline SuiteResults suite_of_every_kind() {
  SuiteResults r;
  r.context.version = "0.1.0", r.context.commit = "c0ffee", r.context.date = "2026-12-07T00:00:00Z";
  r.context.machine = {"host", "Linux", "g++", 2};
  r.context.engines = {engine("ref", true), engine("alpha"), engine("beta")};
  r.context.jobs = 2, r.context.timeout_s = 120.0;
  r.scenarios = {scenario("s.one", "a"), scenario("s.two", "b"), scenario("s.three", "c"), scenario("s.four", "d"),
                 scenario("s.control", "e", true)};
  using TK = TolKind;
  const auto a = [](double err) { return metric("a", TK::kAbsolute, 0.0, err, 1e-3); };
  const auto b = [](double err) { return metric("b", TK::kRelative, 2.0, 2.0 * (1 + err), 1e-4); };
  for (const char* sc : {"s.one", "s.two", "s.three", "s.four", "s.control"})
    r.runs.push_back(run(sc, "ref", {a(1e-9), b(1e-9)}));
  r.runs.push_back(run("s.one", "alpha", {a(3e-3), b(1e-9)}, listing({{"a", 6e-3}})));
  r.runs.push_back(run("s.two", "alpha", {a(1e-9), b(4e-3)}, listing({{"b", 8e-3}})));
  r.runs.push_back(
      run("s.three", "alpha", {metric("c", TK::kAbsolute, 0.0, 87.0, 0.0, "N"), a(1e-9)}, listing({{"c", 174.0}})));
  Expectation listed_error{{}, "car left the ground", "cause not shown: it leaves the ground", "an error"};
  r.runs.push_back(run("s.four", "alpha", {}, listed_error, false, Status::kError, "car left the ground at 1 s"));
  r.runs.push_back(run("s.control", "alpha", {a(5.0), b(1e-9)}, std::nullopt, true));  // 5000x, a control
  r.runs.push_back(run("s.one", "beta", {a(12e-3), b(1e-9)}));
  r.runs.push_back(run("s.two", "beta", {a(1e-9), b(1e-9)}, listing({{"b", 8e-3}})));
  r.runs.push_back(run("s.three", "beta", {}, std::nullopt, false, Status::kSkip, "engine 'beta' has no car"));
  r.runs.push_back(run("s.four", "beta", {a(2e-3)}, listed_error));
  r.runs.push_back(run("s.control", "beta", {a(5.0)}, std::nullopt, true));
  return r;
}

}  // namespace liftcheck::fixture
