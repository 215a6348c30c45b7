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

/// One drive: the servo's loop over the engine's steps, the wheel angle and heading it books, the
/// slip and the ground's load it measures.
class RigidCar::Drive {
 public:
  Drive(RigidCar& car, const car::BasePath& path);
  std::vector<car::TimedConfig> run();

 private:
  /// The realized virtual steering angle: the tricycle's one wheel, or for four wheels the mean of
  /// the front wheels' cotangents (models/ackermann.hpp), exact for Ackermann and parallel wheels.
  double virtual_beta(const RigidCarState& st) const {
    return four_ ? car::virtual_steering_angle(st.steer_rad[0], st.steer_rad[1]) : st.steer_rad[0];
  }
  /// Front wheel k rolls at rho_k times the front-axle centre (its turning radius over the
  /// centre's; 1 for the tricycle): the electronic differential drives it so, and the tricycle's
  /// wheel angle alpha of (3.3) advances by the mean of the wheels' increments over their rho_k.
  /// (The plain average of the two wheel angles, Fecko's introduction, runs faster by
  /// (rho_left + rho_right)/2 - 1, 6.2e-4 at beta = 0.3, w/l = 0.8.)
  double rho(int k, double beta) const {
    return four_ ? car::ackermann_drive_ratio(beta, car_.def_.l_m, car_.def_.track_m, kSides[k]) : 1.0;
  }
  FrontRates rates_for(const ServoTarget& g) const;
  void advance(double t_end, const ServoTarget& g);
  void book_angles();
  void check(double t_end) const;
  template <class TargetOf>
  void plan_from(long k, long n, const TargetOf& target_of);
  void settle();
  ServoTarget command(long k) const;
  void book_slip();
  void sample(double t) { trace_.push_back({t, car::Config{alpha_, beta_, s_.x_m, s_.y_m, phi_}}); }

  static constexpr car::Side kSides[2] = {car::Side::kLeft, car::Side::kRight};
  static constexpr const char* kTricycle[3] = {"front", "rear left", "rear right"};
  static constexpr const char* kFour[4] = {"front left", "front right", "rear left", "rear right"};

  RigidCar& car_;
  const car::BasePath& path_;
  const double dt_;
  const bool four_;
  const int n_front_, n_wheels_;
  const char* const* names_;
  /// A wheel hub faster than ten times the cruise speed (or 50 m/s) has blown up.
  const double runaway_mps_;
  RigidCarState s_;
  double beta_, alpha_ = 0.0;  ///< alpha: the unwrapped wheel angle of the tricycle equivalent
  double prev_joint_[2];
  double prev_phi_, phi_;  ///< phi unwrapped from the start heading
  std::vector<car::TimedConfig> trace_;
  LoadBook load_;                     ///< the ground's load (the plane z = 0), from the engine's own contact report
  std::vector<ServoTarget> targets_;  ///< the planned run of steps (kPlanSteps)
  double sum_sq_[4] = {0.0, 0.0, 0.0, 0.0}, roll_sum_[4] = {0.0, 0.0, 0.0, 0.0};
};

RigidCar::Drive::Drive(RigidCar& car, const car::BasePath& path)
    : car_(car),
      path_(path),
      dt_(car.setup_.dt_s),
      four_(car.def_.wheels == 4),
      n_front_(four_ ? 2 : 1),
      n_wheels_(four_ ? 4 : 3),
      names_(four_ ? kFour : kTricycle),
      runaway_mps_(std::max(kRunawaySpeed_mps, kRunawayFactor * car.setup_.drive.speed_mps)),
      s_(car.read()),
      beta_(virtual_beta(s_)),
      prev_joint_{s_.spin_joint_rad[0], s_.spin_joint_rad[1]},
      prev_phi_(s_.phi_rad),
      phi_(car.q0_.phi_rad + e2::wrap_angle(s_.phi_rad - car.q0_.phi_rad)),
      load_(car.def_, car.setup_) {}

