// What the Bullet and ODE cars share: the tricycle's dimensions, the servo that makes the wheel
// angle and steering follow the commanded base path, and the stepping loop that samples the
// realized (alpha, beta, x, y, phi). Each engine implements only build, actuate, step and read.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Dense>

#include "engines/engine.hpp"

namespace liftcheck {

/// The tricycle of the paper as rigid bodies (all lengths in m, masses in kg), or the four-wheel
/// car behind it. Chassis frame: x forward along the tie rod, y left, z up; origin at the
/// front-axle centre.
struct TricycleDef {
  double R_m = 0.3;      ///< front and rear wheel radius
  double l_m = 1.0;      ///< tie rod: rear-axle centre to front-axle centre
  double track_m = 0.8;  ///< distance between the two rear wheels (and the two front wheels of a four-wheel car)
  int wheels = 3;        ///< 3: one front wheel at the front-axle centre; 4: front wheels at (0, +-track/2)
  bool parallel_steering = false;  ///< four wheels: both front wheels at beta instead of their Ackermann angles
  double wheel_width_m = 0.09;     ///< cylinder wheels only
  double chassis_mass_kg = 40.0;
  double wheel_mass_kg = 2.0;
  /// Each steering knuckle: the body the steering joint turns and the spin joint carries the
  /// wheel on. Its inertia is isotropic, with the squared radius of gyration below (a 7 cm solid
  /// sphere; the 0.05 kg knuckle liftcheck built before it was a parameter had 1e-4 kg m^2).
  double knuckle_mass_kg = 2.0;
  static constexpr double kKnuckleGyrationSq_m2 = 2e-3;
  double knuckle_inertia_kgm2() const { return knuckle_mass_kg * kKnuckleGyrationSq_m2; }
  double chassis_height_m = 0.1;  ///< box thickness (the chassis does not collide)

  static TricycleDef from(const CarSetup& setup);
};

/// The car's whole mass as declared, kg: chassis, every wheel, every steering knuckle.
double car_mass_kg(const TricycleDef& car);

/// Servo gains: rate command = commanded rate + gain * (commanded angle - realized angle).
/// Before t = 0 the car settles on its wheels with the servos holding alpha and beta; after the
/// path's end it holds still a little longer, so the servos finish converging.
struct ServoDef {
  double settle_s = 0.5;
  double hold_s = 0.2;
  double spin_gain_per_s = 40.0;
  double steer_gain_per_s = 40.0;
  double spin_torque_max_Nm = 0.0;  ///< for_car: kGripMultiple x mu N R of a driven wheel
  double steer_torque_max_Nm =
      0.0;  ///< for_car: the same limit (a convention: a sphere wheel's scrub torque is far below it)
  /// Above 0 (CarSetup::rear_brake): each rear wheel held at zero spin rate against the chassis by
  /// the engine's own joint motor, up to this torque (for_car: kGripMultiple x mu x half the car's
  /// weight x R, past what a rear wheel's grip can ask however the load shifts).
  double rear_brake_torque_max_Nm = 0.0;
  /// A real drive is sized to its grip: the motor can lock its wheel against the full Coulomb
  /// torque mu N R with half as much again to spare, and can never overpower the grip by more.
  /// (A 500 N m limit, seven times the grip of the default car's front wheel, let the motor spin
  /// the wheel against friction an iterative solver had not yet converged at the start of a drive.)
  static constexpr double kGripMultiple = 1.5;
  /// The static normal load on each driven (front) wheel, N: half the chassis (a box from the rear
  /// to the front axle, its centre of mass at l/2) and the front wheels with their knuckles, shared
  /// by the front wheels.
  static double front_wheel_load_N(const CarSetup& setup, const TricycleDef& car);
  /// The servo of `setup`'s car: the gains above, both torque limits kGripMultiple x mu N R (for
  /// the default car, mu = 1: 1.5 x 235 N x 0.3 m = 106 N m).
  static ServoDef for_car(const CarSetup& setup, const TricycleDef& car);
};

/// Rates for the steered and driven front wheels: index 0 is the tricycle's one front wheel or the
/// four-wheel car's left one, index 1 its right one.
struct FrontRates {
  double spin_radps[2] = {0.0, 0.0};   ///< about the axle, positive rolls forward
  double steer_radps[2] = {0.0, 0.0};  ///< steering, left positive
};

/// What the servo aims at during one step (RigidCar::drive): the command at the step's start and
/// its rates at the step's middle.
struct ServoTarget {
  double alpha_rad = 0.0;         ///< the tricycle-equivalent wheel angle commanded
  double beta_rad = 0.0;          ///< the (virtual) steering angle commanded
  double alpha_rate_radps = 0.0;  ///< feed-forward rolling rate
  double beta_rate_radps = 0.0;   ///< feed-forward steering rate
};

/// One wheel's body state in world coordinates.
struct WheelState {
  Eigen::Vector3d v_hub_W;  ///< linear velocity of the wheel centre, m/s
  Eigen::Vector3d omega_W;  ///< angular velocity, rad/s
  Eigen::Vector3d axle_W;   ///< the axle direction (unit)
  double hub_z_m = 0.0;     ///< height of the wheel centre above the ground
};

/// The realized state an engine reads off its bodies and joints. Front wheel k is the tricycle's
/// one front wheel (k = 0) or the four-wheel car's left (0) and right (1) front wheels.
struct RigidCarState {
  double spin_joint_rad[2];  ///< front wheel k's angle about its axle relative to its steering knuckle, wrapped
  double steer_rad[2];  ///< front wheel k's steering angle against the tie rod, left positive (start offset applied)
  double x_m, y_m;      ///< front-axle centre (the front wheel centre; the midpoint of the two for four wheels)
  double z_m;           ///< lowest front wheel centre height (for blow-up detection)
  double phi_rad;       ///< chassis heading
  double rear_z_m;      ///< lowest rear wheel centre height
  /// Tricycle: front, rear left, rear right; four wheels: front left, front right, rear left, rear right.
  WheelState wheels[4];
  /// The chassis body's centre-of-mass velocity, world frame, m/s, as the engine reports it (NaN
  /// where it gives none): with the hubs', the car's momentum that momentum_balance books.
  Eigen::Vector3d v_chassis_W = Eigen::Vector3d::Constant(NAN);
};

class RigidCar : public CarEngine {
  friend class ProtocolServer;  // `liftcheck serve`: these hooks over the engine protocol

