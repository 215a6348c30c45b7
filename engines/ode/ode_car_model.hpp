// The tricycle in ODE as a class, for the engine registry and for tests that derive from it
// (tests/faults). See ode_car.cpp for the model.
#pragma once

#include <ode/ode.h>

#include <array>
#include <cmath>
#include <memory>

#include "engines/ode/ode_car.hpp"
#include "engines/rigid_car.hpp"
#include "models/ackermann.hpp"

namespace liftcheck {

/// The ODE car's knobs, typed once when the car is made.
struct OdeCarKnobs {
  bool cylinder = false;                       ///< wheel: cylinders instead of spheres
  double soft_erp = kContactSoftErp;           ///< contact_erp (ode-quick has none: ODE's default)
  double soft_cfm = kContactSoftCfm_m_per_Ns;  ///< contact_cfm
  bool wheel_dirs = true;                      ///< friction_dirs: dContactFDir1 along the rolling direction
  static OdeCarKnobs from(const Settings& s) {
    return {.cylinder = s.choice("wheel") == "cylinder",
            .soft_erp = s.has("contact_erp") ? s.number("contact_erp") : kContactSoftErp,
            .soft_cfm = s.number("contact_cfm"),
            .wheel_dirs = s.choice("friction_dirs") == "wheel"};
  }
};

class OdeCar : public RigidCar {
  friend class OdeRawCar;  // the benchmarks' raw loop on these bodies (ode_raw.cpp)

 public:
  explicit OdeCar(Settings settings, const OdeStepper& stepper = {})
      : RigidCar(std::move(settings)), stepper_(stepper), knobs_(OdeCarKnobs::from(settings_)) {}
  ~OdeCar() override { destroy(); }

 protected:
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    destroy();
    sim_ = std::make_unique<OdeWorld>(stepper_, setup.gravity_W());
    world_ = sim_->id();
    space_ = dSimpleSpaceCreate(nullptr);
    contacts_ = dJointGroupCreate(0);
    ground_ = dCreatePlane(space_, 0, 0, 1, 0);

    const double c = std::cos(q0.phi_rad), s = std::sin(q0.phi_rad);
    const auto to_world = [&](double bx, double by, double bz) {
      return std::array<double, 3>{q0.x_m + c * bx - s * by, q0.y_m + s * bx + c * by, bz};
    };
    dMatrix3 R_chassis;
    dRFromAxisAndAngle(R_chassis, 0, 0, 1, q0.phi_rad);

    // Chassis: a box from the rear axle to the front axle, at axle height.
    chassis_ = dBodyCreate(world_);
    dMass m;
    dMassSetBoxTotal(&m, d.chassis_mass_kg, d.l_m, d.track_m, d.chassis_height_m);
    dBodySetMass(chassis_, &m);
    const auto cc = to_world(-0.5 * d.l_m, 0.0, d.R_m);
    // ODE puts the centre of mass at the body origin: the chassis origin is the box centre.
    dBodySetPosition(chassis_, cc[0], cc[1], cc[2]);
    dBodySetRotation(chassis_, R_chassis);

