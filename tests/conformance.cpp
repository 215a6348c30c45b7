// One conformance suite for every engine: each scenario the engine can run, with default
// parameters, must pass its tolerances (data per engine in the catalogue). CTest runs this binary
// once per engine as conformance_<engine>.
#include <gtest/gtest.h>

#include <cstring>
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
  const RunRecord r = run_scenario(*s, *e);
  for (const auto& m : r.metrics)
    std::cout << "  " << m.name << ": expected " << m.expected << " measured " << m.measured << " err "
              << (m.kind == TolKind::kRelative ? m.rel_error : m.abs_error) << " tol " << m.tolerance << "\n";
  EXPECT_EQ(r.status, Status::kPass) << r.message;
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
