// The tricycle in Bullet 3 (double precision build, BT_USE_DOUBLE_PRECISION).
// Chassis: a box body that collides with nothing. Front wheel: btHinge2Constraint (frame x = axle,
// z = steering axis) with the linear suspension locked and motors on both angular axes. Rear
// wheels: btHingeConstraint about the rear axle. Wheel-ground friction uses two friction rows
// (SOLVER_USE_2_FRICTION_DIRECTIONS); with friction_dirs = wheel the first row lies along the
// wheel's rolling direction, set on every contact point before each solve.
// Signs (tests/conformance.cpp, ForwardIsPositiveAlphaAndLeftIsPositiveBeta): the 6DOF angles are of body B relative to
// body A with the chassis as A; the steering angle and spin rate are negated where marked.
#include "engines/bullet/bullet_car.hpp"
#include "engines/bullet/bullet_core.hpp"

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <fmt/format.h>
#include <memory>

#include "engines/rigid_car.hpp"
#include "models/ackermann.hpp"

namespace liftcheck {

namespace {

constexpr int kGroupWheel = 1, kGroupGround = 2, kWheelTag = 7;

/// A dynamics world that aligns each wheel contact's first friction direction with the wheel's
/// rolling direction (the axle turned a quarter about the contact normal) before the solver runs.
class WheelFrictionWorld final : public btDiscreteDynamicsWorld {
 public:
  using btDiscreteDynamicsWorld::btDiscreteDynamicsWorld;
  bool align = true;

 protected:
  void solveConstraints(btContactSolverInfo& info) override {
    if (align) {
      btDispatcher* d = getDispatcher();
      for (int i = 0; i < d->getNumManifolds(); ++i) {
        btPersistentManifold* m = d->getManifoldByIndexInternal(i);
        const auto* a = static_cast<const btCollisionObject*>(m->getBody0());
        const auto* b = static_cast<const btCollisionObject*>(m->getBody1());
        const btCollisionObject* wheel = a->getUserIndex() == kWheelTag ? a : b;
        if (wheel->getUserIndex() != kWheelTag) continue;
        // Every wheel's local y axis is its axle.
        const btVector3 axle = wheel->getWorldTransform().getBasis().getColumn(1);
        for (int k = 0; k < m->getNumContacts(); ++k) {
          btManifoldPoint& p = m->getContactPoint(k);
          btVector3 roll = axle.cross(p.m_normalWorldOnB);
          if (roll.length2() < 1e-12) continue;
          roll.normalize();
          p.m_lateralFrictionDir1 = roll;
          p.m_lateralFrictionDir2 = p.m_normalWorldOnB.cross(roll).normalized();
          p.m_contactPointFlags |= BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED;
        }
      }
    }
    btDiscreteDynamicsWorld::solveConstraints(info);
  }
};

class RawBulletCar;

/// bullet's car knobs, typed once when the car is made.
struct BulletKnobs {
  bool wheel_dirs = true;  ///< friction_dirs: the first direction along the rolling direction
  int iterations = 100;    ///< btContactSolverInfo::m_numIterations
  bool cylinder = false;   ///< wheel: cylinders instead of spheres
  static BulletKnobs from(const Settings& s) {
    return {.wheel_dirs = s.choice("friction_dirs") == "wheel",
            .iterations = s.integer("iterations"),
            .cylinder = s.choice("wheel") == "cylinder"};
  }
};

class BulletCar final : public RigidCar {
  friend class RawBulletCar;  // the benchmarks' raw loop on these bodies

 public:
  explicit BulletCar(Settings settings) : RigidCar(std::move(settings)), knobs_(BulletKnobs::from(settings_)) {}

 private:
  const BulletKnobs knobs_;