    const auto make_wheel = [&](const std::array<double, 3>& p, double yaw, bool steered) {
      dBodyID b = dBodyCreate(world_);
      dMass wm;
      dGeomID g;
      dMatrix3 Rw;
      if (knobs_.cylinder) {
        dMassSetCylinderTotal(&wm, d.wheel_mass_kg, 3, d.R_m, d.wheel_width_m);  // along local z
        g = dCreateCylinder(space_, d.R_m, d.wheel_width_m);
        // Local z along the axle: rotate +90 deg about x (z -> -y), then yaw.
        dMatrix3 Rx, Rz;
        dRFromAxisAndAngle(Rx, 1, 0, 0, M_PI / 2);
        dRFromAxisAndAngle(Rz, 0, 0, 1, yaw);
        dMultiply0(Rw, Rz, Rx, 3, 3, 3);
      } else {
        dMassSetSphereTotal(&wm, d.wheel_mass_kg, d.R_m);
        g = dCreateSphere(space_, d.R_m);
        dRFromAxisAndAngle(Rw, 0, 0, 1, yaw);
      }
      if (steered) {
        // No knuckle body: the hinge-2 joint steers the wheel body itself, so the knuckle's mass
        // rides on it (at the wheel centre, its inertia isotropic: a solid sphere with the
        // knuckle's radius of gyration).
        dMass km;
        dMassSetSphereTotal(&km, d.knuckle_mass_kg, std::sqrt(d.kKnuckleGyrationSq_m2 / 0.4));
        dMassAdd(&wm, &km);
      }
      dBodySetMass(b, &wm);
      dBodySetPosition(b, p[0], p[1], p[2]);
      dBodySetRotation(b, Rw);
      dGeomSetBody(g, b);
      return b;
    };
    // Front wheels: the tricycle's one at the front-axle centre, or a four-wheel car's two at
    // (0, +-track/2), each at its Ackermann angle for beta0 (or at beta0 itself, steered in parallel).
    n_front_ = d.wheels == 4 ? 2 : 1;
    front_[1] = nullptr;
    steer_joint_[1] = nullptr;
    for (int k = 0; k < n_front_; ++k) {
      const double y_k = n_front_ == 1 ? 0.0 : (k == 0 ? 0.5 : -0.5) * d.track_m;
      beta0_[k] = q0.beta_rad;
      if (n_front_ == 2 && !d.parallel_steering)
        beta0_[k] =
            car::ackermann_wheel_angle(q0.beta_rad, d.l_m, d.track_m, k == 0 ? car::Side::kLeft : car::Side::kRight);
      const double steer_yaw = q0.phi_rad + beta0_[k];
      const auto p = to_world(0.0, y_k, d.R_m);
      front_[k] = make_wheel(p, steer_yaw, true);
      // Hinge-2: axis 1 vertical (steering), axis 2 the axle (left of the wheel).
      steer_joint_[k] = dJointCreateHinge2(world_, nullptr);
      dJointAttach(steer_joint_[k], chassis_, front_[k]);
      dJointSetHinge2Anchor(steer_joint_[k], p[0], p[1], p[2]);
      const dReal z_axis[3] = {0, 0, 1};
      const dReal axle[3] = {-std::sin(steer_yaw), std::cos(steer_yaw), 0};
      dJointSetHinge2Axes(steer_joint_[k], z_axis, axle);
      dJointSetHinge2Param(steer_joint_[k], dParamSuspensionERP, 0.2);
      dJointSetHinge2Param(steer_joint_[k], dParamSuspensionCFM, 1e-10);  // rigid: no suspension
    }
    rear_[0] = make_wheel(to_world(-d.l_m, 0.5 * d.track_m, d.R_m), q0.phi_rad, false);
    rear_[1] = make_wheel(to_world(-d.l_m, -0.5 * d.track_m, d.R_m), q0.phi_rad, false);

    // Rear: plain hinges about the rear axle.
    for (int i = 0; i < 2; ++i) {
      rear_joint_[i] = dJointCreateHinge(world_, nullptr);
      dJointAttach(rear_joint_[i], chassis_, rear_[i]);
      const dReal* p = dBodyGetPosition(rear_[i]);
      dJointSetHingeAnchor(rear_joint_[i], p[0], p[1], p[2]);
      dJointSetHingeAxis(rear_joint_[i], -s, c, 0);
    }
    mu_ = setup.mu;
    soft_erp_ = knobs_.soft_erp;
    soft_cfm_ = knobs_.soft_cfm;
    wheel_dirs_ = knobs_.wheel_dirs;
  }

  bool four_wheels() const override { return true; }

