#include "models/car.hpp"

#include <cmath>
#include <stdexcept>

namespace liftcheck::car {

Vec5 Config::vec() const {
  Vec5 v;
  v << alpha_rad, beta_rad, x_m, y_m, phi_rad;
  return v;
}

Config Config::from(const Vec5& v) { return {v[kAlpha], v[kBeta], v[kX], v[kY], v[kPhi]}; }

Eigen::Vector2d rear_axle_W(const CarDef& car, const Config& q) {
  return {q.x_m - car.l_m * std::cos(q.phi_rad), q.y_m - car.l_m * std::sin(q.phi_rad)};
}

Vec5 H_alpha(const CarDef& car, const Config& q) {
  // (4.3): H_alpha = d_alpha + R cos(beta+phi) d_x + R sin(beta+phi) d_y + (R/l) sin(beta) d_phi
  const double s = q.beta_rad + q.phi_rad;
  Vec5 v;
  v << 1.0, 0.0, car.R_m * std::cos(s), car.R_m * std::sin(s), car.R_m / car.l_m * std::sin(q.beta_rad);
  return v;
}

Vec5 H_beta(const CarDef&, const Config&) {
  Vec5 v = Vec5::Zero();
  v[kBeta] = 1.0;
  return v;
}

Eigen::Matrix<double, 3, 5> connection_form(const CarDef& car, const Config& q) {
  // (3.3), columns (dalpha, dbeta, dx, dy, dphi):
  //   omega^0 = dphi - (R/l) sin(beta) dalpha
  //   omega^1 = dx + y omega^0 - R cos(beta+phi) dalpha
  //   omega^2 = dy - x omega^0 - R sin(beta+phi) dalpha
  const double s = q.beta_rad + q.phi_rad;
  Eigen::Matrix<double, 1, 5> w0;
  w0 << -car.R_m / car.l_m * std::sin(q.beta_rad), 0.0, 0.0, 0.0, 1.0;
  Eigen::Matrix<double, 1, 5> w1 = q.y_m * w0;
  w1[kAlpha] -= car.R_m * std::cos(s);
  w1[kX] += 1.0;
  Eigen::Matrix<double, 1, 5> w2 = -q.x_m * w0;
  w2[kAlpha] -= car.R_m * std::sin(s);
  w2[kY] += 1.0;
  Eigen::Matrix<double, 3, 5> w;
  w << w0, w1, w2;
  return w;
}

Mat3 gauge_potential(const CarDef& car, double beta_rad) {
  // (3.4): A = -(R/l) [[0, sin b, 0], [-sin b, 0, 0], [l cos b, l sin b, 0]] dalpha
  const double sb = std::sin(beta_rad), cb = std::cos(beta_rad);
  Mat3 m;
  m << 0.0, sb, 0.0, -sb, 0.0, 0.0, car.l_m * cb, car.l_m * sb, 0.0;
  return -car.R_m / car.l_m * m;
}

Vec5 bracket_alpha_beta(const CarDef& car, const Config& q) {
  // (5.5): [H_alpha, H_beta] = R { sin(phi+beta) d_x - cos(phi+beta) d_y - (1/l) cos(beta) d_phi }
  const double s = q.beta_rad + q.phi_rad;
  Vec5 v;
  v << 0.0, 0.0, car.R_m * std::sin(s), -car.R_m * std::cos(s), -car.R_m / car.l_m * std::cos(q.beta_rad);
  return v;
}

Vec5 bracket_alpha_alpha_beta(const CarDef& car, const Config& q) {
  // (5.6): (R^2/l) (cos(phi) d_y - sin(phi) d_x)
  const double k = car.R_m * car.R_m / car.l_m;
  Vec5 v;
  v << 0.0, 0.0, -k * std::sin(q.phi_rad), k * std::cos(q.phi_rad), 0.0;
  return v;
}

Vec5 bracket_beta_alpha_beta(const CarDef& car, const Config& q) {
  // (5.7): H_alpha - d_alpha
  Vec5 v = H_alpha(car, q);
  v[kAlpha] = 0.0;
  return v;
}

Vec3 curvature(const CarDef& car, const Config& q) {
  // (5.12), coefficients of dalpha ^ dbeta.
  const double s = q.beta_rad + q.phi_rad;
  const double k = car.R_m / car.l_m * std::cos(q.beta_rad);
  return {k, -car.R_m * std::sin(s) + k * q.y_m, car.R_m * std::cos(s) - k * q.x_m};
}

Mat3 field_strength(const CarDef& car, double beta_rad) {
  // sigma^* Omega: (5.12) at x = y = phi = 0 gives F^0 = (R/l) cos b, F^1 = -R sin b,
  // F^2 = R cos b. The printed (5.13) has (R/l) sin b in place of -R sin b (ERRATA.md).
  return e2::hat(curvature(car, Config{0.0, beta_rad, 0.0, 0.0, 0.0}));
}

Vec5 fundamental_field(int a, const Config& q) {
  // (E.5): xi_0 = -y d_x + x d_y + d_phi, xi_1 = d_x, xi_2 = d_y
  Vec5 v = Vec5::Zero();
  switch (a) {
    case 0:
      v[kX] = -q.y_m;
      v[kY] = q.x_m;
      v[kPhi] = 1.0;
      break;
    case 1:
      v[kX] = 1.0;
      break;
    case 2:
      v[kY] = 1.0;
      break;
    default:
      throw std::out_of_range("e(2) has basis indices 0, 1, 2");
  }
  return v;
}

Eigen::Vector2d particle_field(const Config& q) { return {std::cos(q.phi_rad), std::sin(q.phi_rad)}; }

Eigen::Matrix2d rho(double theta_rad) {
  // (6.7): rho(B(theta), b) = [[cos, sin], [-sin, cos]]
  Eigen::Matrix2d m;
  m << std::cos(theta_rad), std::sin(theta_rad), -std::sin(theta_rad), std::cos(theta_rad);
  return m;
}

Eigen::Vector2d particle_field_rate(const CarDef& car, const Config& q) {
  // (6.8): H_alpha psi = (R/l) sin(beta) (-sin phi, cos phi)
  return car.R_m / car.l_m * std::sin(q.beta_rad) * Eigen::Vector2d(-std::sin(q.phi_rad), std::cos(q.phi_rad));
}

Config act(const Mat3& g, const Config& q) {
  const e2::Pose p = e2::act(g, q.pose());
  return {q.alpha_rad, q.beta_rad, p.x_m, p.y_m, p.phi_rad};
}

Config flow_alpha(const CarDef& car, const Config& q, double d_alpha_rad) {
  // Appendix D with beta0 = beta, started at (x0, y0, phi0); arc length of the front wheel R dalpha.
  Config r = q;
  r.alpha_rad = q.alpha_rad + d_alpha_rad;
  const double sb = std::sin(q.beta_rad);
  const double turn = d_alpha_rad * car.R_m / car.l_m * sb;  // phi(alpha) - phi0
  const double a0 = q.phi_rad + q.beta_rad;
  // x(alpha) - x0 = (l/sin b)(sin(a0 + t) - sin a0) = L (cos a0 * sin t/t - sin a0 * (1 - cos t)/t),
  // likewise for y; the right-hand form with L = R dalpha has no cancellation for small t.
  const double L = car.R_m * d_alpha_rad;
  double f = 1.0, g = 0.0;  // sin(t)/t and (1 - cos t)/t = 2 sin^2(t/2)/t
  if (std::abs(turn) < 1e-4) {
    const double t2 = turn * turn;
    f = 1.0 - t2 / 6.0 + t2 * t2 / 120.0;
    g = turn / 2.0 - turn * t2 / 24.0 + turn * t2 * t2 / 720.0;
  } else {
    const double h = std::sin(0.5 * turn);
    f = std::sin(turn) / turn;
    g = 2.0 * h * h / turn;
  }
  r.x_m = q.x_m + L * (std::cos(a0) * f - std::sin(a0) * g);
  r.y_m = q.y_m + L * (std::sin(a0) * f + std::cos(a0) * g);
  r.phi_rad = q.phi_rad + turn;
  return r;
}

Config flow_beta(const Config& q, double d_beta_rad) {
  Config r = q;
  r.beta_rad += d_beta_rad;
  return r;
}

Circle front_circle(const CarDef& car, const Config& q0) {
  // Appendix D: r_c = l / sin(beta0), x_c = x0 - r_c sin(phi0 + beta0),
  // y_c = y0 + r_c cos(phi0 + beta0) (printed with x0; ERRATA.md). Radius reported positive.
  const double sb = std::sin(q0.beta_rad);
  if (sb == 0.0) throw std::invalid_argument("beta0 = 0 drives a straight line, not a circle");
  const double rc = car.l_m / sb;
  const double a0 = q0.phi_rad + q0.beta_rad;
  return {std::abs(rc), q0.x_m - rc * std::sin(a0), q0.y_m + rc * std::cos(a0)};
}

Circle rear_circle(const CarDef& car, const Config& q0) {
  Circle c = front_circle(car, q0);
  c.radius_m = std::abs(car.l_m / std::tan(q0.beta_rad));
  return c;
}

}  // namespace liftcheck::car