/// The servo's rates towards the step's targets, with feed-forward rates.
FrontRates RigidCar::Drive::rates_for(const ServoTarget& g) const {
  const ServoDef& servo = car_.servo_;
  const TricycleDef& def = car_.def_;
  FrontRates rates;
  const double roll_radps = g.alpha_rate_radps + servo.spin_gain_per_s * (g.alpha_rad - alpha_);
  for (int k = 0; k < n_front_; ++k) {
    // Four wheels: each front wheel's own steering target (its Ackermann angle, or beta itself
    // when steered in parallel), its feed-forward rate d(beta_k)/d(beta) x beta_rate.
    double target_k = g.beta_rad, rate_k = g.beta_rate_radps;
    if (four_ && !def.parallel_steering) {
      target_k = car::ackermann_wheel_angle(g.beta_rad, def.l_m, def.track_m, kSides[k]);
      rate_k = car::ackermann_steer_rate_factor(g.beta_rad, def.l_m, def.track_m, kSides[k]) * g.beta_rate_radps;
    }
    rates.steer_radps[k] = rate_k + servo.steer_gain_per_s * (target_k - s_.steer_rad[k]);
    rates.spin_radps[k] = rho(k, beta_) * roll_radps;
  }
  return rates;
}

/// One step: servo towards the targets with feed-forward rates, then read and check. The targets
/// are the command at the start of the step, the instant of the realized angles they are compared
/// with; the feed-forward is the command's rate at the step's middle, so the step carries the angle
/// from the command at its start to (to second order) the command at its end.
void RigidCar::Drive::advance(double t_end, const ServoTarget& g) {
  car_.actuate(rates_for(g), car_.servo_);
  car_.step(dt_);
  car_.stepped_s_ += dt_;
  s_ = car_.read();
  book_angles();
  check(t_end);
}

/// The realized steering angle, the wheel angle's increment and the heading's, from the state read.
void RigidCar::Drive::book_angles() {
  beta_ = virtual_beta(s_);
  double d_alpha = 0.0;
  for (int k = 0; k < n_front_; ++k) {
    d_alpha += e2::wrap_angle(s_.spin_joint_rad[k] - prev_joint_[k]) / rho(k, beta_);
    prev_joint_[k] = s_.spin_joint_rad[k];
  }
  alpha_ += d_alpha / n_front_;
  phi_ += e2::wrap_angle(s_.phi_rad - prev_phi_);
  prev_phi_ = s_.phi_rad;
}

/// A blow-up (a NaN, a runaway wheel) or a car off the ground ends the drive with an error.
void RigidCar::Drive::check(double t_end) const {
  const bool finite = std::isfinite(s_.x_m) && std::isfinite(s_.y_m) && std::isfinite(s_.z_m) &&
                      std::isfinite(s_.phi_rad) && std::isfinite(beta_) && std::isfinite(alpha_);
  if (!finite) throw EngineError(fmt::format("simulation produced NaN at t = {:.4f} s", t_end));
  for (int w = 0; w < n_wheels_; ++w) {
    const double v = s_.wheels[w].v_hub_W.norm();
    if (!(v <= runaway_mps_))
      throw EngineError(fmt::format("{} wheel speed {:.3g} m/s at t = {:.4f} s (a blow-up: above {:g} m/s)", names_[w],
                                    v, t_end, runaway_mps_));
  }
  const double R = car_.def_.R_m;
  for (const auto& [which, z] : {std::pair{"front", s_.z_m}, std::pair{"rear", s_.rear_z_m}})
    if (std::abs(z - R) > R)
      throw EngineError(
          fmt::format("car left the ground ({} wheel centre at z = {:.3f} m, radius {:.3f} m) at t = {:.4f} s", which,
                      z, R, t_end));
}

/// The steps go in runs of kPlanSteps, each run's targets told to the engine first (plan()).
template <class TargetOf>
void RigidCar::Drive::plan_from(long k, long n, const TargetOf& target_of) {
  targets_.clear();
  for (long j = k; j < std::min(n, k + kPlanSteps); ++j) targets_.push_back(target_of(j));
  car_.plan(targets_, alpha_, s_);
}