 public:
  /// drive() tells the engine the targets of this many steps at a time (plan()).
  static constexpr long kPlanSteps = 32;
  explicit RigidCar(Settings settings) : settings_(std::move(settings)) {}
  void reset(const CarSetup& setup, const car::Config& q0) final;
  std::vector<car::TimedConfig> drive(const car::BasePath& path) final;
  std::vector<WheelSlip> slip() const final { return slip_; }
  double simulated_s() const final { return stepped_s_; }
  GroundLoad ground_load() const final { return load_; }

 protected:
  /// reset with the motors' limits given (`liftcheck serve`: the request's, which an engine that
  /// builds its limits into the model, as MuJoCo does, must have before it builds).
  void reset_with(const CarSetup& setup, const car::Config& q0, const ServoDef& servo);
  /// Builds the world with the car at q0 (steering at q0.beta), at rest on the ground.
  virtual void build(const CarSetup& setup, const TricycleDef& car, const car::Config& q0) = 0;
  /// Sets each front wheel's spin rate about its axle (positive rolls forward) and steering rate.
  virtual void actuate(const FrontRates& rates, const ServoDef& servo) = 0;
  virtual void step(double dt_s) = 0;
  /// True where build() makes the four-wheel car (TricycleDef::wheels = 4).
  virtual bool four_wheels() const { return false; }
  virtual RigidCarState read() const = 0;
  /// False where a wheel has no spin state of its own (WheelSlip::along_measured).
  virtual bool wheels_spin() const { return true; }
  /// The force the ground exerted on the wheels during the last step, world frame, N: the sum of
  /// the engine's own wheel-ground contact forces as its contact report gives them. Empty where the
  /// engine reports none (then ground_force_absent_why says why).
  virtual std::optional<Eigen::Vector3d> ground_force_W() const { return std::nullopt; }
  virtual std::string ground_force_absent_why() const {
    return "liftcheck does not yet read this engine's contact forces";
  }
  /// The instant whose command the servo aims the steering (`steering`) or the drive at during the
  /// step from t_s: t_s itself. Only the fault-injection suite shifts it (a servo a step early or late).
  virtual double servo_instant_s(double t_s, bool /*steering*/) const { return t_s; }
  /// The targets of the steps about to be taken, one per step, before drive() actuates and steps
  /// them one by one; `alpha_rad` is the servo's wheel angle and `now` the state they start from.
  /// An engine over the protocol may then step them in one exchange, its adapter applying the
  /// servo's law (docs/protocol.md, "steps"); its step() checks each rate applied. Default: nothing.
  virtual void plan(const std::vector<ServoTarget>& /*next*/, double /*alpha_rad*/, const RigidCarState& /*now*/) {}

  /// The engine's knob values, typed (declared in its EngineInfo; resolved by resolve_settings).
  Settings settings_;
  CarSetup setup_;
  TricycleDef def_;
  ServoDef servo_;
  car::Config q0_;
  std::vector<WheelSlip> slip_;
  GroundLoad load_;
  double stepped_s_ = 0.0;

 private:
  class Drive;  ///< drive()'s loop and its state (rigid_car.cpp)
};

}  // namespace liftcheck