 public:
 protected:
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    teardown();
    rear_hinge_[0].reset();
    rear_hinge_[1].reset();
    for (auto& h : hinge2_) h.reset();
    bodies_.clear();
    shapes_.clear();
    world_.reset();
    core_ = std::make_unique<BulletCore>();
    world_ = core_->make_world<WheelFrictionWorld>();
    world_->setGravity(btVector3(setup.gravity_W().x(), setup.gravity_W().y(), setup.gravity_W().z()));
    world_->align = knobs_.wheel_dirs;
    btContactSolverInfo& info = world_->getSolverInfo();
    info.m_numIterations = knobs_.iterations;
    info.m_solverMode |= SOLVER_USE_2_FRICTION_DIRECTIONS;
    // Fixed world axes when not aligned: no velocity-dependent friction direction either.
    info.m_solverMode |= SOLVER_DISABLE_VELOCITY_DEPENDENT_FRICTION_DIRECTION;
    // The solver keeps preset friction directions (BT_CONTACT_FLAG_LATERAL_FRICTION_INITIALIZED)
    // only with direction caching on; without it, it recomputes them from the normal every step.
    if (world_->align) info.m_solverMode |= SOLVER_ENABLE_FRICTION_DIRECTION_CACHING;

    // Ground plane z = 0.
    auto* ground_shape = add_shape(std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0));
    ground_ = add_body(0.0, ground_shape, btTransform::getIdentity(), kGroupGround, kGroupWheel);
    ground_->setFriction(setup.mu);  // Bullet multiplies the two bodies' coefficients: mu * 1

    const double c = std::cos(q0.phi_rad), s = std::sin(q0.phi_rad);
    const auto to_world = [&](double bx, double by, double bz) {
      return btVector3(q0.x_m + c * bx - s * by, q0.y_m + s * bx + c * by, bz);
    };
    const btQuaternion yaw_chassis(btVector3(0, 0, 1), q0.phi_rad);

    auto* chassis_shape =
        add_shape(std::make_unique<btBoxShape>(btVector3(0.5 * d.l_m, 0.5 * d.track_m, 0.5 * d.chassis_height_m)));
    chassis_ =
        add_body(d.chassis_mass_kg, chassis_shape, btTransform(yaw_chassis, to_world(-0.5 * d.l_m, 0, d.R_m)), 0, 0);

    btCollisionShape* wheel_shape = nullptr;
    if (knobs_.cylinder)
      wheel_shape = add_shape(
          std::make_unique<btCylinderShape>(btVector3(d.R_m, 0.5 * d.wheel_width_m, d.R_m)));  // along local y
    else
      wheel_shape = add_shape(std::make_unique<btSphereShape>(d.R_m));
    // Wheel local frames: y along the axle (left), so cylinder and sphere wheels share the joints.
    // Front wheels: the tricycle's one at the front-axle centre, or a four-wheel car's two at
    // (0, +-track/2), each at its Ackermann angle for beta0 (or at beta0, steered in parallel).
    n_front_ = d.wheels == 4 ? 2 : 1;
    front_[1] = nullptr;
    for (int k = 0; k < n_front_; ++k) {
      beta0_[k] = q0.beta_rad;
      if (n_front_ == 2 && !d.parallel_steering)
        beta0_[k] =
            car::ackermann_wheel_angle(q0.beta_rad, d.l_m, d.track_m, k == 0 ? car::Side::kLeft : car::Side::kRight);
      const double y_k = n_front_ == 1 ? 0.0 : (k == 0 ? 0.5 : -0.5) * d.track_m;
      front_[k] =
          add_body(d.wheel_mass_kg, wheel_shape,
                   btTransform(btQuaternion(btVector3(0, 0, 1), q0.phi_rad + beta0_[k]), to_world(0, y_k, d.R_m)),
                   kGroupWheel, kGroupGround);
      // No knuckle body: the hinge-2 constraint steers the wheel body itself, so the knuckle's
      // mass rides on it (at the wheel centre, its isotropic inertia added to the wheel's).
      btVector3 inertia;
      wheel_shape->calculateLocalInertia(d.wheel_mass_kg, inertia);
      front_[k]->setMassProps(d.wheel_mass_kg + d.knuckle_mass_kg,
                              inertia + btVector3(1, 1, 1) * d.knuckle_inertia_kgm2());
      front_[k]->updateInertiaTensor();
    }
    rear_[0] = add_body(d.wheel_mass_kg, wheel_shape,
                        btTransform(yaw_chassis, to_world(-d.l_m, 0.5 * d.track_m, d.R_m)), kGroupWheel, kGroupGround);
    rear_[1] = add_body(d.wheel_mass_kg, wheel_shape,
                        btTransform(yaw_chassis, to_world(-d.l_m, -0.5 * d.track_m, d.R_m)), kGroupWheel, kGroupGround);
    for (btRigidBody* w : {front_[0], front_[1], rear_[0], rear_[1]}) {
      if (!w) continue;
      w->setFriction(1.0);
      w->setUserIndex(kWheelTag);
    }

