// Scoring, error handling and the analytic engine's records against exact computations.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <fmt/format.h>

#include <chrono>
#include <filesystem>
#include <future>
#include <thread>
#include <unistd.h>

#include "harness/results.hpp"
#include "harness/runner.hpp"
#include "harness/suite_plan.hpp"
#include "harness/suite_results.hpp"
#include "harness/worker_pool.hpp"
#include "harness/sweeps.hpp"
#include "input/results_codec.hpp"
#include "scenarios/disk_scenarios.hpp"
#include "models/holonomy.hpp"
#include "reports/report.hpp"

using namespace liftcheck;

namespace {

/// An engine that blows up: its trace turns to NaN.
class ExplodingCar final : public CarEngine {
 public:
  void reset(const CarSetup&, const car::Config& q0) override { q0_ = q0; }
  std::vector<car::TimedConfig> drive(const car::BasePath& path) override {
    car::Config bad = q0_;
    bad.x_m = std::nan("");
    return {{0.0, q0_}, {path.duration_s(), bad}};
  }
  double simulated_s() const override { return 0.0; }
  std::vector<WheelSlip> slip() const override { return {}; }
  car::Config q0_;
};

class ThrowingCar final : public CarEngine {
 public:
  void reset(const CarSetup&, const car::Config&) override {}
  std::vector<car::TimedConfig> drive(const car::BasePath&) override { throw EngineError("solver diverged"); }
  double simulated_s() const override { return 0.0; }
  std::vector<WheelSlip> slip() const override { return {}; }
};

/// A test double's registry entry: a car engine made by `make`.
EngineInfo stub_engine(std::string name, std::function<std::unique_ptr<CarEngine>(const Settings&)> make) {
  EngineInfo e;
  e.name = std::move(name);
  e.library = "test";
  e.version = "0";
  e.description = "test double";
  e.make_car = std::move(make);
  return e;
}

}  // namespace

TEST(Runner, AnExplodingEngineIsAnErrorRunNotACrash) {
  const EngineInfo bad = stub_engine("exploding", [](const Settings&) { return std::make_unique<ExplodingCar>(); });
  const RunRecord r = run_scenario(*find_scenario("car.cycle"), bad);
  EXPECT_EQ(r.status, Status::kError);
  EXPECT_NE(r.message.find("not finite"), std::string::npos) << r.message;
  const EngineInfo thrower = stub_engine("thrower", [](const Settings&) { return std::make_unique<ThrowingCar>(); });
  const RunRecord t = run_scenario(*find_scenario("car.circle"), thrower);
  EXPECT_EQ(t.status, Status::kError);
  EXPECT_EQ(t.message, "solver diverged");
}

TEST(Runner, EngineWithoutCarIsSkipped) {
  const EngineInfo none{"none", "0", "no vehicles", {}};
  EXPECT_EQ(run_scenario(*find_scenario("car.circle"), none).status, Status::kSkip);
}

TEST(Runner, ScoringUsesPerEngineToleranceData) {
  Scenario s;
  s.name = "t";
  s.metrics = {{"m", "m", TolKind::kRelative, {{TolRole::kReference, 1e-3}, {TolRole::kDefault, 1e-1}}, ""},
               {"z", "m", TolKind::kAbsolute, {{TolRole::kDefault, 1e-6}}, ""}};
  Outcome o;
  o.values["m"] = {2.0, 2.01};
  o.values["z"] = {0.0, 5e-7};
  const auto strict = score(s, TolRole::kReference, o), loose = score(s, TolRole::kDefault, o);
  EXPECT_FALSE(strict[0].pass);
  EXPECT_TRUE(loose[0].pass);
  EXPECT_NEAR(strict[0].rel_error, 0.005, 1e-12);
  EXPECT_TRUE(strict[1].pass);
  o.values["m"].tolerance_factor = 10.0;  // tolerance scaled, e.g. by eps for leading-order metrics
  EXPECT_TRUE(score(s, TolRole::kReference, o)[0].pass);
  o.values["q"] = {1.0, 1.0};
  EXPECT_THROW(score(s, TolRole::kReference, o), std::logic_error);
}

// Precision declared, not assumed: a bookkeeping metric's tolerance scales with the engine's
// precision (1e-9 m becomes 1e-5 m for float32), a physics metric's does not.
TEST(Runner, BookkeepingTolerancesScaleWithDeclaredPrecision) {
  EXPECT_EQ(bookkeeping_factor("float64"), 1.0);
  EXPECT_EQ(bookkeeping_factor("float32"), 1e4);
  Scenario s;
  s.name = "t";
  s.metrics = {{"n_path", "m", TolKind::kAbsolute, {{TolRole::kDefault, 1e-9}}, "", {}, true},
               {"penetration", "m", TolKind::kAbsolute, {{TolRole::kDefault, 1e-9}}, ""}};
  Outcome o;
  o.values["n_path"] = {0.0, 3e-7};  // float32 storage of N's position at a few metres
  o.values["penetration"] = {0.0, 3e-7};
  const auto f64 = score(s, TolRole::kDefault, o, bookkeeping_factor("float64"));
  const auto f32 = score(s, TolRole::kDefault, o, bookkeeping_factor("float32"));
  EXPECT_FALSE(f64[0].pass);
  EXPECT_TRUE(f32[0].pass);
  EXPECT_DOUBLE_EQ(f32[0].tolerance, 1e-5);
  EXPECT_FALSE(f32[1].pass);  // physics: the same tolerance whatever the precision
  EXPECT_DOUBLE_EQ(f32[1].tolerance, 1e-9);
  o.values["n_path"] = {0.0, 2e-5};  // beyond rounding: still a failure in float32
  EXPECT_FALSE(score(s, TolRole::kDefault, o, bookkeeping_factor("float32"))[0].pass);
  // The disk scenarios mark exactly their bookkeeping of the engine against itself and the
  // round-off floor of a free step.
  std::set<std::string> marked;
  for (const MetricDef& m : find_scenario("disks.linear")->metrics)
    if (m.bookkeeping) marked.insert(m.name);
  EXPECT_EQ(marked, (std::set<std::string>{"n_path_error", "contact_missed", "contact_report_gap",
                                           "contact_depth_error", "step_displacement"}));
}

