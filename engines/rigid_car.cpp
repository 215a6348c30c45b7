#include "engines/rigid_car.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "models/ackermann.hpp"
#include "models/e2.hpp"

namespace liftcheck {

TricycleDef TricycleDef::from(const CarSetup& setup) {
  TricycleDef d;
  d.R_m = setup.car.R_m;
  d.l_m = setup.car.l_m;
  d.track_m = setup.track_m;
  d.wheels = setup.wheels;
  d.parallel_steering = setup.parallel_steering;
  d.chassis_mass_kg = setup.chassis_mass_kg;
  d.wheel_mass_kg = setup.wheel_mass_kg;
  d.knuckle_mass_kg = setup.knuckle_mass_kg;
  d.wheel_width_m = 0.3 * setup.car.R_m;
  d.chassis_height_m = std::min(0.1, 0.5 * setup.car.R_m);
  return d;
}

double car_mass_kg(const TricycleDef& car) {
  const int n_front = car.wheels == 4 ? 2 : 1;
  return car.chassis_mass_kg + car.wheels * car.wheel_mass_kg + n_front * car.knuckle_mass_kg;
}

double ServoDef::front_wheel_load_N(const CarSetup& setup, const TricycleDef& car) {
  const int n_front = car.wheels == 4 ? 2 : 1;
  const double front_kg = 0.5 * car.chassis_mass_kg + n_front * (car.wheel_mass_kg + car.knuckle_mass_kg);
  return setup.gravity_mps2 * front_kg / n_front;
}

ServoDef ServoDef::for_car(const CarSetup& setup, const TricycleDef& car) {
  ServoDef s;
  s.spin_torque_max_Nm = kGripMultiple * setup.mu * front_wheel_load_N(setup, car) * car.R_m;
  s.steer_torque_max_Nm = s.spin_torque_max_Nm;
  if (setup.rear_brake)
    s.rear_brake_torque_max_Nm = kGripMultiple * setup.mu * 0.5 * car_mass_kg(car) * setup.gravity_mps2 * car.R_m;
  return s;
}

namespace {

/// The car's momentum along the ground, N s, from the velocities the engine reports: the chassis's
/// centre of mass, every wheel's hub and every steering knuckle (centred on its wheel's hub), with
/// their declared masses. NaN where the engine reports no chassis velocity.
Eigen::Vector2d plane_momentum_Ns(const TricycleDef& d, const RigidCarState& s) {
  const int n_front = d.wheels == 4 ? 2 : 1, n_wheels = d.wheels == 4 ? 4 : 3;
  Eigen::Vector3d p = d.chassis_mass_kg * s.v_chassis_W;
  for (int w = 0; w < n_wheels; ++w)
    p += (d.wheel_mass_kg + (w < n_front ? d.knuckle_mass_kg : 0.0)) * s.wheels[w].v_hub_W;
  return p.head<2>();
}

/// The ground's load (GroundLoad), booked step by step from the engine's own contact forces:
/// the normal and in-plane force at rest, the normal force and the in-plane momentum balance over
/// the drive. An engine that reports no forces leaves every figure unmeasured; one that reports
/// them on some steps only, or reports a non-finite one, is an error, and so is a chassis velocity
/// reported at the drive's start and lost later (or the reverse).
class LoadBook {
 public:
  LoadBook(const TricycleDef& d, const CarSetup& setup)
      : def_(d), m_kg_(car_mass_kg(d)), cruise_mps_(setup.drive.speed_mps), g_plane_(setup.gravity_W().head<2>()) {
    load_.weight_normal_N = m_kg_ * -setup.gravity_W().z();
    load_.plane_weight_N = m_kg_ * g_plane_.norm();
  }
  /// One step of the rest window, ending at t_s.
  void rest(const std::optional<Eigen::Vector3d>& f_W, double t_s) {
    if (!book(f_W, t_s)) return;
    rest_sum_ += *f_W, ++rest_steps_;
  }
  /// The drive starts from state s.
  void start_drive(const RigidCarState& s) {
    p0_ = plane_momentum_Ns(def_, s);
    momentum_ = p0_.allFinite();
  }
  /// One step of the drive, dt long, ending at t_s in state s.
  void drive(const std::optional<Eigen::Vector3d>& f_W, const RigidCarState& s, double t_s, double dt_s) {
    if (!book(f_W, t_s)) return;
    drive_normal_sum_N_ += f_W->z(), ++drive_steps_;
    impulse_ += (f_W->head<2>() + m_kg_ * g_plane_) * dt_s;  // Newton II along the ground
    const Eigen::Vector2d p = plane_momentum_Ns(def_, s), dp = p - p0_;
    if (p.allFinite() != momentum_)
      throw EngineError(
          fmt::format("the engine reported the chassis velocity at the drive's start {} but {} at t = {:.4f} s",
                      momentum_ ? "finite" : "absent", momentum_ ? "absent or non-finite" : "finite", t_s));
    if (!momentum_) return;
    gap_ = std::max(gap_, (dp - impulse_).norm());
    change_ = std::max(change_, dp.norm());
  }
  GroundLoad finish(const std::string& absent_why) {
    if (given_ == 0) {
      load_.absent_why = absent_why;
      return load_;
    }
    if (rest_steps_ > 0) {
      load_.rest_normal_N = rest_sum_.z() / rest_steps_;
      load_.rest_hold_gap_N = (rest_sum_.head<2>() / rest_steps_ + m_kg_ * g_plane_).norm();
    }
    if (drive_steps_ > 0) load_.drive_normal_N = drive_normal_sum_N_ / drive_steps_;
    if (drive_steps_ > 0 && momentum_) {
      load_.momentum_gap_Ns = gap_, load_.momentum_change_Ns = change_;
      load_.momentum_scale_Ns = std::max(change_, GroundLoad::kCruiseShare * m_kg_ * cruise_mps_);
    }
    if (!momentum_)
      load_.momentum_absent_why = "the engine reports no chassis velocity (the protocol's optional v_chassis_W)";
    return load_;
  }

