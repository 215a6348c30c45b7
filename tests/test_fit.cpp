#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "scenarios/fit.hpp"

using liftcheck::fit_circle;

TEST(CircleFit, RecoversAnExactArc) {
  std::vector<Eigen::Vector2d> pts;
  for (double a = 0.3; a < 1.9; a += 0.01) pts.emplace_back(5.0 + 3.38 * std::cos(a), -2.0 + 3.38 * std::sin(a));
  const auto f = fit_circle(pts);
  EXPECT_NEAR(f.radius_m, 3.38, 1e-12);
  EXPECT_NEAR(f.cx_m, 5.0, 1e-11);
  EXPECT_NEAR(f.cy_m, -2.0, 1e-11);
  EXPECT_LT(f.rms_residual_m, 1e-12);
}

TEST(CircleFit, GeometricFitIsUnbiasedUnderSymmetricNoise) {
  std::mt19937 rng(11);
  std::normal_distribution<double> n(0.0, 1e-3);
  std::vector<Eigen::Vector2d> pts;
  for (double a = 0.0; a < 6.28; a += 0.002) {
    const double r = 10.0 + n(rng);
    pts.emplace_back(r * std::cos(a), r * std::sin(a));
  }
  const auto f = fit_circle(pts);
  EXPECT_NEAR(f.radius_m, 10.0, 1e-4);
  EXPECT_NEAR(f.rms_residual_m, 1e-3, 1e-4);
}

TEST(CircleFit, RejectsTooFewPoints) { EXPECT_THROW(fit_circle({{0, 0}, {1, 0}}), std::invalid_argument); }

TEST(LogLogSlope, RecoversAPowerLaw) {
  std::vector<double> x, y;
  for (double v : {0.01, 0.03, 0.1, 0.3}) x.push_back(v), y.push_back(7.0 * std::pow(v, 4.0));
  EXPECT_NEAR(liftcheck::loglog_slope(x, y), 4.0, 1e-12);
  EXPECT_THROW(liftcheck::loglog_slope({1.0}, {1.0}), std::invalid_argument);
}
