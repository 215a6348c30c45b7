// The connection, its lifts, brackets, curvature and particle field against independent
// computations: finite differences of the exact flows and of the connection form, and the
// defining properties of a connection.
#include <gtest/gtest.h>

#include <random>

#include "models/car.hpp"
#include "models/holonomy.hpp"

using namespace liftcheck;
using namespace liftcheck::car;

namespace {

const CarDef kCar{0.3, 1.2};

std::vector<Config> sample_points() {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<Config> v;
  for (int i = 0; i < 12; ++i) v.push_back({u(rng), 0.6 * u(rng), 2.0 * u(rng), 2.0 * u(rng), 3.0 * u(rng)});
  return v;
}

Config flow(Field f, const Config& q, double s) {
  return f == Field::kAlpha ? flow_alpha(kCar, q, s) : flow_beta(q, s);
}

/// A vector field read off its exact flow by central differences.
Vec5 field_from_flow(Field f, const Config& q, double h = 1e-4) {
  return (flow(f, q, h).vec() - flow(f, q, -h).vec()) / (2.0 * h);
}

/// Lie bracket [U, V] from the four-step cycle of exact flows, Richardson-extrapolated:
/// (cycle(s) - p)/s^2 = [U, V] + O(s) with the convention checked in test_holonomy.cpp.
Vec5 bracket_from_flows(Field U, Field V, const Config& q) {
  const auto c = [&](double s) {
    Config r = flow(U, q, s);
    r = flow(V, r, s);
    r = flow(U, r, -s);
    r = flow(V, r, -s);
    return Vec5((r.vec() - q.vec()) / (s * s));
  };
  const double s = 2e-4;
  return 2.0 * c(s / 2.0) - c(s);
}

/// Jacobian of a vector field on P by central differences.
template <class F>
Eigen::Matrix<double, 5, 5> jacobian(F field, const Config& q, double h = 1e-4) {
  Eigen::Matrix<double, 5, 5> J;
  for (int j = 0; j < 5; ++j) {
    Vec5 dp = Vec5::Zero();
    dp[j] = h;
    J.col(j) = (field(Config::from(q.vec() + dp)) - field(Config::from(q.vec() - dp))) / (2.0 * h);
  }
  return J;
}

/// [U, V] = (DV) U - (DU) V for fields given as functions of the point.
template <class F, class G>
Vec5 lie_bracket_fd(F U, G V, const Config& q) {
  return jacobian(V, q) * U(q) - jacobian(U, q) * V(q);
}

}  // namespace

TEST(Connection, HorizontalLiftsAnnihilateTheConnectionForm33) {
  for (const Config& q : sample_points()) {
    EXPECT_TRUE((connection_form(kCar, q) * H_alpha(kCar, q)).isZero(1e-15));
    EXPECT_TRUE((connection_form(kCar, q) * H_beta(kCar, q)).isZero(1e-15));
  }
}

TEST(Connection, ReproducesFundamentalFieldsE5) {
  // A connection form maps the fundamental field of e_a to e_a: omega^b(xi_a) = delta^b_a.
  for (const Config& q : sample_points())
    for (int a = 0; a < 3; ++a) {
      const Eigen::Vector3d w = connection_form(kCar, q) * fundamental_field(a, q);
      EXPECT_TRUE(w.isApprox(Eigen::Vector3d::Unit(a), 1e-14)) << a << ": " << w.transpose();
    }
}

TEST(Connection, FundamentalFieldsE5GenerateTheActionA6) {
  for (const Config& q : sample_points())
    for (int a = 0; a < 3; ++a) {
      const double h = 1e-6;
      Eigen::Vector3d l = Eigen::Vector3d::Zero();
      l[a] = h;
      const Vec5 fd = (act(e2::exp(l), q).vec() - act(e2::exp(-l), q).vec()) / (2 * h);
      EXPECT_TRUE(fd.isApprox(fundamental_field(a, q), 1e-8)) << a;
    }
}

TEST(Connection, GaugePotential34IsThePullbackBySigma) {
  for (double beta : {-0.5, 0.0, 0.3, 1.0}) {
    const auto w = connection_form(kCar, Config{0.2, beta, 0.0, 0.0, 0.0});
    EXPECT_TRUE(e2::vee(gauge_potential(kCar, beta)).isApprox(w.col(kAlpha), 1e-15));
    EXPECT_TRUE(w.col(kBeta).isZero());
  }
}

