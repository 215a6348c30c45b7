// Holonomy of the parking cycles: exact compositions of flows against the bracket predictions,
// over a decade sweep of eps, with fitted log-log slopes.
#include <gtest/gtest.h>

#include <cmath>

#include "models/holonomy.hpp"
#include "scenarios/fit.hpp"
#include "models/lift.hpp"

using liftcheck::loglog_slope;

using namespace liftcheck::car;

namespace {

const CarDef kCar{0.3, 1.2};
const Config kStart{0.0, 0.4, 0.0, 0.0, 0.7};

Vec5 holonomy(const std::vector<Step>& steps, const Config& q = kStart) {
  return apply_exact(kCar, q, steps).vec() - q.vec();
}

const std::vector<double> kEps{0.001, 0.002, 0.005, 0.01, 0.02, 0.05, 0.1};

}  // namespace

TEST(Cycles, StepsCloseInTheBase) {
  for (const auto& steps : {simple_cycle(0.1, 0.2), iterated_cycle_alpha(0.1), iterated_cycle_beta(0.1)}) {
    double a = 0, b = 0;
    for (const Step& s : steps) (s.field == Field::kAlpha ? a : b) += s.amount_rad;
    EXPECT_NEAR(a, 0.0, 1e-15);
    EXPECT_NEAR(b, 0.0, 1e-15);
  }
  EXPECT_EQ(iterated_cycle_alpha(0.1).size(), 10u);
}

TEST(Cycles, SimpleCycleHolonomyScalesAsEpsSquared) {
  std::vector<double> size;
  for (double e : kEps) size.push_back(holonomy(simple_cycle(e, e)).norm());
  EXPECT_NEAR(loglog_slope(kEps, size), 2.0, 0.02);
}

TEST(Cycles, IteratedCyclesScaleAsEpsToTheFourth) {
  std::vector<double> a, b;
  for (double e : kEps) {
    a.push_back(holonomy(iterated_cycle_alpha(e)).norm());
    b.push_back(holonomy(iterated_cycle_beta(e)).norm());
  }
  EXPECT_NEAR(loglog_slope(kEps, a), 4.0, 0.02);
  EXPECT_NEAR(loglog_slope(kEps, b), 4.0, 0.02);
}

TEST(Cycles, LeadingOrderPredictionsConvergeLinearlyInEps) {
  // |exact - predicted| / |predicted| = O(eps): the error ratio over a decade is about 10.
  const auto rel = [](const Vec5& exact, const Vec5& pred) { return (exact - pred).norm() / pred.norm(); };
  for (int kind = 0; kind < 3; ++kind) {
    std::vector<double> err;
    for (double e : kEps) {
      const Vec5 ex = kind == 0   ? holonomy(simple_cycle(e, e))
                      : kind == 1 ? holonomy(iterated_cycle_alpha(e))
                                  : holonomy(iterated_cycle_beta(e));
      const Vec5 pr = kind == 0   ? predicted_simple(kCar, kStart, e, e)
                      : kind == 1 ? predicted_iterated_alpha(kCar, kStart, e)
                                  : predicted_iterated_beta(kCar, kStart, e);
      err.push_back(rel(ex, pr));
      EXPECT_LT(err.back(), e) << "kind " << kind << " eps " << e;
    }
    EXPECT_NEAR(loglog_slope(kEps, err), 1.0, 0.1) << "kind " << kind;
  }
}

TEST(Cycles, SimpleCycleMovesAlongPlusBracketNotThePrinted53) {
  // At beta = phi = 0: forth, steer left, back, steer right. Backing with the wheel turned left
  // swings the front to the right: dy < 0 and dphi < 0, i.e. +eps^2 [H_alpha, H_beta].
  const double e = 1e-3;
  const Config q0{0, 0, 0, 0, 0};
  const Vec5 d = apply_exact(kCar, q0, simple_cycle(e, e)).vec() - q0.vec();
  EXPECT_NEAR(d[kY] / (e * e), -kCar.R_m, 1e-3);
  EXPECT_NEAR(d[kPhi] / (e * e), -kCar.R_m / kCar.l_m, 1e-3);
  // The printed (5.3) predicts y + eps^2 R cos(phi + beta), phi + eps^2 (R/l) cos(beta).
  EXPECT_LT(d[kY] * (e * e * kCar.R_m), 0.0);
}

TEST(Cycles, IteratedCycle58ShiftsSidewaysAsIn59) {
  // (5.9): x + eps^4 (R^2/l) sin(phi), y - eps^4 (R^2/l) cos(phi), phi unchanged.
  const double e = 0.01, k = e * e * e * e * kCar.R_m * kCar.R_m / kCar.l_m;
  const Vec5 d = holonomy(iterated_cycle_alpha(e));
  EXPECT_NEAR(d[kX] / (k * std::sin(kStart.phi_rad)), 1.0, 0.02);
  EXPECT_NEAR(d[kY] / (-k * std::cos(kStart.phi_rad)), 1.0, 0.02);
  EXPECT_NEAR(d[kPhi], 0.0, 1e-15);
}

TEST(Cycles, IteratedCycle510SlidesBackwardsNotForth) {
  // -eps^4 (H_alpha - d_alpha): the rod moves against its rolling direction for eps > 0.
  for (double e : {0.01, 0.05}) {
    const Vec5 d = holonomy(iterated_cycle_beta(e));
    const double along =
        d[kX] * std::cos(kStart.beta_rad + kStart.phi_rad) + d[kY] * std::sin(kStart.beta_rad + kStart.phi_rad);
    EXPECT_LT(along, 0.0);
    EXPECT_NEAR(along / (-std::pow(e, 4) * kCar.R_m), 1.0, 0.1);
  }
}

TEST(Cycles, HolonomyIsEquivariant) {
  // The holonomy seen from a moved start is the moved holonomy: R_B commutes with the lift.
  const auto g = liftcheck::e2::element(1.3, -0.7, 2.2);
  const Config moved = act(g, kStart);
  const Config a = act(g, apply_exact(kCar, kStart, iterated_cycle_alpha(0.2)));
  const Config b = apply_exact(kCar, moved, iterated_cycle_alpha(0.2));
  EXPECT_TRUE((a.vec() - b.vec()).norm() < 1e-14);
}

TEST(Cycles, ExactFlowsAgreeWithIntegratedLift) {
  const DriveDef drive{kCar.R_m, 0.5, 0.5, 1.0, 4.0};
  for (const auto& steps : {simple_cycle(0.1, 0.15), iterated_cycle_alpha(0.3), iterated_cycle_beta(0.3)}) {
    const BasePath path(to_segments(steps), kStart.alpha_rad, kStart.beta_rad, drive);
    const Config integrated = lift_end(kCar, path, kStart);
    const Vec5 exact = holonomy(steps), numeric = integrated.vec() - kStart.vec();
    EXPECT_LT((exact - numeric).norm(), 1e-9 * exact.norm()) << exact.transpose() << "\n" << numeric.transpose();
  }
}
