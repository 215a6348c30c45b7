// The horizontal lift of a driver's path: the parallel-transport equations (4.1),
//   phi' = alpha' (R/l) sin(beta),  x' = alpha' R cos(beta + phi),  y' = alpha' R sin(beta + phi),
// integrated with Boost.Odeint's error-controlled Dormand-Prince 5(4) stepper (or Bulirsch-Stoer).
#pragma once

#include <vector>

#include "models/car.hpp"
#include "models/path.hpp"

namespace liftcheck::car {

/// The analytic engine integrates with dopri5; references that compare against it use
/// Bulirsch-Stoer, so the two are independent computations.
enum class LiftMethod { kDopri5, kBulirschStoer };

struct LiftDef {
  LiftMethod method = LiftMethod::kDopri5;
  double abs_tol = 1e-13;    ///< odeint absolute error tolerance per step [m, rad]
  double rel_tol = 1e-13;    ///< odeint relative error tolerance per step
  double sample_dt_s = 0.0;  ///< spacing of the returned trace (0: only the segment corners)
};

struct TimedConfig {
  double t_s;
  Config q;
};

/// Lifts `path` from the rod position of `q0` (its alpha, beta are taken from the path's start).
/// Returns the trace: start, every sample_dt_s, and each segment end.
std::vector<TimedConfig> lift(const CarDef& car, const BasePath& path, const Config& q0, const LiftDef& def = {});

/// Lift of a sampled base path (alpha_i, beta_i), e.g. the one an engine realized, from the rod
/// position of samples.front(): between samples, steer half-way, drive the exact arc, steer the
/// rest (a symmetric composition of exact flows, second order in the sample spacing; exact when
/// only one of alpha and beta changes between two samples). Returns the end configuration.
Config lift_of_samples(const CarDef& car, const std::vector<TimedConfig>& samples);

/// Only the end configuration of the lift.
Config lift_end(const CarDef& car, const BasePath& path, const Config& q0, const LiftDef& def = {});

}  // namespace liftcheck::car