TEST(Connection, HorizontalLiftsAreTheDerivativesOfTheExactFlows) {
  for (const Config& q : sample_points()) {
    EXPECT_TRUE(field_from_flow(Field::kAlpha, q).isApprox(H_alpha(kCar, q), 1e-8));
    EXPECT_TRUE(field_from_flow(Field::kBeta, q).isApprox(H_beta(kCar, q), 1e-9));
  }
}

TEST(Brackets, Bracket55MatchesFourStepCycleOfExactFlows) {
  for (const Config& q : sample_points()) {
    const Vec5 numeric = bracket_from_flows(Field::kAlpha, Field::kBeta, q);
    EXPECT_TRUE((numeric - bracket_alpha_beta(kCar, q)).norm() < 1e-6 * bracket_alpha_beta(kCar, q).norm())
        << numeric.transpose() << "\n"
        << bracket_alpha_beta(kCar, q).transpose();
  }
}

TEST(Brackets, IteratedBrackets56And57MatchFiniteDifferencesOfFlowFields) {
  const auto Ha = [](const Config& p) { return field_from_flow(Field::kAlpha, p); };
  const auto Hb = [](const Config& p) { return field_from_flow(Field::kBeta, p); };
  const auto W = [&](const Config& p) { return lie_bracket_fd(Ha, Hb, p); };
  for (const Config& q : sample_points()) {
    EXPECT_TRUE((W(q) - bracket_alpha_beta(kCar, q)).norm() < 1e-6) << (W(q) - bracket_alpha_beta(kCar, q)).norm();
    // One level of differences on the closed-form (5.5), which the test above checked.
    const auto W55 = [](const Config& p) { return bracket_alpha_beta(kCar, p); };
    const Vec5 aab = lie_bracket_fd(Ha, W55, q), bab = lie_bracket_fd(Hb, W55, q);
    EXPECT_TRUE((aab - bracket_alpha_alpha_beta(kCar, q)).norm() < 1e-6) << aab.transpose();
    EXPECT_TRUE((bab - bracket_beta_alpha_beta(kCar, q)).norm() < 1e-6) << bab.transpose();
  }
}

TEST(Curvature, Curvature512IsTheStructureEquationE8) {
  // Omega^a = d omega^a + 1/2 c^a_bc omega^b ^ omega^c, horizontal part: evaluated on hor U, hor V.
  // d omega by central differences of the coefficients of (3.3).
  for (const Config& q : sample_points()) {
    std::array<Eigen::Matrix<double, 3, 5>, 5> dw;  // derivative of the coefficient rows along coordinate i
    for (int i = 0; i < 5; ++i) {
      const double h = 1e-6;
      Vec5 dp = Vec5::Zero();
      dp[i] = h;
      dw[i] = (connection_form(kCar, Config::from(q.vec() + dp)) - connection_form(kCar, Config::from(q.vec() - dp))) /
              (2 * h);
    }
    const auto Omega = [&](const Vec5& U, const Vec5& V) {
      const Eigen::Matrix<double, 3, 5> w = connection_form(kCar, q);
      Eigen::Vector3d out = Eigen::Vector3d::Zero();
      for (int a = 0; a < 3; ++a) {
        double d = 0.0;  // d omega^a(U, V) = sum_ij d_i omega^a_j (U^i V^j - V^i U^j)
        for (int i = 0; i < 5; ++i)
          for (int j = 0; j < 5; ++j) d += dw[i](a, j) * (U[i] * V[j] - V[i] * U[j]);
        double quad = 0.0;
        for (int b = 0; b < 3; ++b)
          for (int c = 0; c < 3; ++c)
            quad += 0.5 * e2::structure_constant(a, b, c) *
                    (w.row(b).dot(U) * w.row(c).dot(V) - w.row(b).dot(V) * w.row(c).dot(U));
        out[a] = d + quad;
      }
      return out;
    };
    // On the horizontal lifts of d_alpha, d_beta the quadratic term vanishes.
    EXPECT_TRUE((Omega(H_alpha(kCar, q), H_beta(kCar, q)) - curvature(kCar, q)).norm() < 1e-8);
    // The structure equation holds on any pair of vectors: its value depends only on their
    // horizontal parts (U^alpha H_alpha + U^beta H_beta), which is what makes Omega tensorial.
    std::mt19937 rng(3);
    std::normal_distribution<double> n;
    for (int k = 0; k < 3; ++k) {
      Vec5 U, V;
      for (int i = 0; i < 5; ++i) U[i] = n(rng), V[i] = n(rng);
      const double area = U[kAlpha] * V[kBeta] - U[kBeta] * V[kAlpha];
      EXPECT_TRUE((Omega(U, V) - area * curvature(kCar, q)).norm() < 1e-7) << Omega(U, V).transpose();
    }
  }
}

