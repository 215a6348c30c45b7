#include "models/ackermann.hpp"

#include <cmath>

namespace liftcheck::car {

double ackermann_wheel_angle(double beta_rad, double l_m, double track_m, Side side) {
  const double s = static_cast<int>(side);
  return std::atan2(l_m * std::sin(beta_rad), l_m * std::cos(beta_rad) - s * 0.5 * track_m * std::sin(beta_rad));
}

double ackermann_drive_ratio(double beta_rad, double l_m, double track_m, Side side) {
  const double s = static_cast<int>(side);
  const double sb = std::sin(beta_rad);
  return std::hypot(sb, std::cos(beta_rad) - s * 0.5 * track_m / l_m * sb);
}

double ackermann_steer_rate_factor(double beta_rad, double l_m, double track_m, Side side) {
  const double rho = ackermann_drive_ratio(beta_rad, l_m, track_m, side);
  return 1.0 / (rho * rho);
}

double virtual_steering_angle(double beta_left_rad, double beta_right_rad) {
  const double num = 2.0 * std::sin(beta_left_rad) * std::sin(beta_right_rad);
  const double den = std::sin(beta_left_rad + beta_right_rad);
  // tan(beta) = num / den with beta in (-pi/2, pi/2]: atan2 with a non-negative second argument.
  return den >= 0.0 ? std::atan2(num, den) : std::atan2(-num, -den);
}

}  // namespace liftcheck::car
