// The parallel-transport equations (4.1) integrated numerically against appendix D, their
// reparametrisation invariance, and E(2) equivariance.
#include <gtest/gtest.h>

#include "models/holonomy.hpp"
#include "models/lift.hpp"

using namespace liftcheck::car;

namespace {
const CarDef kCar{0.25, 0.9};
}

TEST(Profile, ReachesTheDistanceAndItsRateIsTheDerivative) {
  for (double D : {0.01, 0.1, 3.0}) {
    const Profile p(D, 0.5, 2.0);
    EXPECT_NEAR(p.position(p.duration()), D, 1e-15);
    EXPECT_EQ(p.position(0.0), 0.0);
    double max_rate = 0.0, max_accel = 0.0;
    for (double t = 0.01; t < p.duration(); t += 0.0013) {
      const double fd = (p.position(t + 1e-6) - p.position(t - 1e-6)) / 2e-6;
      EXPECT_NEAR(fd, p.rate(t), 1e-7);
      max_rate = std::max(max_rate, p.rate(t));
      max_accel = std::max(max_accel, std::abs(p.rate(t + 1e-6) - p.rate(t - 1e-6)) / 2e-6);
    }
    EXPECT_LE(max_rate, 0.5 + 1e-12);
    EXPECT_LE(max_accel, 2.0 + 1e-6);
    EXPECT_GE(max_accel, 1.9);  // the bound is reached: no slower than it needs to be
  }
}

TEST(BasePath, CornersAndTiming) {
  const DriveDef drive{0.3, 0.6, 0.4, 0.6 * M_PI / 0.2, 4.0};
  const BasePath path({{2.0, 0.0}, {0.0, -0.3}, {1.0, 0.2}}, 0.5, 0.1, drive);
  EXPECT_NEAR(path.corner(3).alpha_rad, 3.5, 1e-15);
  EXPECT_NEAR(path.corner(3).beta_rad, 0.0, 1e-15);
  const BaseSample end = path.at(path.duration_s() + 1.0);
  EXPECT_NEAR(end.alpha_rad, 3.5, 1e-15);
  EXPECT_EQ(end.alpha_rate_radps, 0.0);
  // First segment: 0.6 m at 0.6 m/s cruise with 0.1 s ramps (peak accel 0.6 pi / 0.2) lasts 1.1 s.
  EXPECT_NEAR(path.segment_end_s(0), 1.1, 1e-12);
  EXPECT_NEAR(path.at(0.5).alpha_rate_radps * drive.R_m, 0.6, 1e-12);
}

TEST(Lift, AppendixDClosedFormMatchesIntegration) {
  const DriveDef drive{kCar.R_m, 0.7, 0.5, 1.0, 4.0};
  for (double beta : {0.0, 1e-6, 0.05, 0.3, -0.8, 1.3})
    for (double d_alpha : {4.0, -25.0}) {
      const Config q0{0.0, beta, -1.0, 2.0, 2.5};
      const BasePath path({{d_alpha, 0.0}}, 0.0, beta, drive);
      LiftDef def;
      def.sample_dt_s = 0.05;
      for (const auto& s : lift(kCar, path, q0, def)) {
        const Config exact = flow_alpha(kCar, q0, s.q.alpha_rad - q0.alpha_rad);
        ASSERT_LT((exact.vec() - s.q.vec()).norm(), 1e-10) << "beta " << beta << " t " << s.t_s;
      }
    }
}

TEST(Lift, ReparametrisationInvariance) {
  // Section 4: only the path in (alpha, beta) matters. Speeds and ramp fractions differ.
  const std::vector<Segment> segs{{2.0, 0.3}, {3.0, -0.5}, {-2.0, 0.2}};
  const Config q0{0.0, 0.1, 0.5, -0.5, 0.3};
  const Config ref = lift_end(kCar, BasePath(segs, 0.0, 0.1, {kCar.R_m, 0.5, 0.5, 1.0, 4.0}), q0);
  for (double k : {0.1, 3.0, 20.0}) {
    const Config q = lift_end(kCar, BasePath(segs, 0.0, 0.1, {kCar.R_m, 0.5 * k, 0.5 * k, 1.0, 4.0}), q0);
    EXPECT_LT((q.vec() - ref.vec()).norm(), 1e-10) << k;
  }
  // And not trivially: the end pose is far from the start.
  EXPECT_GT(std::hypot(ref.x_m - q0.x_m, ref.y_m - q0.y_m), 0.5);
}

TEST(Lift, EquivarianceOfTheLift) {
  // Lifting from R_B p gives R_B of the lift from p, for a path that steers while driving.
  const std::vector<Segment> segs{{2.0, 0.3}, {3.0, -0.5}, {-2.0, 0.2}};
  const BasePath path(segs, 0.0, 0.1, {kCar.R_m, 0.5, 0.5, 1.0, 4.0});
  const Config q0{0.0, 0.1, 0.5, -0.5, 0.3};
  for (double theta : {0.0, 1.0, 2.5, -2.0}) {
    const auto g = liftcheck::e2::element(theta, 3.0, -1.0);
    const Config a = act(g, lift_end(kCar, path, q0));
    const Config b = lift_end(kCar, path, act(g, q0));
    EXPECT_LT((a.vec() - b.vec()).norm(), 1e-10) << theta;
  }
}

TEST(Lift, SteeringAloneMovesNoRod) {
  const Config q0{0.0, -0.2, 1.0, 1.0, 0.4};
  const BasePath path({{0.0, 0.6}, {0.0, -0.3}}, 0.0, -0.2, {kCar.R_m, 0.5, 0.5, 1.0, 4.0});
  const Config q = lift_end(kCar, path, q0);
  EXPECT_EQ(q.x_m, q0.x_m);
  EXPECT_EQ(q.y_m, q0.y_m);
  EXPECT_EQ(q.phi_rad, q0.phi_rad);
  EXPECT_NEAR(q.beta_rad, 0.1, 1e-15);
}

TEST(Lift, LiftOfSamplesConvergesToTheIntegratedLift) {
  // Second order in the sample spacing along a path that steers while driving.
  const std::vector<Segment> segs{{2.0, 0.3}, {3.0, -0.5}};
  const BasePath path(segs, 0.0, 0.1, {kCar.R_m, 0.5, 0.5, 1.0, 4.0});
  const Config q0{0.0, 0.1, 0.5, -0.5, 0.3};
  const Config ref = lift_end(kCar, path, q0);
  std::vector<double> err;
  for (double h : {0.04, 0.02, 0.01}) {
    LiftDef def;
    def.sample_dt_s = h;
    const Config q = lift_of_samples(kCar, lift(kCar, path, q0, def));
    err.push_back((q.vec() - ref.vec()).norm());
  }
  EXPECT_LT(err[2], 1e-5);
  EXPECT_NEAR(err[0] / err[1], 4.0, 0.5);
  EXPECT_NEAR(err[1] / err[2], 4.0, 0.5);
}