  void actuate(const FrontRates& rates, const ServoDef& servo) override {
    for (int k = 0; k < n_front_; ++k) {
      // Body 1 relative to body 2: both rates are negated.
      dJointSetHinge2Param(steer_joint_[k], dParamVel, -rates.steer_radps[k]);
      dJointSetHinge2Param(steer_joint_[k], dParamFMax, servo.steer_torque_max_Nm);
      dJointSetHinge2Param(steer_joint_[k], dParamVel2, -rates.spin_radps[k]);
      dJointSetHinge2Param(steer_joint_[k], dParamFMax2, servo.spin_torque_max_Nm);
    }
    // The brake: each rear hinge's motor at zero speed, up to its torque (0: ODE's default, no motor).
    for (dJointID rear : rear_joint_) {
      dJointSetHingeParam(rear, dParamVel, 0.0);
      dJointSetHingeParam(rear, dParamFMax, servo.rear_brake_torque_max_Nm);
    }
  }

  void step(double dt_s) override {
    n_feedback_ = 0;
    dSpaceCollide(space_, this, &OdeCar::near_callback);
    sim_->step(dt_s);
    // Each contact joint's feedback (dJointSetFeedback): f1, the force on the joint's first body,
    // which is always the wheel: dJointAttach moves the ground's null body to the second place
    // (and the stepper writes f2 only for a second body that exists).
    ground_force_W_.setZero();
    for (int i = 0; i < n_feedback_; ++i)
      ground_force_W_ += Eigen::Vector3d(feedback_[i].f1[0], feedback_[i].f1[1], feedback_[i].f1[2]);
    dJointGroupEmpty(contacts_);
  }

  std::optional<Eigen::Vector3d> ground_force_W() const override { return ground_force_W_; }

  RigidCarState read() const override {
    const dReal* Rc = dBodyGetRotation(chassis_);  // row-major 3x4
    RigidCarState s{};
    s.x_m = s.y_m = 0.0;
    s.z_m = INFINITY;
    for (int k = 0; k < n_front_; ++k) {
      const dReal* p = dBodyGetPosition(front_[k]);
      s.spin_joint_rad[k] = dJointGetHinge2Angle2(steer_joint_[k]);
      s.steer_rad[k] = beta0_[k] - dJointGetHinge2Angle1(steer_joint_[k]);
      s.x_m += p[0] / n_front_;  // the front-axle centre: the midpoint of the front wheel centres
      s.y_m += p[1] / n_front_;
      s.z_m = std::min<double>(s.z_m, p[2]);
    }
    s.phi_rad = std::atan2(Rc[4], Rc[0]);  // chassis x axis in the world: (R00, R10)
    s.rear_z_m = std::min(dBodyGetPosition(rear_[0])[2], dBodyGetPosition(rear_[1])[2]);
    const dBodyID bodies[4] = {front_[0], n_front_ == 2 ? front_[1] : rear_[0], n_front_ == 2 ? rear_[0] : rear_[1],
                               rear_[1]};
    for (int w = 0; w < n_front_ + 2; ++w) {
      const dReal* v = dBodyGetLinearVel(bodies[w]);
      const dReal* o = dBodyGetAngularVel(bodies[w]);
      dVector3 axle;
      if (w < n_front_)
        dJointGetHinge2Axis2(steer_joint_[w], axle);
      else
        dJointGetHingeAxis(rear_joint_[w - n_front_], axle);
      s.wheels[w] = {
          {v[0], v[1], v[2]}, {o[0], o[1], o[2]}, {axle[0], axle[1], axle[2]}, dBodyGetPosition(bodies[w])[2]};
    }
    const dReal* vc = dBodyGetLinearVel(chassis_);  // ODE's body origin is its centre of mass
    s.v_chassis_W = {vc[0], vc[1], vc[2]};
    return s;
  }