TEST(Runner, CycleRecordMatchesExactHolonomy) {
  // The run of the README: measured and expected against a direct composition of the exact flows.
  const Overrides ov{{"R", "0.3"},   {"l", "1.2"},          {"beta", "0.4"},
                     {"phi", "0.7"}, {"eps_alpha", "0.01"}, {"eps_beta", "0.01"}};
  const RunRecord r = run_scenario(*find_scenario("car.cycle"), *find_engine("analytic"), ov);
  ASSERT_EQ(r.status, Status::kPass) << r.message;
  const car::CarDef c{0.3, 1.2};
  const car::Config q0{0.0, 0.4, 0.0, 0.0, 0.7};
  const car::Config end = car::apply_exact(c, q0, car::simple_cycle(0.01, 0.01));
  const double exact[] = {end.x_m - q0.x_m, end.y_m - q0.y_m, end.phi_rad - q0.phi_rad};
  const char* names[] = {"dx", "dy", "dphi"};
  for (int i = 0; i < 3; ++i) {
    const Metric* m = nullptr;
    for (const auto& x : r.metrics)
      if (x.name == names[i]) m = &x;
    ASSERT_NE(m, nullptr);
    EXPECT_NEAR(m->expected, exact[i], 1e-15 * std::abs(exact[i]) + 1e-300);
    EXPECT_LT(std::abs(m->measured - exact[i]), 1e-9 * std::abs(exact[i])) << names[i];
  }
}

TEST(Runner, CircleRadiiOfTheAnalyticEngine) {
  const RunRecord r = run_scenario(*find_scenario("car.circle"), *find_engine("analytic"), {{"beta", "0.3"}});
  ASSERT_EQ(r.status, Status::kPass) << r.message;
  for (const auto& m : r.metrics) {
    if (m.name == "front_radius") {
      EXPECT_NEAR(m.measured, 1.0 / std::sin(0.3), 1e-9);
    }
    if (m.name == "rear_radius") {
      EXPECT_NEAR(m.measured, 1.0 / std::tan(0.3), 1e-9);
    }
  }
}

TEST(Runner, NonPhysicalCombinationIsAnInputError) {
  EXPECT_THROW(run_scenario(*find_scenario("car.circle"), *find_engine("analytic"), {{"beta", "0"}}), InputError);
}

TEST(Runner, RecordsAreDeterministic) {
  const auto a = encode_run(run_scenario(*find_scenario("car.iterated"), *find_engine("analytic")));
  const auto b = encode_run(run_scenario(*find_scenario("car.iterated"), *find_engine("analytic")));
  EXPECT_EQ(a["metrics"], b["metrics"]);
  EXPECT_EQ(a["details"], b["details"]);
}

// The reference passes every scenario at every parameter value its ranges allow: each numeric
// parameter at the ends of its range (durations capped for time), one at a time. A value the
// scenario rejects as non-physical or ill-posed is an InputError; anything else must pass.
// (car.coulomb and car.beyond-grip are Coulomb's law, which the no-slip lift does not obey: they
// need contact dynamics and are skipped, as car.slip is.)
TEST(Runner, AnalyticPassesAcrossParameterRanges) {
  const EngineInfo& analytic = *find_engine("analytic");
  int runs = 0;
  for (const Scenario& s : scenarios()) {
    if (s.needs_contact_dynamics) continue;
    for (const ParamSpec& p : s.params) {
      if (p.kind != ParamKind::kNumber && p.kind != ParamKind::kInteger) continue;
      const double def = std::stod(p.default_text);
      std::vector<double> values;
      values.push_back(std::isfinite(p.min)
                           ? (p.min_exclusive ? p.min + (p.min == 0.0 ? 1e-3 : std::abs(p.min) * 1e-3) : p.min)
                           : def - 3.0);
      values.push_back(std::isfinite(p.max) ? (p.key == "drive" || p.key == "T" ? std::min(p.max, 15.0) : p.max)
                                            : def + 3.0);
      for (double v : values) {
        if (p.kind == ParamKind::kInteger) v = std::round(v);
        const std::string text = fmt::format("{}", v);
        try {
          const RunRecord r = run_scenario(s, analytic, {{p.key, text}});
          ++runs;
          EXPECT_EQ(r.status, Status::kPass) << s.name << " " << p.key << "=" << text << ": " << r.message;
          // The per-sample metrics are measured on the reference too (shown: it reports the
          // commanded shape and its exact lift, so they compare the lift with itself), and it
          // passes them at the reference's tolerance: a shown metric is still within it. All but
          // com_accel_excess, Coulomb's bound on the centre of mass, which the no-slip lift does
          // not obey (at mu = 0.001 or accel = 100 m/s^2 the lift needs far more than mu g; the
          // same reason car.coulomb and car.beyond-grip skip the analytic engine).
          std::vector<std::string> per_sample;
          if (s.name == "car.circle")
            per_sample = {"realized_lift_error", "com_accel_excess", "trace_path_error", "trace_shape_error"};
          if (s.name == "car.cycle") per_sample = {"realized_lift_error", "trace_path_error", "trace_shape_error"};
          for (const std::string& name : per_sample) {
            const auto m =
                std::find_if(r.metrics.begin(), r.metrics.end(), [&](const Metric& x) { return x.name == name; });
            ASSERT_NE(m, r.metrics.end()) << s.name << " " << p.key << "=" << text << ": no " << name;
            EXPECT_TRUE(m->informational) << name;
          }
          for (const Metric& m : r.metrics) {
            if (m.name == "com_accel_excess") continue;
            EXPECT_TRUE(m.pass) << s.name << " " << p.key << "=" << text << ": " << m.name << " error "
                                << m.compared_error() << " tolerance " << m.tolerance;
          }
        } catch (const InputError&) {}
      }
    }
  }
  EXPECT_GT(runs, 150);
}

