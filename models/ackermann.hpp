// The four-wheel car behind Fecko's tricycle (introduction: "the *average* angle is understood
// ... as if the car were a tricycle"). Two steered front wheels at (0, +-w/2) in the chassis
// frame (x forward along the tie rod, origin at the front-axle centre, y left), the rear axle at
// x = -l. For the virtual (bicycle) steering angle beta the front-axle centre moves at beta to the
// rod (the paper's beta), and the instantaneous centre of rotation (ICR) lies on the rear axle
// line at y = c = l cot(beta). Ackermann steering turns each front wheel perpendicular to the line
// from the ICR to its centre:
//   cot(beta_s) = cot(beta) - s w / (2 l),  s = +1 left wheel, -1 right wheel,
// so cot(outer) - cot(inner) = w / l, and the virtual angle is recovered from the two wheel
// angles by the mean of their cotangents: cot(beta) = (cot(beta_left) + cot(beta_right)) / 2.
// Without slip each wheel centre moves at (its distance from the ICR) x (yaw rate): an electronic
// differential drives wheel s at rho_s times the front-axle centre's rolling rate,
//   rho_s = r_s / r = hypot(sin beta, cos beta - s (w / 2l) sin beta).
// All formulas are written with sin and cos so that they are continuous through beta = 0.
#pragma once

namespace liftcheck::car {

/// Which front wheel: +1 left, -1 right.
enum class Side : int { kLeft = 1, kRight = -1 };

/// Ackermann angle of the front wheel on `side` for the virtual steering angle beta (|beta| < pi/2):
/// atan2(l sin beta, l cos beta - s (w/2) sin beta), in (-pi, pi) (the inner wheel passes pi/2
/// when l cot|beta| < w/2).
double ackermann_wheel_angle(double beta_rad, double l_m, double track_m, Side side);

/// d(beta_s)/d(beta) = sin^2(beta_s) / sin^2(beta) = 1 / rho_s^2: the steering rate of wheel s
/// per unit rate of the virtual angle.
double ackermann_steer_rate_factor(double beta_rad, double l_m, double track_m, Side side);

/// rho_s: the rolling rate of front wheel s per unit rolling rate of the front-axle centre
/// (its turning radius over the centre's), 1 when driving straight.
double ackermann_drive_ratio(double beta_rad, double l_m, double track_m, Side side);

/// The virtual steering angle from the two front wheels' angles by the mean of the cotangents,
/// cot(beta) = (cot(beta_left) + cot(beta_right)) / 2, i.e. tan(beta) = 2 sin(bl) sin(br) / sin(bl + br),
/// returned in (-pi/2, pi/2]. Exact for Ackermann angles (and for parallel wheels, bl = br = beta).
double virtual_steering_angle(double beta_left_rad, double beta_right_rad);

}  // namespace liftcheck::car
