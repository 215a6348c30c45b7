// Simbody's side of the Simbody engine: the car and the disks on Simbody's own bodies, mobilizers,
// compliant contact and integrators. Simbody 3.7's headers do not compile as C++20 (ambiguous
// comparison operators in ContactGeometry.h), so this interface carries plain numbers only and its
// implementation (simbody_sim.cpp) is built as C++17 in a target of its own; simbody_engine.cpp
// puts it behind RigidCar and DrivenDisks.
#pragma once

#include <cmath>
#include <memory>
#include <string>

#include <Eigen/Dense>

namespace liftcheck::simbody {

/// Compliant contact (SimTK::ContactMaterial on every contact surface, Hunt-Crossley with
/// Simbody's Stribeck-like friction law) and the integrator that advances between two steps.
struct ContactDef {
  double stiffness_Pa = 1e8;              ///< plane-strain modulus of each surface (Hertz)
  double dissipation_s_per_m = 100.0;     ///< Hunt-Crossley dissipation
  double transition_velocity_mps = 0.01;  ///< CompliantContactSubsystem::setTransitionVelocity
};
struct IntegratorDef {
  std::string method = "semi_explicit_euler2";  ///< or "rk_merson", "rk3"
  double accuracy = 1e-3;                       ///< Integrator::setAccuracy (relative)
};

/// The tricycle (TricycleDef's chassis frame: origin at the front-axle centre, x forward, z up).
struct CarDef {
  double R_m, l_m, track_m, chassis_height_m;
  double chassis_mass_kg, wheel_mass_kg, knuckle_mass_kg, knuckle_inertia_kgm2;
  double mu;
  Eigen::Vector3d gravity_W_mps2;
  double x0_m, y0_m, phi0_rad, beta0_rad;
  ContactDef contact;
  IntegratorDef integrator;
  /// The rear wheels held: each rear Pin's speed prescribed at 0 (Motion::Steady, as the servos).
  bool rear_brake = false;
};

struct WheelOut {
  Eigen::Vector3d v_hub_W, omega_W, axle_W;
  double hub_z_m;
};
struct CarOut {
  double spin_joint_rad, steer_rad;
  Eigen::Vector3d front_W;  ///< front wheel centre
  double phi_rad, rear_z_m;
  WheelOut wheels[3];  ///< front, rear left, rear right
};

/// Per step: the servos' commanded rates, then the integrator advanced to the step's end.
class CarSim {
 public:
  explicit CarSim(const CarDef& def);
  ~CarSim();
  /// The spin and steering joints' speeds over the next step: Motion::Steady, Simbody's prescribed
  /// motion, written into the state (System::prescribeU). The torque it takes is not limited; the
  /// default suite's peak is 39 N m of the other engines' 106 N m limit (docs/adapters-simbody.md).
  void command(double spin_radps, double steer_radps);
  void step(double dt_s);
  CarOut read() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

/// Two spheres of radius_m, no gravity: M on a Translation mobilizer (it cannot turn), its velocity
/// set each step; N on a Translation mobilizer whose rates a Motion::Steady prescribes.
struct DisksDef {
  double radius_m, mass_kg, mu_MN;
  Eigen::Vector2d cM0_m, cN0_m;
  ContactDef contact;
  IntegratorDef integrator;
};
struct DisksContacts {
  int count = 0;
  double depth_max_m = 0.0;
  /// NaN where the contacts touch at the step's start. Where none did and the tracker reports one
  /// at the step's end (the compliant force acts from the instant within the step the spheres
  /// meet), the separation at the step's start, both positions Simbody's: what the engine protocol
  /// calls a speculative contact (made while the shapes were apart), judged as one, so that the
  /// verdict is the same compiled in and over `liftcheck serve`.
  double distance_min_m = NAN;
};
class DisksSim {
 public:
  explicit DisksSim(const DisksDef& def);
  ~DisksSim();
  /// Sets M's velocity and N's, then advances dt; the contacts are those of the step's start, or
  /// the one the step entered (DisksContacts::distance_min_m).
  DisksContacts step(const Eigen::Vector2d& vM_mps, const Eigen::Vector2d& vN_mps, double dt_s);
  Eigen::Vector2d cM() const;
  Eigen::Vector2d cN() const;
  Eigen::Vector3d wM_radps() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace liftcheck::simbody
