// One conformance suite for every engine: each scenario the engine can run, with default
// parameters, must pass its tolerances (data per engine in the catalogue). CTest runs this binary
// once per engine as conformance_<engine>.
#include <gtest/gtest.h>

#include <cstring>
#include <fmt/format.h>
#include <iostream>

#include "harness/runner.hpp"

using namespace liftcheck;

namespace {

std::string g_engine = "analytic";

class Conformance : public ::testing::TestWithParam<std::string> {};

TEST_P(Conformance, DefaultRunPasses) {
  const EngineInfo* e = find_engine(g_engine);
  ASSERT_NE(e, nullptr) << "unknown engine " << g_engine;
  const Scenario* s = find_scenario(GetParam());
  if (s->vehicle == "car" && !e->make_car) GTEST_SKIP() << g_engine << " has no car";
  if (s->vehicle == "disks" && !e->make_disks) GTEST_SKIP() << g_engine << " has no two-disk vehicles";
  if (s->needs_contact_dynamics && !e->contact_dynamics) GTEST_SKIP() << g_engine << " simulates no contact forces";
  const RunRecord r = run_scenario(*s, *e);
  for (const auto& m : r.metrics)
    std::cout << "  " << m.name << ": expected " << m.expected << " measured " << m.measured << " err "
              << (m.kind == TolKind::kRelative ? m.rel_error : m.abs_error) << " tol " << m.tolerance << "\n";
  if (s->negative_control) {
    // A negative control must fail its no-slip comparison, and through the metrics built to see
    // slip (present, and out of tolerance), not through an engine error.
    EXPECT_EQ(r.status, Status::kFail) << r.message;
    int slip_metrics = 0;
    for (const auto& m : r.metrics)
      if (m.name == "slip_across_max" || m.name == "slip_rms") {
        ++slip_metrics;
        EXPECT_FALSE(m.pass) << m.name;
      }
    EXPECT_EQ(slip_metrics, 2) << "the slip metrics were not measured";
  } else {
    EXPECT_EQ(r.status, Status::kPass) << r.message;
  }
}

// Same inputs, same numbers: a car and a disk scenario run twice give identical records.
TEST(Determinism, SameInputsSameNumbers) {
  const EngineInfo* e = find_engine(g_engine);
  ASSERT_NE(e, nullptr);
  for (const char* name : {"car.cycle", "disks.repel"}) {
    const Scenario* s = find_scenario(name);
    if ((s->vehicle == "car" && !e->make_car) || (s->vehicle == "disks" && !e->make_disks)) continue;
    const auto a = run_scenario(*s, *e).to_json(), b = run_scenario(*s, *e).to_json();
    EXPECT_EQ(a["metrics"], b["metrics"]) << name;
    EXPECT_EQ(a["details"]["trace"], b["details"]["trace"]) << name;
  }
}

// Sign conventions on every engine with a car: steering left is positive beta, forward is positive
// alpha. Driving forward with beta > 0 turns the car left (phi grows) and moves the front axle
// along its heading.
TEST(Signs, ForwardIsPositiveAlphaAndLeftIsPositiveBeta) {
  const EngineInfo* e = find_engine(g_engine);
  ASSERT_NE(e, nullptr);
  if (!e->make_car) GTEST_SKIP();
  auto car = e->make_car(e->defaults("car"));
  CarSetup setup;
  for (double beta : {0.3, -0.3}) {
    const car::Config q0{0.0, beta, 1.0, 2.0, 0.5};
    car->reset(setup, q0);
    const car::BasePath path({{2.0, 0.0}}, 0.0, beta, setup.drive);
    const auto trace = car->drive(path);
    const car::Config& end = trace.back().q;
    EXPECT_NEAR(end.alpha_rad, 2.0, 1e-3);
    EXPECT_NEAR(end.beta_rad, beta, 1e-3);
    EXPECT_GT((end.x_m - q0.x_m) * std::cos(0.5) + (end.y_m - q0.y_m) * std::sin(0.5), 0.5);  // went forward
    EXPECT_GT((end.phi_rad - q0.phi_rad) * beta, 0.0);                                          // turned to the steered side
  }
  // Steering alone: the realized beta follows the command with its sign.
  const car::Config q0{0.0, 0.0, 0.0, 0.0, 0.0};
  car->reset(setup, q0);
  const auto trace = car->drive(car::BasePath({{0.0, 0.4}}, 0.0, 0.0, setup.drive));
  EXPECT_NEAR(trace.back().q.beta_rad, 0.4, 1e-3);
}

// Honest settings: every setting the engine declares changes some result when changed (a setting
// the engine ignores must not be declared).
TEST(Settings, EveryDeclaredSettingChangesAResult) {
  const EngineInfo* e = find_engine(g_engine);
  ASSERT_NE(e, nullptr);
  const Scenario* circle = find_scenario("car.circle");
  for (const SettingSpec& k : e->knobs) {
    ASSERT_EQ(k.vehicle, "car") << k.key << ": only car settings are tested here";
    std::string other;
    if (k.kind == SettingSpec::kInteger) other = fmt::format("{}", std::max<long>(static_cast<long>(k.min), std::stol(k.default_text) / 20));
    else if (k.kind == SettingSpec::kReal) other = fmt::format("{:g}", std::stod(k.default_text) * 0.5);
    else
      for (const auto& c : k.choices)
        if (c != k.default_text && other.empty()) other = c;
    ASSERT_FALSE(other.empty()) << k.key;
    ASSERT_NE(other, k.default_text) << k.key;
    const Overrides base{{"drive", "3"}};
    Overrides changed = base;
    changed.emplace_back(k.key, other);
    const auto a = run_scenario(*circle, *e, base).to_json(), b = run_scenario(*circle, *e, changed).to_json();
    EXPECT_EQ(a["settings"][k.key], k.default_text);
    EXPECT_EQ(b["settings"][k.key], other);
    EXPECT_NE(a["details"]["trace"], b["details"]["trace"]) << k.key << " = " << other << " changed nothing";
  }
}

std::vector<std::string> scenario_names() {
  std::vector<std::string> v;
  for (const auto& s : scenarios()) v.push_back(s.name);
  return v;
}

INSTANTIATE_TEST_SUITE_P(Catalogue, Conformance, ::testing::ValuesIn(scenario_names()),
                         [](const auto& info) {
                           std::string n = info.param;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--engine") == 0) g_engine = argv[i + 1];
  return RUN_ALL_TESTS();
}