/// Settle on the wheels: the contacts load up while the servos hold alpha = 0 and beta = beta0.
void RigidCar::Drive::settle() {
  const long settle_steps = std::lround(car_.servo_.settle_s / dt_);
  const long rest_steps = std::min(settle_steps, std::lround(GroundLoad::kRestWindow_s / dt_));
  const auto hold = [&](long) { return ServoTarget{0.0, car_.q0_.beta_rad, 0.0, 0.0}; };
  for (long k = 0; k < settle_steps; ++k) {
    if (k % kPlanSteps == 0) plan_from(k, settle_steps, hold);
    advance(-(settle_steps - k - 1) * dt_, targets_[k % kPlanSteps]);
    if (k >= settle_steps - rest_steps) load_.rest(car_.ground_force_W(), -(settle_steps - k - 1) * dt_);
  }
  load_.start_drive(s_);
  alpha_ = 0.0;  // the drive starts at alpha = 0
}

/// The command of the step from t0 = k dt: at its start, its rates at its middle.
ServoTarget RigidCar::Drive::command(long k) const {
  const double t0 = k * dt_;
  const double ta = std::max(0.0, car_.servo_instant_s(t0, false)), tb = std::max(0.0, car_.servo_instant_s(t0, true));
  const car::BaseSample drive = path_.at(ta), drive_mid = path_.at(ta + 0.5 * dt_);
  const car::BaseSample steer = tb == ta ? drive : path_.at(tb),
                        steer_mid = tb == ta ? drive_mid : path_.at(tb + 0.5 * dt_);
  return ServoTarget{drive.alpha_rad, steer.beta_rad, drive_mid.alpha_rate_radps, steer_mid.beta_rate_radps};
}

/// Contact-point slip of each wheel, every step of the drive: the contact point of a sphere (or an
/// upright cylinder) on the ground z = 0 lies straight below the hub.
void RigidCar::Drive::book_slip() {
  std::vector<WheelSlip>& slip = car_.slip_;
  for (int w = 0; w < n_wheels_; ++w) {
    const WheelState& ws = s_.wheels[w];
    const Eigen::Vector3d v = ws.v_hub_W + ws.omega_W.cross(Eigen::Vector3d(0.0, 0.0, -ws.hub_z_m));
    Eigen::Vector3d axle(ws.axle_W.x(), ws.axle_W.y(), 0.0);
    axle.normalize();
    const Eigen::Vector3d roll = axle.cross(Eigen::Vector3d::UnitZ());
    slip[w].along_max_mps = std::max(slip[w].along_max_mps, std::abs(v.dot(roll)));
    slip[w].across_max_mps = std::max(slip[w].across_max_mps, std::abs(v.dot(axle)));
    sum_sq_[w] += v.x() * v.x() + v.y() * v.y();
    roll_sum_[w] += std::abs(ws.omega_W.dot(axle) * ws.hub_z_m);
  }
}

std::vector<car::TimedConfig> RigidCar::Drive::run() {
  const long steps = static_cast<long>(std::ceil((path_.duration_s() + car_.servo_.hold_s) / dt_ - 1e-9));
  const long sample_every = std::max(1L, std::lround(car_.setup_.sample_dt_s / dt_));
  settle();
  car_.slip_.assign(n_wheels_, WheelSlip{});
  sample(0.0);
  for (long k = 0; k < steps; ++k) {
    const double t1 = (k + 1) * dt_;
    if (k % kPlanSteps == 0) plan_from(k, steps, [&](long j) { return command(j); });
    advance(t1, targets_[k % kPlanSteps]);
    book_slip();
    load_.drive(car_.ground_force_W(), s_, t1, dt_);
    if ((k + 1) % sample_every == 0 || k + 1 == steps) sample(t1);
  }
  for (int w = 0; w < n_wheels_; ++w) {
    WheelSlip& slip = car_.slip_[w];
    slip.wheel = names_[w];
    slip.rms_mps = steps > 0 ? std::sqrt(sum_sq_[w] / steps) : 0.0;
    slip.roll_mean_mps = steps > 0 ? roll_sum_[w] / steps : 0.0;
    slip.along_measured = car_.wheels_spin();
  }
  car_.load_ = load_.finish(car_.ground_force_absent_why());
  return trace_;
}

std::vector<car::TimedConfig> RigidCar::drive(const car::BasePath& path) { return Drive(*this, path).run(); }

}  // namespace liftcheck
