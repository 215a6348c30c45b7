#include <gtest/gtest.h>

#include "harness/params.hpp"
#include "harness/runner.hpp"
#include "harness/scenario.hpp"

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
  EXPECT_EQ(error_of({{"R", "abc"}}), "parameter 'R' needs a finite number, got 'abc'");
  EXPECT_EQ(error_of({{"R", "0.3m"}}), "parameter 'R' needs a finite number, got '0.3m'");
  EXPECT_EQ(error_of({{"R", "nan"}}), "parameter 'R' needs a finite number, got 'nan'");
  EXPECT_EQ(error_of({{"R", ""}}), "parameter 'R' needs a finite number, got ''");
  EXPECT_EQ(error_of({{"l", "0"}}), "parameter 'l' must be > 0 (got 0)");
  EXPECT_EQ(error_of({{"R", "-1"}}), "parameter 'R' must be > 0 (got -1)");
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
  EXPECT_EQ(setting_error(bullet, {{"wheel", "square"}}), "parameter 'wheel' must be one of sphere|cylinder, got 'square'");
  const std::string no_iterations = setting_error(*find_engine("ode"), {{"iterations", "5"}});
  EXPECT_EQ(no_iterations.rfind("engine 'ode' has no setting 'iterations' for cars (its settings there: wheel, friction_dirs; 'iterations' is a setting of ", 0), 0u)
      << no_iterations;
  EXPECT_NE(no_iterations.find("ode-quick"), std::string::npos) << no_iterations;
  EXPECT_NE(no_iterations.find("bullet"), std::string::npos) << no_iterations;
  // The quick-step solver's SOR factor: a real in (0, 2], only where it exists.
  const EngineInfo& quick = *find_engine("ode-quick");
  EXPECT_EQ(split_settings(circle, quick, {{"w", "1.0"}}).second.at("w"), "1");
  EXPECT_EQ(split_settings(circle, quick, {}).second.at("w"), "1.3");
  EXPECT_EQ(split_settings(circle, quick, {}).second.at("iterations"), "50");
  EXPECT_EQ(setting_error(quick, {{"w", "0"}}), "parameter 'w' must be > 0 (got 0)");
  EXPECT_NE(setting_error(quick, {{"w", "2.5"}}), "");
  EXPECT_NE(setting_error(quick, {{"w", "fast"}}), "");
  EXPECT_EQ(setting_error(*find_engine("ode"), {{"w", "1.0"}}).rfind("engine 'ode' has no setting 'w' for cars", 0), 0u);
}

TEST(Params, SplitAssignment) {
  EXPECT_EQ(split_assignment("R=0.3"), (std::pair<std::string, std::string>{"R", "0.3"}));
  EXPECT_THROW(split_assignment("R0.3"), InputError);
  EXPECT_THROW(split_assignment("=1"), InputError);
}

TEST(Params, EveryScenarioDefaultParses) {
  for (const auto& s : scenarios()) EXPECT_NO_THROW(Params::resolve(s.params, {}, s.name)) << s.name;
}