// Sweeps are a gate: an unlisted failing point, a listed known failure that passes, an error
// point and a slope outside its band each fail it; listed failures that fail pass it.
TEST(Sweeps, GateNamesEveryProblem) {
  SweepDef sw;
  sw.name = "error_vs_speed";
  sw.param = "speed";
  ASSERT_FALSE(known_sweep_failures().empty());
  double ceiling = 0.0;
  for (const auto& k : known_sweep_failures())
    if (k.sweep == "error_vs_speed" && k.engine == "ode" && k.x == 3.5) ceiling = k.metrics.at("front_radius");
  ASSERT_GT(ceiling, 0.01);  // 3.5 m/s on ode is a listed failure: past the grip limit the circle opens
  SweepEngine entry;
  entry.engine = "ode";
  SweepPoint slow, fast;
  slow.x = 1.0, slow.status = Status::kPass;
  fast.x = 3.5, fast.status = Status::kFail, fast.message = "out of tolerance: front_radius";
  fast.failed = {"front_radius"};
  fast.errors = {{"front_radius", 0.5 * ceiling}};
  entry.points = {slow, fast};
  const auto problems = [&] { return fmt::format("{}", fmt::join(entry.gate.problems, "; ")); };
  SweepPoint& listed = entry.points[1];
  EXPECT_TRUE(gate_sweep_entry(sw, entry)) << problems();
  EXPECT_EQ(entry.gate.points_known_failure, 1);
  listed.errors["front_radius"] = 10.0 * ceiling;
  EXPECT_FALSE(gate_sweep_entry(sw, entry));  // listed, but ten times worse than its ceiling: a regression
  listed.errors["front_radius"] = 0.5 * ceiling;
  listed.failed = {"front_radius", "base_closure"};
  EXPECT_FALSE(gate_sweep_entry(sw, entry));  // listed, but now failing a metric the list does not name
  listed.failed = {"front_radius"};
  listed.status = Status::kPass;
  EXPECT_FALSE(gate_sweep_entry(sw, entry));  // listed, but passes: the file is no longer true
  listed.status = Status::kError;
  EXPECT_FALSE(gate_sweep_entry(sw, entry));
  // Past the grip limit the car must slide: a listed point failing only in its heading (a car that
  // kept its grip) is not the listed failure.
  listed.status = Status::kFail;
  listed.failed = {"heading_residual"};
  listed.errors = {{"heading_residual", 1.0}};
  SweepDef speed_sweep = sw;
  speed_sweep.marker = 3.155, speed_sweep.slide_past_marker = true;
  EXPECT_TRUE(gate_sweep_entry(sw, entry));  // without the rule, any listed failure would do
  EXPECT_FALSE(gate_sweep_entry(speed_sweep, entry));
  EXPECT_NE(problems().find("kept its grip"), std::string::npos) << problems();
  listed.failed = {"front_radius"};
  listed.errors = {{"front_radius", 0.5 * ceiling}};
  EXPECT_TRUE(gate_sweep_entry(speed_sweep, entry)) << problems();
  entry.points[0].status = Status::kFail;
  EXPECT_FALSE(gate_sweep_entry(sw, entry));  // 1 m/s is not listed
  EXPECT_EQ(entry.gate.points_unexpected, 1);

  SweepDef fit;
  fit.name = "slope";
  fit.param = "eps";
  fit.loglog_fit = true;
  fit.slope_expected = 2.0;
  fit.slope_band = 0.05;
  const auto fitted = [](double slope) {
    SweepEngine e;
    e.engine = "x";
    e.fit = SweepFit{.slope = slope};
    return e;
  };
  SweepEngine good = fitted(1.98), bad = fitted(1.9), none = fitted(NAN);
  EXPECT_TRUE(gate_sweep_entry(fit, good));
  EXPECT_FALSE(gate_sweep_entry(fit, bad));
  EXPECT_FALSE(gate_sweep_entry(fit, none));
  SweepEngine unfitted;  // no fit at all: no slope either
  unfitted.engine = "x";
  EXPECT_FALSE(gate_sweep_entry(fit, unfitted));
}