    // Front: a hinge-2 at each front wheel centre; axis 1 up (steering), axis 2 the axle.
    for (int k = 0; k < n_front_; ++k) {
      const double steer_yaw = q0.phi_rad + beta0_[k];
      btVector3 anchor = front_[k]->getWorldTransform().getOrigin(), up(0, 0, 1),
                axle(-std::sin(steer_yaw), std::cos(steer_yaw), 0);
      hinge2_[k] = std::make_unique<btHinge2Constraint>(*chassis_, *front_[k], anchor, up, axle);
      hinge2_[k]->setLinearLowerLimit(btVector3(0, 0, 0));  // suspension locked
      hinge2_[k]->setLinearUpperLimit(btVector3(0, 0, 0));
      hinge2_[k]->enableSpring(2, false);
      hinge2_[k]->setAngularLowerLimit(btVector3(1, 0, 1));  // lower > upper: spin (x) and steering (z) free
      hinge2_[k]->setAngularUpperLimit(btVector3(-1, 0, -1));
      hinge2_[k]->enableMotor(3, true);  // angular x: spin
      hinge2_[k]->enableMotor(5, true);  // angular z: steering
      world_->addConstraint(hinge2_[k].get(), true);
    }

    for (int i = 0; i < 2; ++i) {
      const btVector3 pivot_in_chassis(-0.5 * d.l_m, (i == 0 ? 0.5 : -0.5) * d.track_m, 0);
      rear_hinge_[i] = std::make_unique<btHingeConstraint>(*chassis_, *rear_[i], pivot_in_chassis, btVector3(0, 0, 0),
                                                           btVector3(0, 1, 0), btVector3(0, 1, 0));
      world_->addConstraint(rear_hinge_[i].get(), true);
    }
  }

  void actuate(const FrontRates& rates, const ServoDef& servo) override {
    for (int k = 0; k < n_front_; ++k) {
      hinge2_[k]->setTargetVelocity(3, -rates.spin_radps[k]);
      hinge2_[k]->setMaxMotorForce(3, servo.spin_torque_max_Nm);
      hinge2_[k]->setTargetVelocity(5, -rates.steer_radps[k]);
      hinge2_[k]->setMaxMotorForce(5, servo.steer_torque_max_Nm);
    }
    rear_brake_Nm_ = servo.rear_brake_torque_max_Nm;
  }

  bool four_wheels() const override { return true; }

  void step(double dt_s) override {
    // The brake: each rear hinge's motor at zero speed; btHingeConstraint's limit is an impulse a step.
    for (auto& h : rear_hinge_) h->enableAngularMotor(rear_brake_Nm_ > 0.0, 0.0, rear_brake_Nm_ * dt_s);
    world_->stepSimulation(dt_s, 1, dt_s);
    ground_force_W_ = impulse_from_ground(*world_->getDispatcher(), ground_) / dt_s;
  }

  std::optional<Eigen::Vector3d> ground_force_W() const override { return ground_force_W_; }