 protected:
  /// Last word on a wheel-ground contact before its joint is made (the fault-injection suite
  /// changes the friction model here); liftcheck's model leaves it as built.
  virtual void contact_surface(dContact&, dBodyID /*wheel*/) const {}
  /// The chassis body (the fault-injection suite pushes it).
  dBodyID chassis() const { return chassis_; }

 private:
  static void near_callback(void* data, dGeomID o1, dGeomID o2) {
    auto* self = static_cast<OdeCar*>(data);
    if ((o1 == self->ground_) == (o2 == self->ground_)) return;  // only wheel against ground
    const dGeomID wheel = o1 == self->ground_ ? o2 : o1;
    dBodyID body = dGeomGetBody(wheel);
    // Rolling direction: the axle (the hinge axis) turned a quarter about the up axis.
    dVector3 axle;
    if (body == self->front_[0])
      dJointGetHinge2Axis2(self->steer_joint_[0], axle);
    else if (body == self->front_[1])
      dJointGetHinge2Axis2(self->steer_joint_[1], axle);
    else
      dJointGetHingeAxis(self->rear_joint_[body == self->rear_[0] ? 0 : 1], axle);
    dContact contact[4];
    const int n = dCollide(o1, o2, 4, &contact[0].geom, sizeof(dContact));
    for (int i = 0; i < n; ++i) {
      dSurfaceParameters& sp = contact[i].surface;
      sp.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
      sp.mu = self->mu_;
      sp.soft_erp = self->soft_erp_;
      sp.soft_cfm = self->soft_cfm_;
      if (self->wheel_dirs_) {
        sp.mode |= dContactFDir1;
        const double nx = axle[1], ny = -axle[0];  // axle x up: forward for a left-pointing axle
        const double len = std::hypot(nx, ny);
        contact[i].fdir1[0] = nx / len;
        contact[i].fdir1[1] = ny / len;
        contact[i].fdir1[2] = 0.0;
      }
      self->contact_surface(contact[i], body);
      dJointID j = dJointCreateContact(self->world_, self->contacts_, &contact[i]);
      dJointAttach(j, dGeomGetBody(contact[i].geom.g1), dGeomGetBody(contact[i].geom.g2));
      if (self->n_feedback_ >= kMaxContacts) continue;  // dCollide gives at most 4 a wheel: never
      dJointSetFeedback(j, &self->feedback_[self->n_feedback_++]);
    }
  }

  void destroy() {
    if (contacts_) dJointGroupDestroy(contacts_);
    if (space_) dSpaceDestroy(space_);  // destroys its geoms
    sim_.reset();                       // destroys the world, its bodies and joints
    contacts_ = nullptr;
    space_ = nullptr;
    world_ = nullptr;
  }

  static constexpr int kMaxContacts = 16;  ///< 4 a wheel (dCollide's limit above), 4 wheels
  std::array<dJointFeedback, kMaxContacts> feedback_{};
  int n_feedback_ = 0;
  Eigen::Vector3d ground_force_W_ = Eigen::Vector3d::Zero();
  std::unique_ptr<OdeWorld> sim_;
  dWorldID world_ = nullptr;  ///< sim_'s world
  dSpaceID space_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  dGeomID ground_ = nullptr;
  dBodyID chassis_ = nullptr, front_[2] = {nullptr, nullptr}, rear_[2] = {nullptr, nullptr};
  dJointID steer_joint_[2] = {nullptr, nullptr}, rear_joint_[2] = {nullptr, nullptr};
  int n_front_ = 1;                          ///< front wheels: 1 (tricycle) or 2 (left, right)
  double beta0_[2] = {0.0, 0.0}, mu_ = 1.0;  ///< each front wheel's start steering angle
  double soft_erp_ = kContactSoftErp,
         soft_cfm_ = kContactSoftCfm_m_per_Ns;  ///< the wheel-ground contacts' soft_erp, soft_cfm
  bool wheel_dirs_ = true;
  OdeStepper stepper_;
  const OdeCarKnobs knobs_;
};

}  // namespace liftcheck
