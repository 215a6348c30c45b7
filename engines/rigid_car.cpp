#include "engines/rigid_car.hpp"

#include <cmath>
#include <fmt/format.h>

#include "models/e2.hpp"

namespace liftcheck {

TricycleDef TricycleDef::from(const CarSetup& setup) {
  TricycleDef d;
  d.R_m = setup.car.R_m;
  d.l_m = setup.car.l_m;
  d.track_m = 0.8 * setup.car.l_m;
  d.wheel_width_m = 0.3 * setup.car.R_m;
  d.chassis_height_m = std::min(0.1, 0.5 * setup.car.R_m);
  return d;
}

void RigidCar::reset(const CarSetup& setup, const car::Config& q0) {
  setup_ = setup;
  def_ = TricycleDef::from(setup);
  q0_ = q0;
  build(setup_, def_, q0_);
}

std::vector<car::TimedConfig> RigidCar::drive(const car::BasePath& path) {
  const double dt = setup_.dt_s;
  const double T = path.duration_s();
  const long settle_steps = std::lround(servo_.settle_s / dt);
  const long steps = static_cast<long>(std::ceil((T + servo_.hold_s) / dt - 1e-9));
  const long sample_every = std::max(1L, std::lround(setup_.sample_dt_s / dt));

  RigidCarState s = read();
  double alpha = 0.0;  // unwrapped wheel angle
  double prev_joint = s.spin_joint_rad;
  double prev_phi = s.phi_rad;
  double phi = q0_.phi_rad + e2::wrap_angle(s.phi_rad - q0_.phi_rad);  // unwrapped from the start heading
  std::vector<car::TimedConfig> trace;

  // One step: servo towards (target_alpha, target_beta) with feed-forward rates, then read and check.
  const auto advance = [&](double t_end, double target_alpha, double target_beta, double alpha_rate, double beta_rate) {
    actuate(alpha_rate + servo_.spin_gain_per_s * (target_alpha - alpha),
            beta_rate + servo_.steer_gain_per_s * (target_beta - s.steer_rad), servo_);
    step(dt);
    stepped_s_ += dt;
    s = read();
    alpha += e2::wrap_angle(s.spin_joint_rad - prev_joint);
    prev_joint = s.spin_joint_rad;
    phi += e2::wrap_angle(s.phi_rad - prev_phi);
    prev_phi = s.phi_rad;
    const bool finite = std::isfinite(s.x_m) && std::isfinite(s.y_m) && std::isfinite(s.z_m) &&
                        std::isfinite(s.phi_rad) && std::isfinite(s.steer_rad) && std::isfinite(alpha);
    if (!finite) throw EngineError(fmt::format("simulation produced NaN at t = {:.4f} s", t_end));
    static const char* const kWheel[3] = {"front", "rear left", "rear right"};
    for (int w = 0; w < 3; ++w) {
      const double v = s.wheels[w].v_hub_W.norm();
      if (!(v <= kRunawaySpeed_mps))
        throw EngineError(fmt::format("{} wheel speed {:.3g} m/s at t = {:.4f} s (a blow-up: above {} m/s)", kWheel[w], v, t_end, kRunawaySpeed_mps));
    }
    for (const auto& [which, z] : {std::pair{"front", s.z_m}, std::pair{"rear", s.rear_z_m}})
      if (std::abs(z - def_.R_m) > def_.R_m)
        throw EngineError(fmt::format("car left the ground ({} wheel centre at z = {:.3f} m, radius {:.3f} m) at t = {:.4f} s",
                                      which, z, def_.R_m, t_end));
  };

  // Settle on the wheels: the contacts load up while the servos hold alpha = 0 and beta = beta0.
  for (long k = 0; k < settle_steps; ++k) advance(-(settle_steps - k - 1) * dt, 0.0, q0_.beta_rad, 0.0, 0.0);
  alpha = 0.0;  // the drive starts at alpha = 0

  // Contact-point slip of each wheel, every step of the drive: the contact point of a sphere (or an
  // upright cylinder) on the ground z = 0 lies straight below the hub.
  static const char* const kWheelNames[3] = {"front", "rear left", "rear right"};
  slip_.assign(3, WheelSlip{});
  double sum_sq[3] = {0.0, 0.0, 0.0};
  const auto book_slip = [&] {
    for (int w = 0; w < 3; ++w) {
      const WheelState& ws = s.wheels[w];
      const Eigen::Vector3d v = ws.v_hub_W + ws.omega_W.cross(Eigen::Vector3d(0.0, 0.0, -ws.hub_z_m));
      Eigen::Vector3d axle(ws.axle_W.x(), ws.axle_W.y(), 0.0);
      axle.normalize();
      const Eigen::Vector3d roll = axle.cross(Eigen::Vector3d::UnitZ());
      slip_[w].along_max_mps = std::max(slip_[w].along_max_mps, std::abs(v.dot(roll)));
      slip_[w].across_max_mps = std::max(slip_[w].across_max_mps, std::abs(v.dot(axle)));
      sum_sq[w] += v.x() * v.x() + v.y() * v.y();
    }
  };

  const auto sample = [&](double t) { trace.push_back({t, car::Config{alpha, s.steer_rad, s.x_m, s.y_m, phi}}); };
  sample(0.0);
  for (long k = 0; k < steps; ++k) {
    const double t1 = (k + 1) * dt;
    const car::BaseSample mid = path.at(t1 - 0.5 * dt), end = path.at(t1);
    advance(t1, end.alpha_rad, end.beta_rad, mid.alpha_rate_radps, mid.beta_rate_radps);
    book_slip();
    if ((k + 1) % sample_every == 0 || k + 1 == steps) sample(t1);
  }
  for (int w = 0; w < 3; ++w) {
    slip_[w].wheel = kWheelNames[w];
    slip_[w].rms_mps = steps > 0 ? std::sqrt(sum_sq[w] / steps) : 0.0;
    slip_[w].along_measured = wheels_spin();
  }
  return trace;
}

}  // namespace liftcheck
