#include <gtest/gtest.h>

#include "input/params.hpp"
#include "harness/runner.hpp"
#include "scenarios/scenario.hpp"

using namespace liftcheck;

namespace {
const std::vector<ParamSpec>& circle_params() { return find_scenario("car.circle")->params; }

std::string error_of(const Overrides& ov) {
  try {
    Params::resolve(circle_params(), ov, "car.circle");
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}
}  // namespace

TEST(Params, DefaultsAndOverrides) {
  const Params p = Params::resolve(circle_params(), {{"R", "0.25"}}, "car.circle");
  EXPECT_EQ(p.num("R"), 0.25);
  EXPECT_EQ(p.num("l"), 1.0);
  EXPECT_EQ(p.to_json()["R"], 0.25);
}

TEST(Params, BadInputNamesTheProblem) {
  EXPECT_EQ(error_of({{"bogus", "1"}}), "unknown parameter 'bogus' for scenario 'car.circle'");
  EXPECT_EQ(error_of({{"sped", "1"}}), "unknown parameter 'sped' for scenario 'car.circle'; did you mean 'speed'?");
  EXPECT_EQ(error_of({{"MU", "1"}}), "unknown parameter 'MU' for scenario 'car.circle'; did you mean 'mu'?");
  EXPECT_EQ(error_of({{"mu", "1e400"}}),
            "parameter 'mu' needs a finite number, got '1e400': too large or too small in magnitude for a double");
  EXPECT_EQ(error_of({{"mu", "-inf"}}), "parameter 'mu' needs a finite number, got '-inf' (not finite)");
  EXPECT_EQ(error_of({{"mu", "0"}}), "parameter 'mu' must be > 0 and <= 10, got '0'");
  EXPECT_EQ(error_of({{"beta", "1.5"}}), "parameter 'beta' must be >= -1.4 and <= 1.4 rad, got '1.5'");
  EXPECT_EQ(error_of({{"dt", " 0.002 "}}), "");
  EXPECT_EQ(error_of({{"dt", "0x10"}}), "parameter 'dt' needs a finite number, got '0x10'");
  EXPECT_EQ(error_of({{"R", "abc"}}), "parameter 'R' needs a finite number, got 'abc'");
  EXPECT_EQ(error_of({{"R", "0.3m"}}), "parameter 'R' needs a finite number, got '0.3m'");
  EXPECT_EQ(error_of({{"R", "nan"}}), "parameter 'R' needs a finite number, got 'nan' (not finite)");
  EXPECT_EQ(error_of({{"R", ""}}), "parameter 'R' needs a finite number, got ''");
  EXPECT_EQ(error_of({{"l", "0"}}), "parameter 'l' must be > 0 m, got '0'");
  EXPECT_EQ(error_of({{"R", "-1"}}), "parameter 'R' must be > 0 m, got '-1'");
  EXPECT_EQ(error_of({{"R", "1e3"}}), "");
}

// Engine settings are split from the scenario's parameters, typed and ranged by the engine.
TEST(Params, EngineSettings) {
  const Scenario& circle = *find_scenario("car.circle");
  const EngineInfo& bullet = *find_engine("bullet");
  const auto setting_error = [&](const EngineInfo& e, const Overrides& ov) -> std::string {
    try {
      split_settings(circle, e, ov);
    } catch (const InputError& err) {
      return err.what();
    }
    return "";
  };
  const auto [params, settings] = split_settings(circle, bullet, {{"R", "0.25"}, {"wheel", "cylinder"}});
  EXPECT_EQ(params, (Overrides{{"R", "0.25"}}));
  EXPECT_EQ(settings.at("wheel"), "cylinder");
  EXPECT_EQ(settings.at("iterations"), "100");
  EXPECT_EQ(settings.at("friction_dirs"), "wheel");
  EXPECT_EQ(setting_error(bullet, {{"iterations", "2.5"}}), "parameter 'iterations' needs a whole number, got '2.5'");
  EXPECT_EQ(setting_error(bullet, {{"wheel", "square"}}),
            "parameter 'wheel' must be one of sphere|cylinder, got 'square'");
  const std::string no_iterations = setting_error(*find_engine("ode"), {{"iterations", "5"}});
  EXPECT_EQ(no_iterations.rfind("engine 'ode' has no setting 'iterations' for cars (its settings there: wheel, "
                                "friction_dirs, contact_erp, contact_cfm; 'iterations' is a setting of ",
                                0),
            0u)
      << no_iterations;
  EXPECT_NE(no_iterations.find("ode-quick"), std::string::npos) << no_iterations;
  EXPECT_NE(no_iterations.find("bullet"), std::string::npos) << no_iterations;
  // The quick-step solver's SOR factor: a real in (0, 2], only where it exists.
  const EngineInfo& quick = *find_engine("ode-quick");
  EXPECT_EQ(split_settings(circle, quick, {{"w", "1.0"}}).second.at("w"), "1");
  EXPECT_EQ(split_settings(circle, quick, {}).second.at("w"), "1.3");
  EXPECT_EQ(split_settings(circle, quick, {}).second.at("iterations"), "50");
  EXPECT_EQ(setting_error(quick, {{"w", "0"}}), "parameter 'w' must be > 0 and <= 2, got '0'");
  EXPECT_NE(setting_error(quick, {{"w", "2.5"}}), "");
  EXPECT_NE(setting_error(quick, {{"w", "fast"}}), "");
  EXPECT_EQ(setting_error(*find_engine("ode"), {{"w", "1.0"}}).rfind("engine 'ode' has no setting 'w' for cars", 0),
            0u);
}

// MuJoCo's refsafe raises a solref time constant below 2 dt to 2 dt without a word: such a value
// is refused as bad input naming the floor, on the car and on the disks alike, at the floor itself
// accepted; the default 0.02 s is refused too where dt makes 2 dt larger than it.
TEST(Params, MujocoRefusesASolrefTimeConstantRefsafeWouldRaise) {
  const EngineInfo& mujoco = *find_engine("mujoco");
  const auto refusal = [&](const char* scenario, const Overrides& ov) -> std::string {
    try {
      (void)run_scenario(*find_scenario(scenario), mujoco, ov);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  const std::string car = refusal("car.circle", {{"solref_timeconst_s", "0.0019"}});
  EXPECT_NE(car.find("below 2 dt = 0.002 s"), std::string::npos) << car;
  EXPECT_NE(car.find("refsafe"), std::string::npos) << car;
  const std::string disks = refusal("disks.copy", {{"solref_timeconst_s", "0.0019"}});
  EXPECT_NE(disks.find("below 2 dt = 0.002 s"), std::string::npos) << disks;
  const std::string coarse = refusal("disks.copy", {{"dt", "0.02"}});
  EXPECT_NE(coarse.find("'solref_timeconst_s' = 0.02 s is below 2 dt = 0.04 s"), std::string::npos) << coarse;
  EXPECT_EQ(refusal("disks.copy", {{"solref_timeconst_s", "0.002"}}), "");
}

TEST(Params, SplitAssignment) {
  EXPECT_EQ(split_assignment("R=0.3"), (std::pair<std::string, std::string>{"R", "0.3"}));
  EXPECT_THROW(split_assignment("R0.3"), InputError);
  EXPECT_THROW(split_assignment("=1"), InputError);
  EXPECT_THROW(split_assignment("  =1"), InputError);
  EXPECT_EQ(split_assignment(" R =0.3=4"), (std::pair<std::string, std::string>{"R", "0.3=4"}));
}

TEST(Params, EveryScenarioDefaultParses) {
  for (const auto& s : scenarios()) EXPECT_NO_THROW(Params::resolve(s.params, {}, s.name)) << s.name;
}

// A 2-D point takes exactly two finite coordinates within its range; a choice names the nearest.
TEST(Params, PointsAndChoices) {
  const auto& specs = find_scenario("disks.copy")->params;
  const auto error = [&](const Overrides& ov) -> std::string {
    try {
      Params::resolve(specs, ov, "disks.copy");
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  };
  EXPECT_EQ(error({{"cM", "1,2,3"}}), "parameter 'cM' needs a 2-D point 'x,y' (two numbers), got '1,2,3' (3 values)");
  EXPECT_EQ(error({{"cM", "1"}}), "parameter 'cM' needs a 2-D point 'x,y' (two numbers), got '1' (1 value)");
  EXPECT_EQ(error({{"cM", ","}}), "parameter 'cM' (x) needs a finite number, got ''");
  EXPECT_EQ(error({{"cM", "1,nan"}}), "parameter 'cM' (y) needs a finite number, got 'nan' (not finite)");
  EXPECT_EQ(error({{"vN", "2000,0"}}), "parameter 'vN' needs coordinates >= -1000 and <= 1000 m/s, got '2000,0'");
  EXPECT_EQ(error({{"cM", " -1 , 2.5 "}}), "");
  EXPECT_EQ(error({{"path", "figure-8"}}),
            "parameter 'path' must be one of line|circle|figure8, got 'figure-8'; did you mean 'figure8'?");
  EXPECT_EQ(error({{"path", "spiral"}}), "parameter 'path' must be one of line|circle|figure8, got 'spiral'");
}

// Every default of every scenario is inside its own range (the defaults are parsed like input).
TEST(Params, DefaultsAreValid) {
  for (const Scenario& s : scenarios()) EXPECT_NO_THROW(Params::resolve(s.params, {}, s.name)) << s.name;
}
