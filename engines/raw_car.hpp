// The physical limit of stepping a car: the tricycle built by a configuration's own build code,
// then stepped by direct calls to the engine's API with fixed motor commands. No state is read
// back between steps: no servo, no slip bookkeeping, no trace. The benchmarks (bench/) time
// liftcheck's CarEngine::drive against it to measure what the adapter costs per step.
#pragma once

#include <memory>

#include <Eigen/Dense>

#include "engines/engine.hpp"

namespace liftcheck {

class RawCar {
 public:
  virtual ~RawCar() = default;
  /// `steps` engine steps of setup.dt_s with the front wheel's spin motor at spin_radps (0: the
  /// wheels held, as in the settle) and the steering held at the start beta.
  virtual void run(long steps, double spin_radps) = 0;
  /// The front wheel centre, world x and y, m (the benchmark checks where the car went).
  virtual Eigen::Vector2d front_xy_m() const = 0;
};

}  // namespace liftcheck
