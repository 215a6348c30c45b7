// The search of `liftcheck tune` (harness/tune.hpp) against engines made of formulas: which runs it
// makes, the answer it picks, its budget and its determinism.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <map>

#include "engines/engine.hpp"
#include "harness/tune.hpp"
#include "input/run_result.hpp"
#include "scenarios/scenario.hpp"

namespace liftcheck {
namespace {

/// iterations (default 20, 1 to 10000) and dt (default 1 ms), as tune_dimensions makes them.
std::vector<TuneDimension> two_dimensions() {
  Scenario s;
  s.vehicle = Vehicle::kCar;
  s.params.push_back(
      {.key = "dt", .default_text = "0.001", .unit = "s", .min = 0.0, .min_exclusive = true, .max = 0.1});
  EngineInfo e;
  SettingSpec it;
  it.key = "iterations";
  it.kind = ParamKind::kInteger;
  it.default_text = "20";
  it.min = 1;
  it.max = 10000;
  it.role = SettingRole::kSolverIterations;
  e.knobs.push_back(it);
  return tune_dimensions(s, e, nullptr);
}

/// A run's record as a formula engine gives it: one absolute metric "m" whose error is `worst`
/// times its tolerance (1), so that the record's worst ratio is `worst`; a pass when it is within.
RunResult formula_record(double worst, double simulated_s, double wall_s) {
  RunResult r;
  r.scenario = "test.formula", r.engine = "formula";
  Metric m;
  m.name = "m", m.kind = TolKind::kAbsolute, m.expected = 0.0, m.measured = worst;
  m.abs_error = worst, m.tolerance = 1.0;
  m.pass = m.passes_by_figures();
  r.metrics = {m};
  r.status = m.pass ? Status::kPass : Status::kFail;
  r.simulated_s = simulated_s, r.wall_s = wall_s;
  r.judge();
  return r;
}

/// An error record (no metrics) that took `wall_s`.
RunResult error_run(const std::string& message, double wall_s) {
  RunResult r = error_result("test.formula", "formula", Vehicle::kCar, message);
  r.wall_s = wall_s;
  return r;
}

/// A formula engine: its worst error over tolerance and its cost from the change, as a record.
struct FormulaEngine {
  std::function<double(double iterations, double dt)> worst;
  /// The clock's error on a run's cost (1: none).
  std::function<double(double iterations)> noise = [](double) { return 1.0; };
  int runs = 0;
  std::vector<RunResult> operator()(const std::vector<Overrides>& changes) {
    std::vector<RunResult> out;
    for (const Overrides& c : changes) {
      std::map<std::string, double> v{{"iterations", 20.0}, {"dt", 1e-3}};
      for (const auto& [k, x] : c) v[k] = std::strtod(x.c_str(), nullptr);
      const double w = worst(v["iterations"], v["dt"]);
      // The cost: proportional to iterations per step and steps per second (8 s simulated).
      out.push_back(formula_record(w, 8.0, 8.0 * 1e-6 * v["iterations"] / v["dt"] * noise(v["iterations"])));
      ++runs;
    }
    return out;
  }
};

TEST(Tune, DimensionsAreTheStepAndTheSettingsOnLadders) {
  const auto dims = two_dimensions();
  ASSERT_EQ(dims.size(), 2u);
  EXPECT_EQ(dims[0].key, "dt");
  EXPECT_EQ(dims[0].ladder, (std::vector<std::string>{"0.002", "0.0005", "0.004", "0.00025", "0.008"}));
  EXPECT_EQ(dims[1].key, "iterations");
  // 20 x {1/4, 4, 1/16, 16}: 1.25 rounds to 1.
  EXPECT_EQ(dims[1].ladder, (std::vector<std::string>{"5", "80", "1", "320"}));
}

TEST(Tune, FindsTheCheapestIterationCountThatPasses) {
  // Passes from 60 iterations on, whatever dt: the ladder brackets it between 20 and 80, the
  // refinement tries 40, then 57 (both fail): 80 is the cheapest pass, 4 times the default's cost.
  FormulaEngine eng{[](double it, double) { return 60.0 / it; }};
  const TuneResult r = tune(two_dimensions(), TuneDef{}, std::ref(eng));
  ASSERT_TRUE(r.answer);
  const TuneStep& a = r.walked[*r.answer];
  EXPECT_EQ(change_text(a.change), "iterations=80");
  EXPECT_NEAR(a.cost_ms_per_s / r.walked[0].cost_ms_per_s, 4.0, 1e-12);
  std::vector<std::string> refined;
  for (const auto& s : r.walked)
    if (s.phase == "refine") refined.push_back(change_text(s.change));
  EXPECT_EQ(refined, (std::vector<std::string>{"iterations=40", "iterations=57"}));
  EXPECT_EQ(eng.runs, static_cast<int>(r.walked.size()));
}

TEST(Tune, FewerIterationsThatPassWinWhateverTheClockSays) {
  // Passes from 50 iterations on: 80 on the ladder, then 40 (fails) and 57 (passes). The clock
  // measures 57 at twice its cost, above 80's: along the iteration count the verdicts decide.
  FormulaEngine eng{[](double it, double) { return 50.0 / it; }, [](double it) { return it == 57.0 ? 2.0 : 1.0; }};
  const TuneResult r = tune(two_dimensions(), TuneDef{}, std::ref(eng));
  ASSERT_TRUE(r.answer);
  EXPECT_EQ(change_text(r.walked[*r.answer].change), "iterations=57");
}

TEST(Tune, ALongerStepThatStillPassesIsCheaper) {
  // Passes up to dt = 4.5 ms at 20 iterations, fewer iterations fail: the cheapest pass is the
  // longest passing step on the ladder, 4 ms, at a quarter of the default's cost (the refinement
  // between 4 and 8 ms tries 5.7 ms, which fails).
  FormulaEngine eng{[](double it, double dt) { return dt / 4.5e-3 * (20.0 / it) * (20.0 / it); }};
  const TuneResult r = tune(two_dimensions(), TuneDef{}, std::ref(eng));
  ASSERT_TRUE(r.answer);
  const TuneStep& a = r.walked[*r.answer];
  EXPECT_EQ(change_text(a.change), "dt=0.004");
  EXPECT_NEAR(a.cost_ms_per_s / r.walked[0].cost_ms_per_s, 0.25, 1e-12);
  bool refined = false;
  for (const auto& s : r.walked) refined = refined || change_text(s.change) == "dt=0.005657";
  EXPECT_TRUE(refined);
}

TEST(Tune, NothingPassesGivesTheClosestAfterCombining) {
  // Better with more iterations and a shorter step, never within tolerance.
  FormulaEngine eng{[](double it, double dt) { return 2.0 + 1.0 / it + dt * 1e3; }};
  const TuneResult r = tune(two_dimensions(), TuneDef{}, std::ref(eng));
  EXPECT_FALSE(r.answer);
  const TuneStep& c = r.walked[r.closest];
  for (const TuneStep& s : r.walked) EXPECT_GE(s.worst_ratio, c.worst_ratio);
  // The combination of the closest value of each dimension was tried and came closest.
  EXPECT_EQ(c.phase, "combine");
  EXPECT_EQ(change_text(c.change), "dt=0.00025, iterations=320");
}

/// Two choices, each passing alone at the given measured costs (ms per simulated s; the default fails).
TuneResult two_passes(double cost_a, double cost_b) {
  const std::map<std::string, double> cost{{"a=1", cost_a}, {"b=1", cost_b}};
  const TuneRunner run = [&](const std::vector<Overrides>& changes) {
    std::vector<RunResult> out;
    for (const Overrides& c : changes) {
      const bool dflt = c.empty();
      out.push_back(formula_record(dflt ? 2.0 : 0.5, 1.0, dflt ? 1e-3 : cost.at(change_text(c)) * 1e-3));
    }
    return out;
  };
  const TuneDimension a{.key = "a", .kind = ParamKind::kChoice, .default_text = "0", .ladder = {"1"}};
  const TuneDimension b{.key = "b", .kind = ParamKind::kChoice, .default_text = "0", .ladder = {"1"}};
  return tune({a, b}, TuneDef{}, run);
}

TEST(Tune, MeasuredCostsNeverDecide) {
  // Settings without a cost model cost alike: the walk's order decides, whatever the clock says.
  for (const auto& [ca, cb] : {std::pair{1.1, 1.0}, std::pair{1.0, 0.5}, std::pair{0.5, 1.0}}) {
    const TuneResult r = two_passes(ca, cb);
    ASSERT_TRUE(r.answer);
    EXPECT_EQ(change_text(r.walked[*r.answer].change), "a=1") << ca << " " << cb;
  }
}

TEST(Tune, TheSameVerdictsGiveTheSameAnswerWhateverTheClock) {
  // Two searches whose clocks disagree by up to 50% on every run make the same runs and answer.
  FormulaEngine a{[](double it, double dt) { return 30.0 / it + dt * 100.0; }};
  FormulaEngine b{a.worst, [](double it) { return 1.0 + 0.5 * std::sin(it); }};
  const TuneResult ra = tune(two_dimensions(), TuneDef{}, std::ref(a));
  const TuneResult rb = tune(two_dimensions(), TuneDef{}, std::ref(b));
  ASSERT_EQ(ra.walked.size(), rb.walked.size());
  for (size_t i = 0; i < ra.walked.size(); ++i) {
    EXPECT_EQ(change_text(ra.walked[i].change), change_text(rb.walked[i].change));
    EXPECT_EQ(ra.walked[i].pass, rb.walked[i].pass);
  }
  ASSERT_TRUE(ra.answer);
  EXPECT_EQ(ra.answer, rb.answer);
  EXPECT_NE(ra.walked[*ra.answer].cost_ms_per_s, rb.walked[*rb.answer].cost_ms_per_s);  // the clocks did differ
}

TEST(Tune, EveryRunIsJudgedAgainstTheDefaultsTolerances) {
  // A metric whose tolerance grows with dt (1e-5 at 1 ms): at 2 ms the error 1.5e-5 is within the
  // run's own 2e-5 and the run says pass, but against the default's 1e-5 it fails (1.5 times).
  const TuneRunner run = [](const std::vector<Overrides>& changes) {
    std::vector<RunResult> out;
    for (const Overrides& c : changes) {
      const double dt = c.empty() ? 1e-3 : std::strtod(c[0].second.c_str(), nullptr);
      const double err = dt > 1e-3 ? 1.5e-5 : 2e-5 * std::pow(dt / 1e-3, 3), tol = 1e-5 * dt / 1e-3;
      RunResult r = formula_record(err, 1.0, 1e-6 / dt);  // the metric "m": error err against tolerance tol
      r.metrics[0].tolerance = tol;
      r.metrics[0].pass = r.metrics[0].passes_by_figures();
      r.status = r.metrics[0].pass ? Status::kPass : Status::kFail;
      r.judge();
      EXPECT_DOUBLE_EQ(r.worst_ratio(), err / tol);
      out.push_back(r);
    }
    return out;
  };
  std::vector<TuneDimension> dims = two_dimensions();
  dims.resize(1);  // dt only
  const TuneResult r = tune(dims, TuneDef{}, run);
  const auto at_2ms = std::find_if(r.walked.begin(), r.walked.end(),
                                   [](const TuneStep& s) { return change_text(s.change) == "dt=0.002"; });
  ASSERT_NE(at_2ms, r.walked.end()) << "the ladder tries dt = 2 ms";
  EXPECT_EQ(at_2ms->record.status, Status::kPass);
  EXPECT_FALSE(at_2ms->pass);
  EXPECT_NEAR(at_2ms->worst_ratio, 1.5, 1e-12);
  // The default fails (2e-5 against 1e-5); 0.5 ms passes (2.5e-6 against its 5e-6), and the
  // refinement's 0.71 ms (7.07e-6 against its own 7.07e-6 and the default's 1e-5) is the answer.
  ASSERT_TRUE(r.answer);
  EXPECT_EQ(change_text(r.walked[*r.answer].change), "dt=0.0007071");
}

// Two iteration counts (Jolt's velocity and position steps, PhysX's position and velocity
// iterations) add to a step's work, one unit for the step itself: no count makes a run free, not
// even 0 position steps, and halving dt doubles the cost whatever the counts.
TEST(Tune, IterationCountsAddAndNoneMakesARunFree) {
  Scenario s;
  s.vehicle = Vehicle::kCar;
  s.params.push_back(
      {.key = "dt", .default_text = "0.001", .unit = "s", .min = 0.0, .min_exclusive = true, .max = 0.1});
  EngineInfo e;
  for (const auto& [key, dflt, min] :
       {std::tuple{"velocity_steps", "10", 1.0}, std::tuple{"position_steps", "2", 0.0}}) {
    SettingSpec k;
    k.key = key, k.kind = ParamKind::kInteger, k.default_text = dflt, k.min = min, k.max = 1000;
    k.role = SettingRole::kSolverIterations;
    e.knobs.push_back(k);
  }
  const TuneRunner run = [](const std::vector<Overrides>& changes) {
    return std::vector<RunResult>(changes.size(), formula_record(2.0, 1.0, 1.0));
  };
  const TuneResult r = tune(tune_dimensions(s, e, nullptr), TuneDef{.budget_runs = 40}, run);
  const auto model_of = [&](const std::string& text) {
    for (const TuneStep& st : r.walked)
      if (change_text(st.change) == text) return st.model_cost;
    return -1.0;
  };
  EXPECT_NEAR(model_of("position_steps=0"), 11.0 / 13.0, 1e-12);
  EXPECT_NEAR(model_of("dt=0.0005"), 2.0, 1e-12);
  EXPECT_NEAR(model_of("velocity_steps=1"), 4.0 / 13.0, 1e-12);  // counts add: (1 + 1 + 2) / (1 + 10 + 2)
  for (const TuneStep& st : r.walked) EXPECT_GT(st.model_cost, 0.0) << change_text(st.change);
}

TEST(Tune, ABudgetCutShort) {
  FormulaEngine eng{[](double it, double) { return 60.0 / it; }};
  const TuneResult r = tune(two_dimensions(), TuneDef{.budget_runs = 4}, std::ref(eng));
  EXPECT_EQ(r.walked.size(), 4u);
  EXPECT_EQ(eng.runs, 4);
  EXPECT_GT(r.unmade, 0);  // the rest of the ladder was planned and not made
  EXPECT_FALSE(r.answer);
}

TEST(Tune, AnErrorIsNoPassAndNoCloser) {
  // Runs above 100 iterations end in an error record: never the answer, never the closest.
  const TuneRunner run = [](const std::vector<Overrides>& changes) {
    std::vector<RunResult> out;
    for (const Overrides& c : changes) {
      const double it = c.empty() ? 20.0 : std::strtod(c[0].second.c_str(), nullptr);
      if (c.size() == 1 && c[0].first == "iterations" && it > 100.0)
        out.push_back(error_run("timed out", 30.0));
      else
        out.push_back(formula_record(3.0 - it / 100.0, 1.0, 1e-3));
    }
    return out;
  };
  std::vector<TuneDimension> dims = two_dimensions();
  dims.erase(dims.begin());  // iterations only
  const TuneResult r = tune(dims, TuneDef{}, run);
  EXPECT_FALSE(r.answer);
  EXPECT_EQ(change_text(r.walked[r.closest].change), "iterations=80");
  int errors = 0;
  for (const TuneStep& s : r.walked) {
    const bool error = s.record.status == Status::kError;
    errors += error;
    EXPECT_TRUE(!error || (std::isinf(s.worst_ratio) && std::isnan(s.cost_ms_per_s))) << change_text(s.change);
  }
  EXPECT_GT(errors, 0);
}

TEST(Tune, ADefaultRunThatErrorsStopsTheSearch) {
  // The default run times out; a longer step would pass on its own (looser, dt-scaled) tolerances,
  // but there are no default tolerances to judge it against: the walk stops at the default.
  int runs = 0;
  const TuneRunner run = [&runs](const std::vector<Overrides>& changes) {
    std::vector<RunResult> out;
    for (const Overrides& c : changes) {
      ++runs;
      if (c.empty())
        out.push_back(error_run("timed out", 30.0));
      else
        out.push_back(formula_record(0.5, 1.0, 1e-3));
    }
    return out;
  };
  const TuneResult r = tune(two_dimensions(), TuneDef{}, run);
  EXPECT_EQ(runs, 1);
  EXPECT_EQ(r.stopped, "error");
  EXPECT_FALSE(r.answer);
  EXPECT_EQ(r.walked.size(), 1U);
}

TEST(Tune, LaddersKeepToTheDeclaredRanges) {
  Scenario s;
  s.vehicle = Vehicle::kCar;
  EngineInfo e;
  const auto spec = [](std::string key, ParamKind kind, std::string dflt, double min, double max, bool excl) {
    SettingSpec k;
    k.key = std::move(key), k.kind = kind, k.default_text = std::move(dflt), k.min = min, k.max = max;
    k.min_exclusive = excl;
    return k;
  };
  e.knobs = {spec("w", ParamKind::kNumber, "1.3", 0.0, 2.0, true),
             spec("steps", ParamKind::kInteger, "2", 0.0, 8.0, false),
             spec("damping", ParamKind::kNumber, "0", 0.0, 1.0, false)};
  std::vector<std::string> left_out;
  const auto dims = tune_dimensions(s, e, &left_out);
  ASSERT_EQ(dims.size(), 2u);
  // w: 1.3 x {1/4, 4, 1/16, 16}: 0.325, 2 (clamped to the maximum), 0.08125 (the maximum once).
  EXPECT_EQ(dims[0].ladder, (std::vector<std::string>{"0.325", "2", "0.08125"}));
  // steps: 2 x {1/4, 4, 1/16, 16} rounded and clamped: 0 (0.5 rounds away from zero to 1: "1"), 8, 0.
  EXPECT_EQ(dims[1].ladder, (std::vector<std::string>{"1", "8", "0"}));
  ASSERT_EQ(left_out.size(), 1u);
  EXPECT_NE(left_out[0].find("damping"), std::string::npos);
}

TEST(Tune, SearchesARealConfigurationsDeclaredSettings) {
  const EngineInfo* e = find_engine("ode-quick");
  ASSERT_NE(e, nullptr);
  const Scenario* s = find_scenario("car.circle");
  ASSERT_NE(s, nullptr);
  std::vector<std::string> left_out;
  const auto dims = tune_dimensions(*s, *e, &left_out);
  std::vector<std::string> keys;
  for (const auto& d : dims) keys.push_back(d.key);
  EXPECT_EQ(keys.front(), "dt");
  EXPECT_NE(std::find(keys.begin(), keys.end(), "iterations"), keys.end());
  // Every declared car setting is searched or named as left out; none of the scenario's others.
  size_t car_knobs = 0;
  for (const auto& k : e->knobs) car_knobs += k.vehicle == Vehicle::kCar;
  EXPECT_EQ(dims.size() - 1 + left_out.size(), car_knobs);
}

}  // namespace
}  // namespace liftcheck