TEST(Curvature, BracketIsMinusCurvatureOnFundamentalFieldsE7) {
  for (const Config& q : sample_points()) {
    const Eigen::Vector3d W = curvature(kCar, q);
    Vec5 rhs = Vec5::Zero();
    for (int a = 0; a < 3; ++a) rhs -= W[a] * fundamental_field(a, q);
    EXPECT_TRUE((rhs - bracket_alpha_beta(kCar, q)).norm() < 1e-15);
  }
}

TEST(Curvature, FieldStrength513IsThePullbackOfOmega) {
  // Follows the check: F^1 = -R sin(beta). The printed (5.13) has (R/l) sin(beta) there.
  for (double beta : {-0.7, 0.25, 1.1}) {
    const Eigen::Vector3d F = e2::vee(field_strength(kCar, beta));
    EXPECT_TRUE(F.isApprox(curvature(kCar, Config{0.0, beta, 0.0, 0.0, 0.0})));
    EXPECT_NEAR(F[1], -kCar.R_m * std::sin(beta), 1e-15);
    const double printed_F1 = kCar.R_m / kCar.l_m * std::sin(beta);
    EXPECT_GT(std::abs(F[1] - printed_F1), 0.1 * std::abs(printed_F1));
  }
}

TEST(ParticleField, TransformsWithRho62And67) {
  for (const Config& q : sample_points()) {
    const double theta = 0.9;
    const auto g = e2::element(theta, 0.4, -1.3);
    // psi(R_B p) = rho(B^{-1}) psi(p), and B^{-1} is the rotation by -theta.
    EXPECT_TRUE(particle_field(act(g, q)).isApprox(rho(-theta) * particle_field(q), 1e-14));
  }
}

TEST(ParticleField, RateAlongHAlpha68IsTheDerivativeAlongTheFlow) {
  for (const Config& q : sample_points()) {
    const double h = 1e-5;
    const Eigen::Vector2d fd =
        (particle_field(flow_alpha(kCar, q, h)) - particle_field(flow_alpha(kCar, q, -h))) / (2 * h);
    EXPECT_TRUE((fd - particle_field_rate(kCar, q)).norm() < 1e-9);
  }
}

TEST(Flows, AppendixDCircleHoldsEveryPointOfTheArc) {
  for (const Config& q0 : sample_points()) {
    if (std::abs(q0.beta_rad) < 1e-3) continue;
    const Circle c = front_circle(kCar, q0), r = rear_circle(kCar, q0);
    EXPECT_NEAR(c.radius_m, kCar.l_m / std::abs(std::sin(q0.beta_rad)), 1e-12);
    for (double a : {0.0, 1.0, 5.0, -7.0, 40.0}) {
      const Config q = flow_alpha(kCar, q0, a);
      EXPECT_NEAR(std::hypot(q.x_m - c.cx_m, q.y_m - c.cy_m), c.radius_m, 1e-11);
      const Eigen::Vector2d rear = rear_axle_W(kCar, q);
      EXPECT_NEAR(std::hypot(rear.x() - r.cx_m, rear.y() - r.cy_m), r.radius_m, 1e-11);
    }
  }
}

TEST(Flows, StraightLineAtZeroSteeringAndContinuityNearIt) {
  const Config q0{0.0, 0.0, 1.0, 2.0, 0.5};
  const Config q = flow_alpha(kCar, q0, 3.0);
  EXPECT_NEAR(q.x_m, 1.0 + 0.9 * std::cos(0.5), 1e-15);
  EXPECT_NEAR(q.y_m, 2.0 + 0.9 * std::sin(0.5), 1e-15);
  EXPECT_EQ(q.phi_rad, 0.5);
  // The arc formula and the series branch agree across the switch at |turn| = 1e-4.
  for (double beta : {3.99e-4, 4.01e-4}) {
    const Config a = flow_alpha(kCar, Config{0, beta, 0, 0, 0.3}, 1.0);
    const double k = kCar.R_m / kCar.l_m * std::sin(beta);
    const double rc = kCar.l_m / std::sin(beta);
    EXPECT_NEAR(a.x_m, rc * (std::sin(0.3 + beta + k) - std::sin(0.3 + beta)), 1e-12);
    EXPECT_NEAR(a.y_m, -rc * (std::cos(0.3 + beta + k) - std::cos(0.3 + beta)), 1e-12);
  }
}