  RigidCarState read() const override {
    const btMatrix3x3& Rc = chassis_->getWorldTransform().getBasis();
    RigidCarState s{};
    s.x_m = s.y_m = 0.0;
    s.z_m = INFINITY;
    for (int k = 0; k < n_front_; ++k) {
      hinge2_[k]->calculateTransforms();
      const btVector3 p = front_[k]->getWorldTransform().getOrigin();
      s.spin_joint_rad[k] = -hinge2_[k]->getAngle2();
      s.steer_rad[k] = beta0_[k] - hinge2_[k]->getAngle1();
      s.x_m += p.x() / n_front_;  // the front-axle centre: the midpoint of the front wheel centres
      s.y_m += p.y() / n_front_;
      s.z_m = std::min<double>(s.z_m, p.z());
    }
    s.phi_rad = std::atan2(Rc[1][0], Rc[0][0]);
    s.rear_z_m = std::min(rear_[0]->getWorldTransform().getOrigin().z(), rear_[1]->getWorldTransform().getOrigin().z());
    const btRigidBody* bodies[4] = {front_[0], n_front_ == 2 ? front_[1] : rear_[0],
                                    n_front_ == 2 ? rear_[0] : rear_[1], rear_[1]};
    for (int w = 0; w < n_front_ + 2; ++w) {
      const btVector3 v = bodies[w]->getLinearVelocity(), o = bodies[w]->getAngularVelocity();
      const btVector3 axle = bodies[w]->getWorldTransform().getBasis().getColumn(1);  // every wheel's local y
      s.wheels[w] = {{v.x(), v.y(), v.z()},
                     {o.x(), o.y(), o.z()},
                     {axle.x(), axle.y(), axle.z()},
                     bodies[w]->getWorldTransform().getOrigin().z()};
    }
    const btVector3 vc = chassis_->getLinearVelocity();  // at the centre of mass
    s.v_chassis_W = {vc.x(), vc.y(), vc.z()};
    return s;
  }

 private:
  btCollisionShape* add_shape(std::unique_ptr<btCollisionShape> s) {
    shapes_.push_back(std::move(s));
    return shapes_.back().get();
  }

  btRigidBody* add_body(double mass, btCollisionShape* shape, const btTransform& tf, int group, int mask) {
    btVector3 inertia(0, 0, 0);
    if (mass > 0) shape->calculateLocalInertia(mass, inertia);
    btRigidBody::btRigidBodyConstructionInfo ci(mass, nullptr, shape, inertia);
    ci.m_startWorldTransform = tf;
    ci.m_linearDamping = 0;
    ci.m_angularDamping = 0;
    auto body = std::make_unique<btRigidBody>(ci);
    body->setActivationState(DISABLE_DEACTIVATION);
    world_->addRigidBody(body.get(), group, mask);
    bodies_.push_back(std::move(body));
    return bodies_.back().get();
  }

 public:
  ~BulletCar() override { teardown(); }

 private:
  void teardown() {
    if (!world_) return;
    for (auto& h : rear_hinge_)
      if (h) world_->removeConstraint(h.get());
    for (auto& h : hinge2_)
      if (h) world_->removeConstraint(h.get());
    for (auto& b : bodies_) world_->removeRigidBody(b.get());
    world_.reset();
  }

  std::unique_ptr<BulletCore> core_;
  std::unique_ptr<WheelFrictionWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::unique_ptr<btHinge2Constraint> hinge2_[2];  ///< one per front wheel
  std::unique_ptr<btHingeConstraint> rear_hinge_[2];
  double rear_brake_Nm_ = 0.0;  ///< the rear hinges' motor limit (ServoDef::rear_brake_torque_max_Nm; 0: free)
  Eigen::Vector3d ground_force_W_ = Eigen::Vector3d::Zero();
  btRigidBody *ground_ = nullptr, *chassis_ = nullptr, *front_[2] = {nullptr, nullptr}, *rear_[2] = {nullptr, nullptr};
  int n_front_ = 1;               ///< front wheels: 1 (tricycle) or 2 (left, right)
  double beta0_[2] = {0.0, 0.0};  ///< each front wheel's start steering angle
};

/// The benchmarks' raw loop (engines/raw_car.hpp): BulletCar's world, bodies and hinges, the motors
/// set once, stepSimulation directly.
class RawBulletCar final : public RawCar {
 public:
  RawBulletCar(const Settings& s, const CarSetup& setup, const car::Config& q0) : car_(s), dt_s_(setup.dt_s) {
    car_.reset(setup, q0);
  }