// A known failure is no blanket: a run must fail only in its listed metrics, each no worse than its
// ceiling, and a listed run that passes is unexpected.
TEST(Expectations, AKnownFailureThatWorsensIsAFailure) {
  const KnownFailure* k = find_known_failure("car.circle", "bullet-raycast");
  ASSERT_NE(k, nullptr);
  ASSERT_TRUE(k->metrics.count("front_radius"));
  const double ceiling = k->metrics.at("front_radius");
  RunRecord r;
  r.scenario = "car.circle";
  r.engine = "bullet-raycast";
  r.expectation = expectation_of(*k);
  r.status = Status::kFail;
  // Every listed metric failing at half its ceiling: the failure as known.
  for (const auto& [name, c] : k->metrics) {
    Metric m{name, "", 0.0, 0.0, 0.5 * c, 0.5 * c, 0.0, TolKind::kAbsolute, false};
    if (name == "front_radius") m.kind = TolKind::kRelative;
    r.metrics.push_back(m);
  }
  const auto front = [&] {
    return std::find_if(r.metrics.begin(), r.metrics.end(), [](const Metric& m) { return m.name == "front_radius"; });
  };
  r.judge();
  EXPECT_TRUE(r.as_expected());
  EXPECT_EQ(r.verdict(), Verdict::kKnownFailure);
  EXPECT_STREQ(to_string(r.verdict()), "known failure");
  front()->rel_error = 2.0 * ceiling;  // twice worse than its ceiling
  r.judge();
  EXPECT_FALSE(r.as_expected());
  EXPECT_EQ(r.verdict(), Verdict::kFail);
  ASSERT_EQ(r.decision.beyond.size(), 1u);
  EXPECT_NE(r.decision.beyond[0].find("above its known ceiling"), std::string::npos) << r.decision.beyond[0];
  front()->rel_error = 0.5 * ceiling;
  r.metrics.push_back(
      {"slip_along_max", "m/s", 0.0, 1.0, 1.0, INFINITY, 1e-4, TolKind::kAbsolute, false});  // not listed
  r.judge();
  EXPECT_FALSE(r.as_expected());
  r.metrics.pop_back();
  const Metric dropped = *front();  // a listed metric no longer measured hides its failure
  r.metrics.erase(front());
  r.judge();
  EXPECT_FALSE(r.as_expected());
  ASSERT_EQ(r.decision.beyond.size(), 1u);
  EXPECT_NE(r.decision.beyond[0].find("not measured"), std::string::npos) << r.decision.beyond[0];
  r.metrics.push_back(dropped);
  r.judge();
  EXPECT_TRUE(r.as_expected());
  r.status = Status::kPass;
  for (auto& m : r.metrics) m.pass = true;
  r.judge();
  EXPECT_EQ(r.verdict(), Verdict::kUnexpectedPass);
  EXPECT_FALSE(r.as_expected());
}

// The reviewed file names only what exists: every entry's scenario or sweep, configuration,
// metrics and points, with ceilings, and no scenario x configuration listed twice.
TEST(Expectations, EveryEntryNamesWhatExists) {
  std::set<std::pair<std::string, std::string>> seen;
  ASSERT_FALSE(known_run_failures().empty());
  for (const KnownFailure& k : known_run_failures()) {
    const Scenario* s = find_scenario(k.scenario);
    ASSERT_NE(s, nullptr) << k.scenario;
    const EngineInfo* e = find_engine(k.engine);
    ASSERT_NE(e, nullptr) << k.engine;
    // The configuration runs the scenario (an entry for a skipped run could never be checked).
    EXPECT_TRUE(s->vehicle == Vehicle::kCar ? bool(e->make_car) : bool(e->make_disks))
        << k.engine << " does not run " << k.scenario;
    EXPECT_TRUE(!s->needs_contact_dynamics || e->contact_dynamics) << k.engine << " does not run " << k.scenario;
    // "params": each names a parameter of the scenario with a valid value, and the run they make is
    // one the configuration can run (a four-wheel car only where one is built).
    std::string with;
    for (const auto& [key, value] : k.params) with += fmt::format(" {}={}", key, value);
    nlohmann::json resolved;
    EXPECT_NO_THROW(resolved = Params::resolve(s->params, k.params, s->name).to_json())
        << k.scenario << " on " << k.engine << with;
    if (s->vehicle == Vehicle::kCar && resolved.is_object()) {
      EXPECT_TRUE(resolved.value("wheels", "3") != "4" || e->four_wheels) << k.engine << " has no four-wheel car";
    }
    EXPECT_TRUE(seen.insert({k.scenario, k.engine + with}).second)
        << k.scenario << " on " << k.engine << with << " listed twice";
    for (const auto& [metric, ceiling] : k.metrics) {
      EXPECT_NE(s->metric(metric), nullptr) << k.scenario << " has no metric " << metric;
      EXPECT_GT(ceiling, 0.0);
    }
  }
  std::set<std::string> sweep_keys;
  for (const KnownSweepFailure& k : known_sweep_failures()) {
    const EngineInfo* e = find_engine(k.engine);
    ASSERT_NE(e, nullptr) << k.engine;
    EXPECT_TRUE(sweep_keys.insert(fmt::format("{}|{}|{}|{}", k.sweep, k.engine, static_cast<int>(k.kind), k.x)).second)
        << k.sweep << " on " << k.engine << " at " << k.x << " listed twice";
    if (k.kind == KnownSweepFailure::kError || k.kind == KnownSweepFailure::kFit) {
      EXPECT_FALSE(k.pattern.empty()) << k.sweep;
    }
    const SweepDef* sw = nullptr;
    for (const SweepDef& d : sweep_catalogue())
      if (d.name == k.sweep) sw = &d;
    const Scenario* s = find_scenario(sw ? sw->scenario : outcome_sweep_scenario());
    if (!sw) {
      EXPECT_EQ(k.sweep, "disk_outcomes");
    }  // the outcome sweep
    EXPECT_TRUE(s->vehicle == Vehicle::kCar ? bool(e->make_car) : bool(e->make_disks))
        << k.engine << " does not run sweep " << k.sweep;
    for (const auto& [metric, ceiling] : k.metrics)
      EXPECT_NE(s->metric(metric), nullptr) << k.sweep << " has no metric " << metric;
    if (sw && (k.kind == KnownSweepFailure::kPoint || k.kind == KnownSweepFailure::kError)) {
      EXPECT_NE(std::find(sw->values.begin(), sw->values.end(), k.x), sw->values.end())
          << k.sweep << " has no point " << k.x;
    }
    if (k.kind == KnownSweepFailure::kFit) {
      EXPECT_TRUE(sw && sw->loglog_fit) << k.sweep << " fits no slope";
    }
    if (k.kind == KnownSweepFailure::kAnywhere) {
      EXPECT_GT(k.points_max, 0);
    }
  }
}

