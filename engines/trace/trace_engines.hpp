// Engines that run no physics: a recorder that captures the path a scenario commands (liftcheck
// path), and a replayer that hands the scenario a simulator's trace read back (liftcheck score,
// validate --trace-dir). The scenario function runs unchanged on both, as on any engine.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engines/engine.hpp"
#include "input/trace.hpp"

namespace liftcheck {

/// The path a scenario commands, as `liftcheck path` writes it: its rows (t and the commanded
/// coordinates) and where it starts.
struct RecordedPath {
  std::vector<std::vector<double>> rows;
  nlohmann::json start;  ///< {alpha, beta, x, y, phi} of the car; {cMx, cMy, T} of the disks
};

/// Captures the path a car scenario commands; drives it with the exact lift so that the scenario
/// function completes (its outcome is discarded).
class RecordingCar final : public CarEngine {
 public:
  explicit RecordingCar(std::string scenario) : scenario_(std::move(scenario)) {}
  void reset(const CarSetup& setup, const car::Config& q0) override {
    setup_ = setup;
    q0_ = q0;
  }
  std::vector<car::TimedConfig> drive(const car::BasePath& path) override;
  double simulated_s() const override { return 0.0; }
  bool exact_by_construction() const override { return true; }  // it drives the exact lift
  std::vector<WheelSlip> slip() const override { return {}; }

  RecordedPath recorded;

 private:
  std::string scenario_;
  CarSetup setup_;
  car::Config q0_;
  int drives_ = 0;
};

/// Captures N's path and M's start of a disk scenario; runs the exact lift so the scenario completes.
class RecordingDisks final : public DiskEngine {
 public:
  explicit RecordingDisks(std::string scenario) : scenario_(std::move(scenario)) {}
  DiskRun run(const DiskSetup& setup, const DiskProblem& pb) override;
  double simulated_s() const override { return 0.0; }

  RecordedPath recorded;

 private:
  std::string scenario_;
  int runs_ = 0;
};

/// A configuration outside liftcheck without its vehicles (name checked: UTF-8, no control character).
EngineInfo outside_engine(const std::string& name, const std::string& description);
/// A configuration that replays `trace` for the scenario `scenario` (of `vehicle`) and no other.
EngineInfo replay_engine(const std::string& name, const std::string& scenario, Vehicle vehicle, const Trace& trace);

}  // namespace liftcheck