 private:
  /// True where the step's force is booked; an error where the report is partial or not finite.
  bool book(const std::optional<Eigen::Vector3d>& f_W, double t_s) {
    if (f_W && !f_W->allFinite())
      throw EngineError(
          fmt::format("the engine's contact report gave a non-finite force ({}, {}, {}) N at t = {:.4f} s", f_W->x(),
                      f_W->y(), f_W->z(), t_s));
    (f_W ? given_ : missing_) += 1;
    if (given_ > 0 && missing_ > 0)
      throw EngineError(
          fmt::format("the engine's contact report gave forces on some steps and none on others (t = {:.4f} s)", t_s));
    return f_W.has_value();
  }
  TricycleDef def_;
  double m_kg_, cruise_mps_;
  Eigen::Vector2d g_plane_;
  GroundLoad load_;
  long given_ = 0, missing_ = 0;
  bool momentum_ = false;
  Eigen::Vector3d rest_sum_ = Eigen::Vector3d::Zero();
  long rest_steps_ = 0, drive_steps_ = 0;
  double drive_normal_sum_N_ = 0.0, gap_ = 0.0, change_ = 0.0;
  Eigen::Vector2d p0_ = Eigen::Vector2d::Zero(), impulse_ = Eigen::Vector2d::Zero();
};

}  // namespace

void RigidCar::reset(const CarSetup& setup, const car::Config& q0) {
  reset_with(setup, q0, ServoDef::for_car(setup, TricycleDef::from(setup)));
}

void RigidCar::reset_with(const CarSetup& setup, const car::Config& q0, const ServoDef& servo) {
  setup_ = setup;
  def_ = TricycleDef::from(setup);
  servo_ = servo;
  if (def_.wheels == 4 && !four_wheels()) throw EngineError("this configuration builds only the tricycle (wheels=3)");
  q0_ = q0;
  build(setup_, def_, q0_);
}

std::vector<car::TimedConfig> RigidCar::drive(const car::BasePath& path) {
  const double dt = setup_.dt_s;
  const double T = path.duration_s();
  const long settle_steps = std::lround(servo_.settle_s / dt);
  const long steps = static_cast<long>(std::ceil((T + servo_.hold_s) / dt - 1e-9));
  const long sample_every = std::max(1L, std::lround(setup_.sample_dt_s / dt));
  const bool four = def_.wheels == 4;
  const int n_front = four ? 2 : 1, n_wheels = four ? 4 : 3;
  static const char* const kTricycle[3] = {"front", "rear left", "rear right"};
  static const char* const kFour[4] = {"front left", "front right", "rear left", "rear right"};
  const char* const* names = four ? kFour : kTricycle;
  const car::Side kSides[2] = {car::Side::kLeft, car::Side::kRight};

  RigidCarState s = read();
  // The realized virtual steering angle: the tricycle's one wheel, or for four wheels the mean of
  // the front wheels' cotangents (models/ackermann.hpp), exact for Ackermann and parallel wheels.
  const auto virtual_beta = [&](const RigidCarState& st) {
    return four ? car::virtual_steering_angle(st.steer_rad[0], st.steer_rad[1]) : st.steer_rad[0];
  };
  // Front wheel k rolls at rho_k times the front-axle centre (its turning radius over the
  // centre's; 1 for the tricycle): the electronic differential drives it so, and the tricycle's
  // wheel angle alpha of (3.3) advances by the mean of the wheels' increments over their rho_k.
  // (The plain average of the two wheel angles, Fecko's introduction, runs faster by
  // (rho_left + rho_right)/2 - 1, 6.2e-4 at beta = 0.3, w/l = 0.8.)
  const auto rho = [&](int k, double beta) {
    return four ? car::ackermann_drive_ratio(beta, def_.l_m, def_.track_m, kSides[k]) : 1.0;
  };
  double beta = virtual_beta(s);
  double alpha = 0.0;  // unwrapped wheel angle of the tricycle equivalent
  double prev_joint[2] = {s.spin_joint_rad[0], s.spin_joint_rad[1]};
  double prev_phi = s.phi_rad;
  double phi = q0_.phi_rad + e2::wrap_angle(s.phi_rad - q0_.phi_rad);  // unwrapped from the start heading
  std::vector<car::TimedConfig> trace;

  // A wheel hub faster than ten times the cruise speed (or 50 m/s) has blown up.
  const double runaway_mps = std::max(kRunawaySpeed_mps, kRunawayFactor * setup_.drive.speed_mps);
  // One step: servo towards (target_alpha, target_beta) with feed-forward rates, then read and check.
  // The targets are the command at the start of the step, the instant of the realized angles they
  // are compared with; the feed-forward is the command's rate at the step's middle, so the step
  // carries the angle from the command at its start to (to second order) the command at its end.
  const auto advance = [&](double t_end, double target_alpha, double target_beta, double alpha_rate, double beta_rate) {
    FrontRates rates;
    const double roll_radps = alpha_rate + servo_.spin_gain_per_s * (target_alpha - alpha);
    for (int k = 0; k < n_front; ++k) {
      // Four wheels: each front wheel's own steering target (its Ackermann angle, or beta itself
      // when steered in parallel), its feed-forward rate d(beta_k)/d(beta) x beta_rate.
      double target_k = target_beta, rate_k = beta_rate;
      if (four && !def_.parallel_steering) {
        target_k = car::ackermann_wheel_angle(target_beta, def_.l_m, def_.track_m, kSides[k]);
        rate_k = car::ackermann_steer_rate_factor(target_beta, def_.l_m, def_.track_m, kSides[k]) * beta_rate;
      }
      rates.steer_radps[k] = rate_k + servo_.steer_gain_per_s * (target_k - s.steer_rad[k]);
      rates.spin_radps[k] = rho(k, beta) * roll_radps;
    }
    actuate(rates, servo_);
    step(dt);
    stepped_s_ += dt;
    s = read();
    beta = virtual_beta(s);
    double d_alpha = 0.0;
    for (int k = 0; k < n_front; ++k) {
      d_alpha += e2::wrap_angle(s.spin_joint_rad[k] - prev_joint[k]) / rho(k, beta);
      prev_joint[k] = s.spin_joint_rad[k];
    }
    alpha += d_alpha / n_front;
    phi += e2::wrap_angle(s.phi_rad - prev_phi);
    prev_phi = s.phi_rad;
    const bool finite = std::isfinite(s.x_m) && std::isfinite(s.y_m) && std::isfinite(s.z_m) &&
                        std::isfinite(s.phi_rad) && std::isfinite(beta) && std::isfinite(alpha);
    if (!finite) throw EngineError(fmt::format("simulation produced NaN at t = {:.4f} s", t_end));
    for (int w = 0; w < n_wheels; ++w) {
      const double v = s.wheels[w].v_hub_W.norm();
      if (!(v <= runaway_mps))
        throw EngineError(fmt::format("{} wheel speed {:.3g} m/s at t = {:.4f} s (a blow-up: above {:g} m/s)", names[w],
                                      v, t_end, runaway_mps));
    }
    for (const auto& [which, z] : {std::pair{"front", s.z_m}, std::pair{"rear", s.rear_z_m}})
      if (std::abs(z - def_.R_m) > def_.R_m)
        throw EngineError(
            fmt::format("car left the ground ({} wheel centre at z = {:.3f} m, radius {:.3f} m) at t = {:.4f} s", which,
                        z, def_.R_m, t_end));
  };

  // The ground's load (the plane z = 0), from the engine's own contact report.
  LoadBook load(def_, setup_);
  const long rest_steps = std::min(settle_steps, std::lround(GroundLoad::kRestWindow_s / dt));

  // The steps go in runs of kPlanSteps, each run's targets told to the engine first (plan()).
  std::vector<ServoTarget> targets;
  const auto plan_from = [&](long k, long n, const auto& target_of) {
    targets.clear();
    for (long j = k; j < std::min(n, k + kPlanSteps); ++j) targets.push_back(target_of(j));
    plan(targets, alpha, s);
  };

  // Settle on the wheels: the contacts load up while the servos hold alpha = 0 and beta = beta0.
  const auto hold = [&](long) { return ServoTarget{0.0, q0_.beta_rad, 0.0, 0.0}; };
  for (long k = 0; k < settle_steps; ++k) {
    if (k % kPlanSteps == 0) plan_from(k, settle_steps, hold);
    const ServoTarget& g = targets[k % kPlanSteps];
    advance(-(settle_steps - k - 1) * dt, g.alpha_rad, g.beta_rad, g.alpha_rate_radps, g.beta_rate_radps);
    if (k >= settle_steps - rest_steps) load.rest(ground_force_W(), -(settle_steps - k - 1) * dt);
  }
  load.start_drive(s);
  alpha = 0.0;  // the drive starts at alpha = 0

  // Contact-point slip of each wheel, every step of the drive: the contact point of a sphere (or an
  // upright cylinder) on the ground z = 0 lies straight below the hub.
  slip_.assign(n_wheels, WheelSlip{});
  double sum_sq[4] = {0.0, 0.0, 0.0, 0.0}, roll_sum[4] = {0.0, 0.0, 0.0, 0.0};
  const auto book_slip = [&] {
    for (int w = 0; w < n_wheels; ++w) {
      const WheelState& ws = s.wheels[w];
      const Eigen::Vector3d v = ws.v_hub_W + ws.omega_W.cross(Eigen::Vector3d(0.0, 0.0, -ws.hub_z_m));
      Eigen::Vector3d axle(ws.axle_W.x(), ws.axle_W.y(), 0.0);
      axle.normalize();
      const Eigen::Vector3d roll = axle.cross(Eigen::Vector3d::UnitZ());
      slip_[w].along_max_mps = std::max(slip_[w].along_max_mps, std::abs(v.dot(roll)));
      slip_[w].across_max_mps = std::max(slip_[w].across_max_mps, std::abs(v.dot(axle)));
      sum_sq[w] += v.x() * v.x() + v.y() * v.y();
      roll_sum[w] += std::abs(ws.omega_W.dot(axle) * ws.hub_z_m);
    }
  };

  const auto sample = [&](double t) { trace.push_back({t, car::Config{alpha, beta, s.x_m, s.y_m, phi}}); };
  sample(0.0);
  // The command of the step from t0 = k dt: at its start, its rates at its middle.
  const auto command = [&](long k) {
    const double t0 = k * dt;
    const double ta = std::max(0.0, servo_instant_s(t0, false)), tb = std::max(0.0, servo_instant_s(t0, true));
    const car::BaseSample drive = path.at(ta), drive_mid = path.at(ta + 0.5 * dt);
    const car::BaseSample steer = tb == ta ? drive : path.at(tb),
                          steer_mid = tb == ta ? drive_mid : path.at(tb + 0.5 * dt);
    return ServoTarget{drive.alpha_rad, steer.beta_rad, drive_mid.alpha_rate_radps, steer_mid.beta_rate_radps};
  };
  for (long k = 0; k < steps; ++k) {
    const double t1 = (k + 1) * dt;
    if (k % kPlanSteps == 0) plan_from(k, steps, command);
    const ServoTarget& g = targets[k % kPlanSteps];
    advance(t1, g.alpha_rad, g.beta_rad, g.alpha_rate_radps, g.beta_rate_radps);
    book_slip();
    load.drive(ground_force_W(), s, t1, dt);
    if ((k + 1) % sample_every == 0 || k + 1 == steps) sample(t1);
  }
  for (int w = 0; w < n_wheels; ++w) {
    slip_[w].wheel = names[w];
    slip_[w].rms_mps = steps > 0 ? std::sqrt(sum_sq[w] / steps) : 0.0;
    slip_[w].roll_mean_mps = steps > 0 ? roll_sum[w] / steps : 0.0;
    slip_[w].along_measured = wheels_spin();
  }
  load_ = load.finish(ground_force_absent_why());
  return trace;
}

}  // namespace liftcheck