// An experiment holds when both figures reproduce (within a factor 2, or within tolerance where
// the recorded one was) and the change moves the figure the recorded way by at least 2 times.
TEST(Evidence, HoldsOnlyWhenReproducedAndMoved) {
  Evidence down;
  down.from = 2.5e-3, down.to = 3.6e-4;
  const double tol = 1e-4;
  EXPECT_TRUE(down.holds(2.5e-3, 3.6e-4, tol, tol));
  EXPECT_TRUE(down.holds(4.9e-3, 2.0e-4, tol, tol));     // both within a factor 2
  EXPECT_FALSE(down.holds(5.1e-3, 3.6e-4, tol, tol));    // the failure is no longer the one listed
  EXPECT_FALSE(down.holds(2.5e-3, 7.3e-4, tol, tol));    // the change no longer moves it as recorded
  EXPECT_FALSE(down.holds(2.5e-3, 1.5e-3, 1e-3, 1e-3));  // recorded within its tolerance, now outside it
  EXPECT_FALSE(down.holds(NAN, 3.6e-4, tol, tol));       // an error run shows nothing
  EXPECT_FALSE(down.holds(2.5e-3, 3.6e-4, 3e-3, 3e-3));  // the listed run passes now: nothing to explain
  EXPECT_TRUE(down.holds(2.5e-3, 3.6e-4, tol, 5e-4));    // the changed run's own tolerance judges the figure it changed
  Evidence to_pass;  // a change that makes it pass: within the tolerance again is enough
  to_pass.from = 4.85e-3, to_pass.to = 2e-9;
  EXPECT_TRUE(to_pass.holds(4.85e-3, 5e-7, 1e-6, 1e-6));
  EXPECT_FALSE(to_pass.holds(4.85e-3, 2e-6, 1e-6, 1e-6));
  EXPECT_FALSE(
      to_pass.holds(4.85e-3, 5e-7, 1e-6, 1e-7));  // within the listed run's tolerance, not within the changed run's
  Evidence up;                                    // a change that strengthens the cause raises the figure
  up.from = 1e-3, up.to = 2e-2;
  EXPECT_TRUE(up.holds(1e-3, 2.1e-2, 1e-4, 1e-4));
  EXPECT_FALSE(up.holds(1e-3, 1.5e-3, 1e-4, 1e-4));
  EXPECT_FALSE(up.holds(1e-2, 2e-2, 1e-4, 1e-4));  // from not reproduced (10x)
  Evidence finishes;                               // an error listing: the change lets the run finish
  finishes.from_error = true, finishes.to = 3e-3;
  EXPECT_TRUE(finishes.holds_from_error(true, 2.5e-3, 1e-4));
  EXPECT_FALSE(finishes.holds_from_error(false, 2.5e-3, 1e-4));  // the listed run no longer ends in an error
  EXPECT_FALSE(finishes.holds_from_error(true, NAN, 1e-4));      // nor does the changed one finish
}

// Every reason that names a cause carries an experiment (a negative control's cause is the
// scenario's physics), each on a metric the scenario has, its change one the configuration takes
// (a parameter or a declared setting) and one that changes the run.
TEST(Expectations, EveryNamedCauseHasAnExperiment) {
  ASSERT_FALSE(listed_reasons().empty());
  for (const ListedReason& l : listed_reasons()) {
    const std::string where = fmt::format("{}{} on {}", l.sweep ? "sweep " : "", l.scenario, l.engine);
    if (!l.negative_control) {
      EXPECT_TRUE(!l.evidence.empty() || !l.cause_not_shown.empty())
          << where << ": its reason names no experiment (nor the ones tried): " << l.reason;
    }
    if (!l.evidence.empty()) {
      EXPECT_TRUE(l.cause_not_shown.empty()) << where << ": has evidence and says no experiment moved its figure";
    }
    // A reason without evidence states the failure, not a cause: it says so first.
    const bool says_not_shown = l.reason.rfind(kCauseNotShown, 0) == 0;
    EXPECT_EQ(says_not_shown, !l.cause_not_shown.empty())
        << where << ": a reason begins with '" << kCauseNotShown
        << "' exactly when no experiment shows its cause: " << l.reason;
    const SweepDef* sw = nullptr;
    for (const SweepDef& d : sweep_catalogue())
      if (d.name == l.scenario) sw = &d;
    const Scenario* s = find_scenario(l.sweep ? (sw ? sw->scenario : outcome_sweep_scenario()) : l.scenario);
    ASSERT_NE(s, nullptr) << where;
    // The metrics the listing says fail: an experiment moves one of them (an error listing, any).
    std::set<std::string> failing;
    for (const KnownFailure& k : known_run_failures())
      if (!l.sweep && k.scenario == l.scenario && k.engine == l.engine && k.params == l.params)
        for (const auto& [m, c] : k.metrics) failing.insert(m);
    for (const KnownSweepFailure& k : known_sweep_failures())
      if (l.sweep && k.sweep == l.scenario && k.engine == l.engine)
        for (const auto& [m, c] : k.metrics) failing.insert(m);
    for (const Evidence& ev : l.evidence) {
      EXPECT_NE(s->metric(ev.metric), nullptr) << where << ": no metric " << ev.metric;
      EXPECT_TRUE(failing.empty() || failing.count(ev.metric))
          << where << ": " << ev.metric << " is not among the metrics it lists as failing";
      for (const auto& [key, value] : ev.change)
        EXPECT_TRUE(std::none_of(l.params.begin(), l.params.end(), [&](const auto& kv) { return kv.first == key; }))
            << where << ": changes its own '" << key << "'";
      if (l.sweep && sw) {
        EXPECT_NE(std::find(sw->values.begin(), sw->values.end(), ev.x), sw->values.end())
            << where << ": no point " << ev.x;
      }
      const EngineInfo* e = nullptr;
      for (const EngineInfo& c : engines())
        if (c.name == l.engine && !c.is_outside()) e = &c;
      if (!e || (l.sweep && !sw)) continue;  // outside configurations: explain checks them when it runs them
      Overrides base = l.sweep ? point_overrides(*sw, ev.x) : l.params, changed = base;
      changed.insert(changed.end(), ev.change.begin(), ev.change.end());
      try {
        const ResolvedRun a = resolve_run(*s, *e, base), b = resolve_run(*s, *e, changed);
        EXPECT_FALSE(a.params.to_json() == b.params.to_json() && a.settings == b.settings)
            << where << ": " << ev.change_text() << " changes nothing";
      } catch (const std::exception& x) {
        ADD_FAILURE() << where << ": " << ev.change_text() << ": " << x.what();
      }
    }
  }
}

