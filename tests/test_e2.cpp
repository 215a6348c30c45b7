// E(2) and e(2) (appendices A, B) against direct matrix computations.
#include <gtest/gtest.h>

#include <unsupported/Eigen/MatrixFunctions>

#include "models/e2.hpp"

using namespace liftcheck::e2;

TEST(E2, CommutationRelationsB1) {
  EXPECT_TRUE(bracket(basis(0), basis(1)).isApprox(-basis(2)));
  EXPECT_TRUE(bracket(basis(0), basis(2)).isApprox(basis(1)));
  EXPECT_TRUE(bracket(basis(1), basis(2)).isZero());
}

TEST(E2, StructureConstantsB2MatchMatrixCommutators) {
  for (int b = 0; b < 3; ++b)
    for (int c = 0; c < 3; ++c) {
      Mat3 from_constants = Mat3::Zero();
      for (int a = 0; a < 3; ++a) from_constants += structure_constant(a, b, c) * basis(a);
      EXPECT_TRUE((bracket(basis(b), basis(c)) - from_constants).isZero(1e-15)) << b << c;
    }
}

TEST(E2, ClosedFormExponentialMatchesMatrixExponential) {
  for (const Vec3& l : {Vec3(0.7, -1.2, 2.5), Vec3(1e-9, 0.3, -0.4), Vec3(-3.0, 0.0, 1.0), Vec3(0.0, 2.0, 3.0)}) {
    const Mat3 numeric = hat(l).exp();
    EXPECT_TRUE(exp(l).isApprox(numeric, 1e-12)) << exp(l) << "\n" << numeric;
  }
}

TEST(E2, ExponentialIsAOneParameterSubgroup) {
  const Vec3 l(0.4, 1.5, -0.7);
  EXPECT_TRUE((exp(0.3 * l) * exp(0.9 * l)).isApprox(exp(1.2 * l), 1e-14));
}

TEST(E2, ActionA4MovesBothEndsOfTheRodRigidly) {
  // (A.4) must equal transforming the rod's two end points by chi -> chi B + b (A.1).
  const Mat3 g = element(0.8, 1.5, -2.0);
  const Pose p{0.3, -0.4, 1.1};
  const double l = 1.7;
  using Row = Eigen::RowVector3d;
  const Row front(p.x_m, p.y_m, 1.0);
  const Row rear(p.x_m - l * std::cos(p.phi_rad), p.y_m - l * std::sin(p.phi_rad), 1.0);
  const Row f2 = front * g, r2 = rear * g;
  const Pose q = act(g, p);
  EXPECT_NEAR(q.x_m, f2[0], 1e-14);
  EXPECT_NEAR(q.y_m, f2[1], 1e-14);
  EXPECT_NEAR(q.phi_rad, std::atan2(f2[1] - r2[1], f2[0] - r2[0]), 1e-14);
}

TEST(E2, ActionIsAGroupActionAndA5IsItsOrbitMap) {
  const Mat3 g = element(0.8, 1.5, -2.0), h = element(-2.1, 0.2, 0.9);
  const Pose p{0.3, -0.4, 1.1};
  const Pose a = act(h, act(g, p)), b = act(g * h, p);  // row vectors: g acts first
  EXPECT_NEAR(a.x_m, b.x_m, 1e-14);
  EXPECT_NEAR(a.y_m, b.y_m, 1e-14);
  EXPECT_NEAR(wrap_angle(a.phi_rad - b.phi_rad), 0.0, 1e-14);
  const Pose r = act(element_of(p), Pose{});
  EXPECT_NEAR(r.x_m, p.x_m, 1e-15);
  EXPECT_NEAR(r.y_m, p.y_m, 1e-15);
  EXPECT_NEAR(r.phi_rad, p.phi_rad, 1e-15);
  const Pose back = pose_of(element_of(p));
  EXPECT_NEAR(back.phi_rad, p.phi_rad, 1e-15);
}

TEST(E2, WrapAngle) {
  EXPECT_NEAR(wrap_angle(3.0 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(wrap_angle(-0.5), -0.5, 1e-15);
  EXPECT_NEAR(wrap_angle(2.0 * M_PI + 0.25), 0.25, 1e-12);
}