  void run(long steps, double spin_radps) override {
    const ServoDef& servo = car_.servo_;                 // the run's own limits (ServoDef::for_car)
    car_.hinge2_[0]->setTargetVelocity(3, -spin_radps);  // negated as in BulletCar::actuate
    car_.hinge2_[0]->setMaxMotorForce(3, servo.spin_torque_max_Nm);
    car_.hinge2_[0]->setTargetVelocity(5, 0.0);
    car_.hinge2_[0]->setMaxMotorForce(5, servo.steer_torque_max_Nm);
    for (long k = 0; k < steps; ++k) car_.world_->stepSimulation(dt_s_, 1, dt_s_);
  }

  Eigen::Vector2d front_xy_m() const override {
    const btVector3 p = car_.front_[0]->getWorldTransform().getOrigin();
    return {p.x(), p.y()};
  }

 private:
  BulletCar car_;
  double dt_s_;
};

}  // namespace

std::unique_ptr<RawCar> make_raw_bullet_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<RawBulletCar>(s, setup, q0);
}

EngineInfo bullet_engine() {
  return {
      .name = "bullet",
      .library = "Bullet",
      .version = fmt::format("{} (double)", LIFTCHECK_BULLET_VERSION),
      .description =
          "Bullet rigid bodies: btHinge2Constraint front wheel, hinge rear wheels, 2 friction directions, fixed step",
      .color = "#ff7f0e",
      .make_car = [](const Settings& s) { return std::make_unique<BulletCar>(s); },
      .make_disks = [](const Settings&) { return make_bullet_disks(); },
      .contact_dynamics = true,
      .settings =
          {{"precision", "double (bullet-float64)"},
           {"stepper", "btDiscreteDynamicsWorld, stepSimulation(dt, 1, dt), sequential impulse solver"},
           {"front wheel",
            "btHinge2Constraint, linear suspension locked, spring off; motors on angular x (spin) and z (steering); no "
            "knuckle body: the knuckle's mass and inertia ride on the wheel body"},
           {"rear wheels", "btHingeConstraint each"},
           {"contact", "friction = mu x 1 (Bullet multiplies both bodies' coefficients)"},
           {"contact forces",
            "read each step from the wheel-ground manifold points: m_appliedImpulse along the normal and the two "
            "lateral impulses along their directions, over dt (the load and momentum checks)"},
           {"friction directions",
            "SOLVER_USE_2_FRICTION_DIRECTIONS; wheel: first direction set along the rolling direction before each "
            "solve, kept with SOLVER_ENABLE_FRICTION_DIRECTION_CACHING; world: plane-space axes of the normal"},
           {"servo",
            "rate = commanded rate + 40/s x angle error, torque limit 1.5 mu N R of the driven wheel (106 N m for the "
            "default car); settle 0.5 s, hold 0.2 s"},
           {"disks",
            "M: dynamic sphere (radius 1, 1 kg, frictionless), linear velocity set to the command before each step; N: "
            "kinematic sphere placed on its path; contact from the step's manifolds (distance <= 0), "
            "sequential-impulse response"}},
      .knobs = {SettingSpec{{.key = "iterations",
                             .kind = ParamKind::kInteger,
                             .default_text = "100",
                             .unit = "1",
                             .help = "sequential-impulse solver iterations (btContactSolverInfo::m_numIterations)",
                             .min = 1,
                             .max = 10000},
                            Vehicle::kCar,
                            SettingRole::kSolverIterations},
                SettingSpec{{.key = "wheel",
                             .kind = ParamKind::kChoice,
                             .default_text = "sphere",
                             .help = "wheel collision shape",
                             .choices = {"sphere", "cylinder"}},
                            Vehicle::kCar},
                SettingSpec{
                    {.key = "friction_dirs",
                     .kind = ParamKind::kChoice,
                     .default_text = "wheel",
                     .help =
                         "first friction direction: along the wheel's rolling direction, or the engine's default axes",
                     .choices = {"wheel", "world"}},
                    Vehicle::kCar}},
      .four_wheels = true,
      .brakes = true,
      .make_raw_car = make_raw_bullet_car};
}

}  // namespace liftcheck