// A negative control is data: every listing of a scenario that declares itself one says so, and a
// listing that says so on another scenario is a variant of its run (its params, or a sweep's
// point), never its default run. The reason's words decide nothing.
TEST(Expectations, NegativeControlsAreDeclared) {
  int controls = 0;
  for (const ListedReason& l : listed_reasons()) {
    const std::string where = fmt::format("{}{} on {}", l.sweep ? "sweep " : "", l.scenario, l.engine);
    const Scenario* s = l.sweep ? nullptr : find_scenario(l.scenario);
    if (s && s->negative_control) {
      EXPECT_TRUE(l.negative_control) << where << ": its scenario is a negative control; the listing must say so";
    }
    if (l.negative_control && !(s && s->negative_control)) {
      EXPECT_TRUE(l.sweep || !l.params.empty()) << where << ": a negative control on the scenario's default run";
    }
    controls += l.negative_control;
  }
  EXPECT_GE(controls, 20);  // car.slip on every configuration with a car, at least
}

// An informational metric (expected and measured from the same computation) is shown but never
// counted: it neither passes a run nor fails it, and a run with nothing else is no pass.
TEST(Runner, InformationalMetricsAreNotCounted) {
  Scenario s;
  s.name = "test.informational";
  s.vehicle = Vehicle::kCar;
  s.metrics = {{"self", "1", TolKind::kAbsolute, {{TolRole::kDefault, 1.0}}, "compares a value with itself"},
               {"real", "1", TolKind::kAbsolute, {{TolRole::kDefault, 1.0}}, "measures the engine"}};
  double real_error = 0.5;
  bool with_real = true;
  s.run_car = [&](const Params&, CarEngine&) {
    Outcome o;
    o.values["self"] = {0.0, 7.0, 0.0, 1.0, true};  // out of tolerance, but informational
    if (with_real) o.values["real"] = {0.0, real_error};
    return o;
  };
  const EngineInfo e = stub_engine("stub", [](const Settings&) { return std::make_unique<ThrowingCar>(); });
  RunRecord r = run_scenario(s, e);
  EXPECT_EQ(r.status, Status::kPass) << r.message;
  EXPECT_TRUE(r.metrics[0].informational);
  EXPECT_NEAR(r.worst_ratio(), 0.5, 1e-15);
  real_error = 2.0;
  r = run_scenario(s, e);
  EXPECT_EQ(r.status, Status::kFail);
  EXPECT_EQ(r.message, "out of tolerance: real");
  with_real = false;
  r = run_scenario(s, e);
  EXPECT_EQ(r.status, Status::kError);
}

// A report asked for zero (or fewer) rendering threads renders on one and finishes: every run's
// snapshots are written. (A stride of zero once looped forever: the wait below would time out.)
TEST(Report, ZeroThreadsRenderOnOne) {
  const EngineInfo& analytic = *find_engine("analytic");
  for (int threads : {0, -3}) {
    SuiteResults suite;
    suite.context = context_of({&analytic}, 0.0);
    for (const char* name : {"car.circle", "disks.copy"}) {
      suite.runs.push_back(run_scenario(*find_scenario(name), analytic));
      suite.scenarios.push_back(find_scenario(name)->info());
    }
    // Shared with the writer: if it never finishes, the test fails without leaving it a dangling reference.
    const auto shared = std::make_shared<SuiteResults>(std::move(suite));
    const SuiteResults& results = *shared;
    const auto dir =
        std::filesystem::temp_directory_path() / fmt::format("liftcheck-report-threads-{}-{}", threads, ::getpid());
    std::filesystem::remove_all(dir);
    ReportDef def;
    def.plots = false;
    def.threads = threads;
    std::promise<void> done;
    std::future<void> finished = done.get_future();
    std::thread([shared, dir, def, p = std::move(done)]() mutable {
      write_report(*shared, dir, def);
      p.set_value();
    }).detach();
    ASSERT_EQ(finished.wait_for(std::chrono::seconds(60)), std::future_status::ready) << "threads = " << threads;
    ASSERT_TRUE(results.report.has_value());
    EXPECT_EQ(results.report->errors.size(), 0u) << fmt::format("{}", fmt::join(results.report->errors, "; "));
    EXPECT_GE(results.report->snapshots.size(), 4u);
    for (const ReportFile& s : results.report->snapshots) EXPECT_TRUE(std::filesystem::exists(dir / s.file)) << s.file;
    std::filesystem::remove_all(dir);
  }
}

// Every scenario declares a headline: metrics it defines, none of them a check of the paper's
// approximation; those checks count for the reference alone.
TEST(Catalogue, EveryScenarioHasAHeadlineOfItsOwnMetrics) {
  for (const Scenario& s : scenarios()) {
    ASSERT_FALSE(s.headline.metrics.empty()) << s.name;
    EXPECT_FALSE(s.headline.label.empty()) << s.name;
    for (const auto& m : s.headline.metrics) {
      const MetricDef* def = s.metric(m);
      ASSERT_NE(def, nullptr) << s.name << ": " << m;
      EXPECT_FALSE(def->reference_only) << s.name << ": " << m;
    }
  }
}

