#include "models/e2.hpp"

#include <cmath>
#include <numbers>
#include <stdexcept>

namespace liftcheck::e2 {

Mat3 basis(int a) {
  Mat3 m = Mat3::Zero();
  switch (a) {
    case 0:
      m(0, 1) = 1.0;
      m(1, 0) = -1.0;
      break;
    case 1:
      m(2, 0) = 1.0;
      break;
    case 2:
      m(2, 1) = 1.0;
      break;
    default:
      throw std::out_of_range("e(2) has basis indices 0, 1, 2");
  }
  return m;
}

Mat3 hat(const Vec3& lambda) { return lambda[0] * basis(0) + lambda[1] * basis(1) + lambda[2] * basis(2); }

Vec3 vee(const Mat3& m) { return {m(0, 1), m(2, 0), m(2, 1)}; }

Mat3 bracket(const Mat3& a, const Mat3& b) { return a * b - b * a; }

double structure_constant(int a, int b, int c) {
  // (B.2): c^2_{10} = -c^2_{01} = c^1_{02} = -c^1_{20} = 1, all others zero.
  if (a == 2 && b == 1 && c == 0) return 1.0;
  if (a == 2 && b == 0 && c == 1) return -1.0;
  if (a == 1 && b == 0 && c == 2) return 1.0;
  if (a == 1 && b == 2 && c == 0) return -1.0;
  return 0.0;
}

Mat3 exp(const Vec3& lambda) {
  // For a row-vector generator [[0, w, 0], [-w, 0, 0], [c1, c2, 0]] the flow of
  // d(eta)/dt = eta * X rotates by the angle w and translates along the integrated direction.
  const double w = lambda[0];
  const double c1 = lambda[1], c2 = lambda[2];
  double s_over_w = 1.0, one_minus_c_over_w = 0.0;
  if (std::abs(w) > 1e-8) {
    s_over_w = std::sin(w) / w;
    one_minus_c_over_w = (1.0 - std::cos(w)) / w;
  } else {
    s_over_w = 1.0 - w * w / 6.0;
    one_minus_c_over_w = w / 2.0 - w * w * w / 24.0;
  }
  // b = c * V with V = [[sin w / w, (1 - cos w)/w], [-(1 - cos w)/w, sin w / w]] (row vector c).
  const double b1 = c1 * s_over_w - c2 * one_minus_c_over_w;
  const double b2 = c1 * one_minus_c_over_w + c2 * s_over_w;
  return element(w, b1, b2);
}

Mat3 element(double theta_rad, double b1_m, double b2_m) {
  const double c = std::cos(theta_rad), s = std::sin(theta_rad);
  Mat3 m;
  m << c, s, 0.0, -s, c, 0.0, b1_m, b2_m, 1.0;
  return m;
}

Mat3 element_of(const Pose& pose) { return element(pose.phi_rad, pose.x_m, pose.y_m); }

Pose pose_of(const Mat3& m) { return {m(2, 0), m(2, 1), std::atan2(m(0, 1), m(0, 0))}; }

Pose act(const Mat3& g, const Pose& pose) {
  // (A.4): both ends of the rod move by chi -> chi B + b; the heading turns by theta.
  const double theta = std::atan2(g(0, 1), g(0, 0));
  const double c = std::cos(theta), s = std::sin(theta);
  return {pose.x_m * c - pose.y_m * s + g(2, 0), pose.x_m * s + pose.y_m * c + g(2, 1), pose.phi_rad + theta};
}

double wrap_angle(double a_rad) {
  const double two_pi = 2.0 * std::numbers::pi;
  double r = std::fmod(a_rad + std::numbers::pi, two_pi);
  if (r <= 0.0) r += two_pi;
  return r - std::numbers::pi;
}

}  // namespace liftcheck::e2
