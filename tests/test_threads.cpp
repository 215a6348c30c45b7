// Runs executing concurrently: every configuration in the registry on a car scenario and a disk
// scenario, first one after the other, then all at once in several threads, round after round.
// Each concurrent record must equal its sequential one exactly (timing fields aside): an engine
// with process-wide state that the runs share (a solver's job list, a random generator, a static
// body) crashes here or gives numbers that depend on what else was running.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <numeric>
#include <random>
#include <string>
#include <thread>
#include <vector>

#include <fmt/format.h>

#include "harness/runner.hpp"
#include "input/results_codec.hpp"

using namespace liftcheck;

namespace {

/// One run: a scenario on a configuration, shortened so a round of every configuration stays short.
struct Job {
  const Scenario* scenario;
  const EngineInfo* engine;
  Overrides overrides;
  std::string label() const { return fmt::format("{} on {}", scenario->name, engine->name); }
};

/// Fields of a run's record (encode_run) that measure the clock, not the simulation.
const char* const kTimingFields[] = {"wall_s", "engine_s"};

/// The record's JSON without its timing fields.
std::string record_json(const Job& job) {
  nlohmann::json j = encode_run(run_scenario(*job.scenario, *job.engine, job.overrides));
  for (const char* key : kTimingFields) j.erase(key);
  return j.dump();
}

/// The first few JSON-patch operations turning `expected` into `got` (the records are long).
std::string first_differences(const std::string& expected, const std::string& got) {
  const nlohmann::json patch = nlohmann::json::diff(nlohmann::json::parse(expected), nlohmann::json::parse(got));
  std::string out;
  for (std::size_t i = 0; i < std::min<std::size_t>(patch.size(), 3); ++i) out += patch[i].dump() + " ";
  return fmt::format("{}({} differences)", out, patch.size());
}

bool offers(const EngineInfo& engine, const Scenario& scenario) {
  return scenario.vehicle == Vehicle::kCar ? static_cast<bool>(engine.make_car) : static_cast<bool>(engine.make_disks);
}

/// A car scenario and a disk scenario on every configuration that has the vehicle. car.circle
/// drives 2 m instead of 10 (4 s of path after the 0.5 s settle); disks.linear runs 2.5 s, past its
/// first contact at 1.5 s.
std::vector<Job> jobs() {
  const Scenario* car = find_scenario("car.circle");
  const Scenario* disks = find_scenario("disks.linear");
  std::vector<Job> out;
  for (const EngineInfo& e : engines()) {
    if (e.is_outside()) continue;  // outside configurations run in worker processes, each with its own child
    if (offers(e, *car)) out.push_back({car, &e, {{"drive", "2"}}});
    if (offers(e, *disks)) out.push_back({disks, &e, {{"T", "2.5"}}});
  }
  return out;
}

constexpr int kThreads = 4;
constexpr int kRounds = 4;

}  // namespace

TEST(Threads, ConcurrentRunsEqualTheSequentialOnes) {
  const std::vector<Job> all = jobs();
  size_t compiled_in = 0;
  for (const EngineInfo& e : engines()) compiled_in += e.is_outside() ? 0 : 1;
  ASSERT_GE(all.size(), 2 * compiled_in - 2) << "every configuration should offer a car or disks";

  std::vector<std::string> sequential;
  for (const Job& job : all) sequential.push_back(record_json(job));
  for (std::size_t i = 0; i < all.size(); ++i) {
    const auto j = nlohmann::json::parse(sequential[i]);
    // A skipped or failed-to-start run would compare nothing.
    EXPECT_NE(j.at("status"), "skip") << all[i].label();
    EXPECT_NE(j.at("status"), "error") << all[i].label() << ": " << j.at("message");
    EXPECT_GT(j.at("simulated_s").get<double>(), 2.0) << all[i].label();
  }

  std::mt19937 shuffle(20240601u);
  for (int round = 0; round < kRounds; ++round) {
    // Round 0 keeps the registry order, so one engine's car and disks (and its sibling
    // configurations) start together; later rounds mix them.
    std::vector<std::size_t> order(all.size());
    std::iota(order.begin(), order.end(), 0);
    if (round > 0) std::shuffle(order.begin(), order.end(), shuffle);

    std::vector<std::string> concurrent(all.size());
    std::atomic<std::size_t> next{0};
    const auto worker = [&] {
      for (std::size_t k; (k = next.fetch_add(1)) < order.size();) concurrent[order[k]] = record_json(all[order[k]]);
    };
    std::vector<std::thread> pool;
    for (int t = 0; t < kThreads; ++t) pool.emplace_back(worker);
    for (std::thread& t : pool) t.join();

    for (std::size_t i = 0; i < all.size(); ++i)
      EXPECT_TRUE(concurrent[i] == sequential[i])
          << "round " << round << ": " << all[i].label()
          << " differs when run alongside the others: " << first_differences(sequential[i], concurrent[i]);
  }
}