TEST(Runner, LeadingOrderChecksCountForTheReferenceOnly) {
  const Scenario* cycle = find_scenario("car.cycle");
  ASSERT_NE(cycle, nullptr);
  Outcome o;
  // An engine that matches the exact holonomy exactly, 30% off the bracket prediction.
  o.values["dx"] = {1e-3, 1e-3};
  o.values["lo_dx"] = {0.7e-3, 1e-3, 0.0, 1.0};
  for (const auto& [role, counted] :
       {std::pair<TolRole, bool>{TolRole::kReference, true}, {TolRole::kDefault, false}}) {
    const std::string key = role == TolRole::kReference ? "reference" : "default";
    const auto metrics = score(*cycle, role, o);
    const auto lo = std::find_if(metrics.begin(), metrics.end(), [](const Metric& m) { return m.name == "lo_dx"; });
    ASSERT_NE(lo, metrics.end());
    EXPECT_EQ(lo->informational, !counted) << key;
    const auto dx = std::find_if(metrics.begin(), metrics.end(), [](const Metric& m) { return m.name == "dx"; });
    EXPECT_FALSE(dx->informational) << key;
  }
}

// The outcome grid's horizons against the exact model run over the whole 8 s by the reference engine:
// a case cut short is one whose reference never comes within the clearance (0.5 m) of contact after
// its horizon (a contact included: its response has released M and carried it clear), and a
// contact the reference holds to the end keeps the full 8 s.
TEST(Runner, OutcomeHorizonsLoseNoContactOfTheExactModel) {
  const Scenario& s = *find_scenario("disks.linear");
  int shortened = 0, contacts = 0, contacts_shortened = 0;
  double total_s = 0.0;
  for (const std::string path : {"line", "circle", "figure8"})
    for (double a : {-1.0, 0.0, 0.5, 0.9, 1.5, 2.0, 3.0})
      for (double b : {-1.0, 0.0, 0.5, 1.0}) {
        const Overrides ov{{"a", fmt::format("{}", a)},
                           {"b", fmt::format("{}", b)},
                           {"path", path},
                           {"cN", "4,0"},
                           {"vN", "-0.6,0.4"},
                           {"T", "8"},
                           {"sample_dt", "0.01"}};
        const OutcomeHorizon& h = kOutcomeHorizon;
        const double T =
            linear_outcome_horizon_s(Params::resolve(s.params, ov, s.name), h.clearance_m, h.after_s, h.t_min_s);
        total_s += T;
        const RunRecord r = run_scenario(resolve_run(s, reference_engine(), ov));
        ASSERT_EQ(r.status, Status::kPass) << path << " a=" << a << " b=" << b << ": " << r.message;
        double d_after_min = INFINITY, last_contact_s = -1.0;
        for (const auto& row : r.details.at("trace")) {
          const double d =
              std::hypot(row[1].get<double>() - row[3].get<double>(), row[2].get<double>() - row[4].get<double>());
          if (d <= 2.0 + 1e-9) last_contact_s = row[0].get<double>();
          if (row[0].get<double>() >= T) d_after_min = std::min(d_after_min, d);
        }
        contacts += last_contact_s >= 0.0 ? 1 : 0;
        if (last_contact_s >= 7.99) {
          EXPECT_EQ(T, 8.0) << path << " a=" << a << " b=" << b << ": a contact held to the end keeps the whole 8 s";
        } else if (T < 8.0) {
          ++shortened;
          contacts_shortened += last_contact_s >= 0.0 ? 1 : 0;
          EXPECT_GT(T, last_contact_s + h.after_s)
              << path << " a=" << a << " b=" << b << ": the horizon ends less than 0.5 s after the contact";
          EXPECT_GE(d_after_min, 2.0 + h.clearance_m)
              << path << " a=" << a << " b=" << b << ": the reference comes within 0.5 m of contact after " << T
              << " s";
        }
      }
  EXPECT_EQ(contacts, 20);   // the grid's collisions
  EXPECT_GT(shortened, 50);  // the contact-free cases mostly stop early, and released contacts too
  EXPECT_GT(contacts_shortened, 5);
  EXPECT_LT(total_s, 0.34 * 84 * 8.0);  // 223.7 of 672 s
}

// car.slip and car.beyond-grip judge one drive (Scenario::shared_drive): made once for both, each
// record is the one the scenario gives alone (same metrics, details, simulated time).
TEST(SharedDrive, RecordsEqualTheRunsMadeAlone) {
  const Scenario& slip = *find_scenario("car.slip");
  const Scenario& beyond = *find_scenario("car.beyond-grip");
  ASSERT_TRUE(slip.shared_drive && beyond.shared_drive);
  EXPECT_EQ(slip.shared_drive->name, beyond.shared_drive->name);
  const EngineInfo& ode = *find_engine("ode");
  const std::vector<RunRecord> shared = run_shared_drive({resolve_run(beyond, ode, {}), resolve_run(slip, ode, {})});
  ASSERT_EQ(shared.size(), 2u);
  for (const auto& [i, s] : {std::pair{0, &beyond}, std::pair{1, &slip}}) {
    const nlohmann::json alone = encode_run(run_scenario(*s, ode)), both = encode_run(shared[static_cast<size_t>(i)]);
    EXPECT_EQ(alone["metrics"], both["metrics"]) << s->name;
    EXPECT_EQ(alone["details"], both["details"]) << s->name;
    EXPECT_EQ(alone["status"], both["status"]) << s->name;
    EXPECT_DOUBLE_EQ(alone["simulated_s"].get<double>(), both["simulated_s"].get<double>()) << s->name;
  }
  EXPECT_TRUE(shared[0].as_expected()) << shared[0].message;  // ode's excess grip past the limit, listed
  EXPECT_EQ(shared[1].status, Status::kFail);  // the car slides: the no-slip comparison fails (the negative control)
}

