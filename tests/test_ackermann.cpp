// The four-wheel car's Ackermann geometry (models/ackermann.hpp) against an independent
// construction: the instantaneous centre of rotation found by intersecting the wheels' axle lines
// with the rear axle line (a linear solve), distances to it, and finite differences.
#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Dense>

#include "models/ackermann.hpp"

using namespace liftcheck::car;

namespace {

/// Where the axle line of a wheel at `p` turned by `angle` (the line through p along
/// (-sin angle, cos angle)) meets the rear axle line x = -l: a 2x2 linear solve.
Eigen::Vector2d axle_meets_rear_axle(const Eigen::Vector2d& p, double angle, double l) {
  Eigen::Matrix2d A;
  // p + t (-sin, cos) = (-l, 0) + u (0, 1)
  A << -std::sin(angle), 0.0, std::cos(angle), -1.0;
  const Eigen::Vector2d tu = A.colPivHouseholderQr().solve(Eigen::Vector2d(-l, 0.0) - p);
  return p + tu[0] * Eigen::Vector2d(-std::sin(angle), std::cos(angle));
}

struct Geometry {
  double l, w;
};

class AckermannGeometry : public ::testing::TestWithParam<std::tuple<double, double, double>> {};

TEST_P(AckermannGeometry, WheelAxlesMeetAtTheIcrOfTheVirtualAngle) {
  const auto [beta, l, w] = GetParam();
  const double bl = ackermann_wheel_angle(beta, l, w, Side::kLeft),
               br = ackermann_wheel_angle(beta, l, w, Side::kRight);
  const Eigen::Vector2d pl(0.0, 0.5 * w), pr(0.0, -0.5 * w), centre(0.0, 0.0);
  const Eigen::Vector2d icr_l = axle_meets_rear_axle(pl, bl, l), icr_r = axle_meets_rear_axle(pr, br, l);
  // Both front axles meet the rear axle line in the same point...
  EXPECT_NEAR((icr_l - icr_r).norm() / (1.0 + icr_l.norm()), 0.0, 1e-12);
  // ...about which the front-axle centre moves at the virtual angle beta to the rod (the paper's
  // beta): its velocity is perpendicular to the radius, turned towards the ICR's side.
  const Eigen::Vector2d radius = centre - icr_l;
  const Eigen::Vector2d v =
      beta > 0 ? Eigen::Vector2d(-radius.y(), radius.x()) : Eigen::Vector2d(radius.y(), -radius.x());
  EXPECT_NEAR(std::atan2(v.y(), v.x()), beta, 1e-12);
  // Turning radii: each wheel rolls at its distance from the ICR over the centre's.
  EXPECT_NEAR(ackermann_drive_ratio(beta, l, w, Side::kLeft), (pl - icr_l).norm() / radius.norm(), 1e-12);
  EXPECT_NEAR(ackermann_drive_ratio(beta, l, w, Side::kRight), (pr - icr_l).norm() / radius.norm(), 1e-12);
  // The Ackermann condition: cot(outer) - cot(inner) = w / l (left is inner for a left turn).
  const double inner = beta > 0 ? bl : br, outer = beta > 0 ? br : bl;
  EXPECT_NEAR(std::abs(1.0 / std::tan(outer) - 1.0 / std::tan(inner)), w / l, 1e-12);
  // The virtual angle back from the two wheel angles.
  EXPECT_NEAR(virtual_steering_angle(bl, br), beta, 1e-13);
  // Steering rate factors against central differences of the wheel angles.
  const double h = 1e-6;
  for (Side s : {Side::kLeft, Side::kRight}) {
    const double fd = (ackermann_wheel_angle(beta + h, l, w, s) - ackermann_wheel_angle(beta - h, l, w, s)) / (2 * h);
    EXPECT_NEAR(ackermann_steer_rate_factor(beta, l, w, s), fd, 1e-8);
  }
}

INSTANTIATE_TEST_SUITE_P(Angles, AckermannGeometry,
                         ::testing::Values(std::tuple{0.3, 1.0, 0.8}, std::tuple{-0.3, 1.0, 0.8},
                                           std::tuple{0.05, 1.0, 0.8}, std::tuple{1.2, 1.0, 0.8},
                                           std::tuple{-1.2, 1.0, 0.8}, std::tuple{0.5, 2.5, 1.6},
                                           std::tuple{-0.7, 0.6, 1.0}));

TEST(Ackermann, StraightAheadBothWheelsStraightAndEqualRates) {
  for (Side s : {Side::kLeft, Side::kRight}) {
    EXPECT_EQ(ackermann_wheel_angle(0.0, 1.0, 0.8, s), 0.0);
    EXPECT_EQ(ackermann_drive_ratio(0.0, 1.0, 0.8, s), 1.0);
    EXPECT_EQ(ackermann_steer_rate_factor(0.0, 1.0, 0.8, s), 1.0);
  }
  EXPECT_EQ(virtual_steering_angle(0.0, 0.0), 0.0);
}

TEST(Ackermann, KnownNumbers) {
  // beta = 0.3, l = 1, w = 0.8: c = cot(0.3) = 3.2327281437658275; the inner wheel's tangent is
  // 1 / (c - 0.4) = 0.353016..., the outer's 1 / (c + 0.4) = 0.275276...
  const double c = 1.0 / std::tan(0.3);
  EXPECT_NEAR(std::tan(ackermann_wheel_angle(0.3, 1.0, 0.8, Side::kLeft)), 1.0 / (c - 0.4), 1e-14);
  EXPECT_NEAR(std::tan(ackermann_wheel_angle(0.3, 1.0, 0.8, Side::kRight)), 1.0 / (c + 0.4), 1e-14);
  EXPECT_NEAR(ackermann_wheel_angle(0.3, 1.0, 0.8, Side::kLeft), 0.339360, 1e-6);
  EXPECT_NEAR(ackermann_wheel_angle(0.3, 1.0, 0.8, Side::kRight), 0.268622, 1e-6);
  // Fecko's "average" front wheel (introduction) is the tricycle's only to first order in w/l:
  // the mean of the two rolling rates exceeds the centre's by 6.2e-4 at beta = 0.3.
  const double mean =
      0.5 * (ackermann_drive_ratio(0.3, 1.0, 0.8, Side::kLeft) + ackermann_drive_ratio(0.3, 1.0, 0.8, Side::kRight));
  EXPECT_NEAR(mean - 1.0, 6.2e-4, 0.3e-4);
  // Parallel wheels give back their common angle.
  EXPECT_NEAR(virtual_steering_angle(-0.4, -0.4), -0.4, 1e-15);
}

}  // namespace
