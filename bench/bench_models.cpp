// The analytic models' costs (targets: the exact holonomy of a ten-segment loop under 1 us, the
// adaptive lift of a 10 s path under 1 ms). Each result is checked against an independent
// computation before timing; a wrong result is reported as an error, not as a time.
#include <benchmark/benchmark.h>

#include <cmath>
#include <fmt/format.h>
#include <numbers>

#include "models/disks.hpp"
#include "models/holonomy.hpp"
#include "models/lift.hpp"

using namespace liftcheck;

namespace {

const car::CarDef kCar{0.3, 1.0};
const car::Config kStart{0.0, 0.2, 0.0, 0.0, 0.0};
const car::DriveDef kDrive{0.3, 0.5, 0.5, 1.0, 4.0};

/// The exact holonomy of the iterated cycle (5.8) (ten segments, eps = 0.3 as car.iterated): the
/// composition of the steps' exact flows (appendix D arcs, steering). Checked against the lift
/// (4.1) of the same loop integrated by Bulirsch-Stoer at 1e-13 (relative 1e-8 of the 7.2e-4 m shift:
/// a few 1e-12 m, the integration's own error), and against the
/// leading order (5.9), eps^4 R^2 / l sideways (relative 3 eps: the next order).
void BM_HolonomyTenSegmentLoop(benchmark::State& state) {
  const double eps = 0.3;
  const std::vector<car::Step> steps = car::iterated_cycle_alpha(eps);
  if (steps.size() != 10) return state.SkipWithError("the iterated cycle (5.8) should have ten steps");
  const car::BasePath path(car::to_segments(steps), kStart.alpha_rad, kStart.beta_rad, kDrive);
  car::LiftDef bs;
  bs.method = car::LiftMethod::kBulirschStoer;
  const car::Vec5 integrated = car::lift_end(kCar, path, kStart, bs).vec() - kStart.vec();
  const car::Vec5 leading = car::predicted_iterated_alpha(kCar, kStart, eps);
  car::Vec5 h = car::Vec5::Zero();
  for (auto _ : state) {
    const car::Config end = car::apply_exact(kCar, kStart, steps);
    benchmark::DoNotOptimize(end);
    h = end.vec() - kStart.vec();
  }
  const double err_integrated = (h - integrated).norm() / integrated.norm();
  const double err_leading = (h - leading).norm() / leading.norm();
  if (!(err_integrated < 1e-8))
    return state.SkipWithError(
        fmt::format("holonomy off the integrated lift by {:.3g} (relative)", err_integrated).c_str());
  if (!(err_leading < 3 * eps))
    return state.SkipWithError(fmt::format("holonomy off (5.9) by {:.3g} (relative)", err_leading).c_str());
  state.counters["holonomy_m"] = std::hypot(h[car::kX], h[car::kY]);
  state.counters["rel_error_vs_integrated"] = err_integrated;
}
BENCHMARK(BM_HolonomyTenSegmentLoop)->Unit(benchmark::kNanosecond);

/// Eq. (4.1) integrated by the analytic engine's method (Dormand-Prince 5(4), error-controlled, dense
/// output) at abs = rel = 1e-10 over a 10 s slalom: four segments, each 2.5 s, steering and driving
/// together (beta +0.4, -0.8, +0.8, -0.4 rad while the front wheel travels 0.857 m at 0.5 m/s), so no
/// closed form applies. Checked against Bulirsch-Stoer at 1e-13: within 1e-7 (m, rad), as the per-step
/// tolerance of 1e-10 adds up over the path (measured 3e-8).
void BM_LiftTenSecondPath(benchmark::State& state) {
  // Each segment: cosine ramps of pi V / (2 A) plus cruise D / V lasts 2.5 s (models/path.hpp); the
  // steering (at most 0.8 rad at 0.5 rad/s) is done sooner, so the driving sets the pace.
  const double ramp_s = std::numbers::pi * kDrive.speed_mps / (2.0 * kDrive.accel_mps2);
  const double d_m = (2.5 - ramp_s) * kDrive.speed_mps;
  const double d_alpha = d_m / kCar.R_m;
  const car::BasePath path({{d_alpha, 0.4}, {d_alpha, -0.8}, {d_alpha, 0.8}, {d_alpha, -0.4}}, 0.0, kStart.beta_rad,
                           kDrive);
  if (!(std::abs(path.duration_s() - 10.0) < 1e-9))
    return state.SkipWithError(fmt::format("the path lasts {} s, not 10 s", path.duration_s()).c_str());
  car::LiftDef bs;
  bs.method = car::LiftMethod::kBulirschStoer;
  const car::Config reference = car::lift_end(kCar, path, kStart, bs);
  car::LiftDef def;
  def.abs_tol = def.rel_tol = 1e-10;
  car::Config end;
  for (auto _ : state) {
    end = car::lift_end(kCar, path, kStart, def);
    benchmark::DoNotOptimize(end);
  }
  const double miss = (end.vec() - reference.vec()).norm();
  if (!(miss < 1e-7))
    return state.SkipWithError(fmt::format("the lift missed Bulirsch-Stoer's by {:.3g}", miss).c_str());
  state.counters["end_x_m"] = end.x_m;
  state.counters["miss_vs_bs"] = miss;
}
BENCHMARK(BM_LiftTenSecondPath)->Unit(benchmark::kMicrosecond);

/// The disk lift (21) with first contact by root finding: repel (38) at lambda = -0.5, N on a line
/// from 5 m away, 4 s. Lemma 5.1: contact at ln(2 / 5) / lambda = 1.8326 s (checked to 1e-9 s).
void BM_DiskLiftFirstContact(benchmark::State& state) {
  disks::Mechanism m;
  m.kind = disks::MechanismKind::kRepel;
  m.lambda = -0.5;
  disks::NPath p;
  p.kind = disks::NPath::Kind::kLine;
  p.c0 = {5.0, 0.0};
  p.v = {0.3, -0.2};
  const double expected_s = std::log(0.4) / m.lambda;
  disks::LiftResult r;
  for (auto _ : state) {
    r = disks::lift(m, p, {0.0, 0.0}, 4.0);
    benchmark::DoNotOptimize(r);
  }
  if (!r.t_contact_s || !(std::abs(*r.t_contact_s - expected_s) < 1e-9))
    return state.SkipWithError(
        fmt::format("first contact at {} s, Lemma 5.1 says {:.10f} s", r.t_contact_s.value_or(NAN), expected_s)
            .c_str());
  state.counters["t_contact_s"] = *r.t_contact_s;
}
BENCHMARK(BM_DiskLiftFirstContact)->Unit(benchmark::kMicrosecond);

}  // namespace