// A suite with both makes the drive once: the later run judges the earlier one's drive, is not
// handed out or dealt to a shard, and is counted once in the simulated seconds; a drive-maker whose
// worker ended without the others' records gives them error records saying why.
TEST(SharedDrive, PlannedOnceAndItsRecordsShared) {
  SuiteDef def;
  def.engines = {find_engine("ode"), find_engine("analytic")};
  def.globs = {"car.slip", "car.beyond-grip"};
  def.sweeps = false;
  const SuitePlan plan = plan_suite(def);
  ASSERT_EQ(plan.items.size(), 4u);
  std::vector<size_t> makers, judges;
  for (size_t i = 0; i < plan.items.size(); ++i) {
    if (!plan.items[i].drive_judges.empty()) makers.push_back(i);
    if (plan.items[i].judges_drive_of >= 0) judges.push_back(i);
  }
  ASSERT_EQ(makers.size(), 2u);  // one drive per configuration
  ASSERT_EQ(judges.size(), 2u);
  for (size_t j : judges) {
    const SuiteItem& judge = plan.items[j];
    const SuiteItem& maker = plan.items[static_cast<size_t>(judge.judges_drive_of)];
    EXPECT_EQ(judge.engine, maker.engine);
    EXPECT_NE(judge.scenario, maker.scenario);
    EXPECT_FALSE(judge.runs_itself());
  }
  std::set<size_t> dealt;
  for (int k = 1; k <= 3; ++k)
    for (size_t i : shard_share(plan, k, 3)) EXPECT_TRUE(dealt.insert(i).second);
  EXPECT_EQ(dealt, std::set<size_t>(makers.begin(), makers.end()));
  // The makers' records, one with its judges' records and one from a worker that died.
  Records records;
  const RunResult died = error_record(plan.items[makers[1]], "the engine ended its process (killed by signal 9)");
  records[plan.items[makers[0]].key] = run_item(plan.items[makers[0]]);
  records[plan.items[makers[1]].key] = died;
  ASSERT_FALSE(records[plan.items[makers[0]].key].shared.empty());
  take_shared_records(plan, records);
  EXPECT_EQ(records.size(), 4u);
  for (size_t j : judges) {
    const RunResult& rec = records.at(plan.items[j].key);
    EXPECT_EQ(rec.scenario, plan.items[j].scenario->name);
    EXPECT_EQ(rec.engine, plan.items[j].engine->name);
    if (plan.items[j].judges_drive_of == static_cast<long>(makers[1])) {
      EXPECT_EQ(rec.status, Status::kError);
      EXPECT_EQ(rec.message, died.message);
    } else {
      EXPECT_NE(rec.status, Status::kError);
    }
  }
  for (size_t m : makers) EXPECT_TRUE(records.at(plan.items[m].key).shared.empty());
  const SimulatedBudget budget = simulated_budget(plan, records);
  EXPECT_NEAR(budget.configuration_total_s.at(plan.items[makers[0]].engine->name),
              records.at(plan.items[makers[0]].key).simulated_s, 1e-6);  // one drive, counted once
}

// A run is resolved once, when its item is made; the worker gets the values, unrounded, and runs
// exactly them (a setting's number is not sent as its "{:g}" text); a run that cannot be resolved
// carries its reason to the worker, which makes it the run's error record.
TEST(SuitePlan, AWorkerRunsTheRunResolvedInThePlan) {
  const EngineInfo& ode = *find_engine("ode-quick");
  const SuiteItem car =
      planned_item(SuiteItem::kRun, "k", *find_scenario("car.circle"), ode,
                   {{"w", "1.23456789"}, {"contact_cfm", "1.234567890123e-6"}, {"R", "0.3123456789"}});
  ASSERT_TRUE(car.run) << car.resolve_error;
  const SuiteItem back = item_from_request(nlohmann::json::parse(item_request(car).dump()));
  ASSERT_TRUE(back.run);
  EXPECT_EQ(back.run->settings, car.run->settings);
  EXPECT_DOUBLE_EQ(back.run->settings.number("w"), 1.23456789);  // "{:g}" would give 1.23457
  EXPECT_DOUBLE_EQ(back.run->settings.number("contact_cfm"), 1.234567890123e-6);
  EXPECT_DOUBLE_EQ(back.run->params.num("R"), 0.3123456789);
  EXPECT_EQ(back.run->params.to_json(), car.run->params.to_json());
  const SuiteItem disks =
      planned_item(SuiteItem::kRun, "d", *find_scenario("disks.target"), ode, {{"target", "4.25,-0.375"}});
  ASSERT_TRUE(disks.run) << disks.resolve_error;
  const SuiteItem disks_back = item_from_request(nlohmann::json::parse(item_request(disks).dump()));
  EXPECT_DOUBLE_EQ(disks_back.run->params.vec("target").x(), 4.25);
  EXPECT_DOUBLE_EQ(disks_back.run->params.vec("target").y(), -0.375);

  const SuiteItem bad = planned_item(SuiteItem::kRun, "b", *find_scenario("car.circle"), ode, {{"w", "7"}});
  ASSERT_FALSE(bad.run);
  EXPECT_NE(bad.resolve_error.find("'w'"), std::string::npos) << bad.resolve_error;
  const RunResult rec = run_item(item_from_request(nlohmann::json::parse(item_request(bad).dump())));
  EXPECT_EQ(rec.status, Status::kError);
  EXPECT_EQ(rec.message, bad.resolve_error);
  EXPECT_TRUE(rec.input_error);
}
