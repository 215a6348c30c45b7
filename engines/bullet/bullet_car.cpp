// The tricycle in Bullet 3 (double precision build, BT_USE_DOUBLE_PRECISION).
// Chassis: a box body that collides with nothing. Front wheel: btHinge2Constraint (frame x = axle,
// z = steering axis) with the linear suspension locked and motors on both angular axes. Rear
// wheels: btHingeConstraint about the rear axle. Wheel-ground friction uses two friction rows
// (SOLVER_USE_2_FRICTION_DIRECTIONS); with friction_dirs = wheel the first row lies along the
// wheel's rolling direction, set on every contact point before each solve.
// Signs (tests/test_engine_signs.cpp): the 6DOF angles are of body B relative to body A with the
// chassis as A; the steering angle and spin rate are negated where marked.
#include "engines/bullet/bullet_car.hpp"
#include "engines/bullet/bullet_core.hpp"

#include <btBulletDynamicsCommon.h>

#include <cmath>
#include <fmt/format.h>
#include <memory>

#include "engines/rigid_car.hpp"

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

class BulletCar final : public RigidCar {
  friend class RawBulletCar;  // the benchmarks' raw loop on these bodies

 public:
  using RigidCar::RigidCar;

 protected:
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    teardown();
    rear_hinge_[0].reset();
    rear_hinge_[1].reset();
    hinge2_.reset();
    bodies_.clear();
    shapes_.clear();
    world_.reset();
    core_ = std::make_unique<BulletCore>();
    world_ = core_->make_world<WheelFrictionWorld>();
    world_->setGravity(btVector3(0, 0, -setup.gravity_mps2));
    world_->align = setting("friction_dirs") == "wheel";
    btContactSolverInfo& info = world_->getSolverInfo();
    info.m_numIterations = std::stoi(setting("iterations"));
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

    auto* chassis_shape = add_shape(std::make_unique<btBoxShape>(btVector3(0.5 * d.l_m, 0.5 * d.track_m, 0.5 * d.chassis_height_m)));
    chassis_ = add_body(d.chassis_mass_kg, chassis_shape, btTransform(yaw_chassis, to_world(-0.5 * d.l_m, 0, d.R_m)), 0, 0);

    btCollisionShape* wheel_shape = nullptr;
    if (setting("wheel") == "cylinder")
      wheel_shape = add_shape(std::make_unique<btCylinderShape>(btVector3(d.R_m, 0.5 * d.wheel_width_m, d.R_m)));  // along local y
    else
      wheel_shape = add_shape(std::make_unique<btSphereShape>(d.R_m));
    // Wheel local frames: y along the axle (left), so cylinder and sphere wheels share the joints.
    const double steer_yaw = q0.phi_rad + q0.beta_rad;
    front_ = add_body(d.wheel_mass_kg, wheel_shape,
                      btTransform(btQuaternion(btVector3(0, 0, 1), steer_yaw), to_world(0, 0, d.R_m)), kGroupWheel, kGroupGround);
    rear_[0] = add_body(d.wheel_mass_kg, wheel_shape, btTransform(yaw_chassis, to_world(-d.l_m, 0.5 * d.track_m, d.R_m)), kGroupWheel, kGroupGround);
    rear_[1] = add_body(d.wheel_mass_kg, wheel_shape, btTransform(yaw_chassis, to_world(-d.l_m, -0.5 * d.track_m, d.R_m)), kGroupWheel, kGroupGround);
    for (btRigidBody* w : {front_, rear_[0], rear_[1]}) {
      w->setFriction(1.0);
      w->setUserIndex(kWheelTag);
    }

    // Front: hinge-2 at the front-axle centre; axis 1 up (steering), axis 2 the axle.
    btVector3 anchor = to_world(0, 0, d.R_m), up(0, 0, 1), axle(-std::sin(steer_yaw), std::cos(steer_yaw), 0);
    hinge2_ = std::make_unique<btHinge2Constraint>(*chassis_, *front_, anchor, up, axle);
    hinge2_->setLinearLowerLimit(btVector3(0, 0, 0));  // suspension locked
    hinge2_->setLinearUpperLimit(btVector3(0, 0, 0));
    hinge2_->enableSpring(2, false);
    hinge2_->setAngularLowerLimit(btVector3(1, 0, 1));  // lower > upper: spin (x) and steering (z) free
    hinge2_->setAngularUpperLimit(btVector3(-1, 0, -1));
    hinge2_->enableMotor(3, true);  // angular x: spin
    hinge2_->enableMotor(5, true);  // angular z: steering
    world_->addConstraint(hinge2_.get(), true);
    beta0_ = q0.beta_rad;

    for (int i = 0; i < 2; ++i) {
      const btVector3 pivot_in_chassis(-0.5 * d.l_m, (i == 0 ? 0.5 : -0.5) * d.track_m, 0);
      rear_hinge_[i] = std::make_unique<btHingeConstraint>(*chassis_, *rear_[i], pivot_in_chassis, btVector3(0, 0, 0),
                                                           btVector3(0, 1, 0), btVector3(0, 1, 0));
      world_->addConstraint(rear_hinge_[i].get(), true);
    }
  }

  void actuate(double spin_radps, double steer_radps, const ServoDef& servo) override {
    hinge2_->setTargetVelocity(3, -spin_radps);
    hinge2_->setMaxMotorForce(3, servo.spin_torque_max_Nm);
    hinge2_->setTargetVelocity(5, -steer_radps);
    hinge2_->setMaxMotorForce(5, servo.steer_torque_max_Nm);
  }

  void step(double dt_s) override {
    world_->stepSimulation(dt_s, 1, dt_s);
  }

  RigidCarState read() const override {
    hinge2_->calculateTransforms();
    const btVector3 p = front_->getWorldTransform().getOrigin();
    const btMatrix3x3& Rc = chassis_->getWorldTransform().getBasis();
    RigidCarState s{};
    s.spin_joint_rad = -hinge2_->getAngle2();
    s.steer_rad = beta0_ - hinge2_->getAngle1();
    s.x_m = p.x();
    s.y_m = p.y();
    s.z_m = p.z();
    s.phi_rad = std::atan2(Rc[1][0], Rc[0][0]);
    s.rear_z_m = std::min(rear_[0]->getWorldTransform().getOrigin().z(), rear_[1]->getWorldTransform().getOrigin().z());
    const btRigidBody* bodies[3] = {front_, rear_[0], rear_[1]};
    for (int w = 0; w < 3; ++w) {
      const btVector3 v = bodies[w]->getLinearVelocity(), o = bodies[w]->getAngularVelocity();
      const btVector3 axle = bodies[w]->getWorldTransform().getBasis().getColumn(1);  // every wheel's local y
      s.wheels[w] = {{v.x(), v.y(), v.z()}, {o.x(), o.y(), o.z()}, {axle.x(), axle.y(), axle.z()},
                     bodies[w]->getWorldTransform().getOrigin().z()};
    }
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
    if (hinge2_) world_->removeConstraint(hinge2_.get());
    for (auto& b : bodies_) world_->removeRigidBody(b.get());
    world_.reset();
  }

  std::unique_ptr<BulletCore> core_;
  std::unique_ptr<WheelFrictionWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::unique_ptr<btHinge2Constraint> hinge2_;
  std::unique_ptr<btHingeConstraint> rear_hinge_[2];
  btRigidBody *ground_ = nullptr, *chassis_ = nullptr, *front_ = nullptr, *rear_[2] = {nullptr, nullptr};
  double beta0_ = 0.0;
};

/// The benchmarks' raw loop (engines/raw_car.hpp): BulletCar's world, bodies and hinges, the motors
/// set once, stepSimulation directly.
class RawBulletCar final : public RawCar {
 public:
  RawBulletCar(const Settings& s, const CarSetup& setup, const car::Config& q0) : car_(s), dt_s_(setup.dt_s) { car_.reset(setup, q0); }

  void run(long steps, double spin_radps) override {
    const ServoDef servo;
    car_.hinge2_->setTargetVelocity(3, -spin_radps);  // negated as in BulletCar::actuate
    car_.hinge2_->setMaxMotorForce(3, servo.spin_torque_max_Nm);
    car_.hinge2_->setTargetVelocity(5, 0.0);
    car_.hinge2_->setMaxMotorForce(5, servo.steer_torque_max_Nm);
    for (long k = 0; k < steps; ++k) car_.world_->stepSimulation(dt_s_, 1, dt_s_);
  }

  Eigen::Vector2d front_xy_m() const override {
    const btVector3 p = car_.front_->getWorldTransform().getOrigin();
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
  return {.name = "bullet",
          .library = "Bullet",
          .version = fmt::format("{} (double)", LIFTCHECK_BULLET_VERSION),
          .description = "Bullet rigid bodies: btHinge2Constraint front wheel, hinge rear wheels, 2 friction directions, fixed step",
          .color = "#ff7f0e",
          .make_car = [](const Settings& s) { return std::make_unique<BulletCar>(s); },
          .make_disks = [](const Settings&) { return make_bullet_disks(); },
          .contact_dynamics = true,
          .settings = {{"precision", "double (bullet-float64)"},
           {"stepper", "btDiscreteDynamicsWorld, stepSimulation(dt, 1, dt), sequential impulse solver"},
           {"front wheel", "btHinge2Constraint, linear suspension locked, spring off; motors on angular x (spin) and z (steering)"},
           {"rear wheels", "btHingeConstraint each"},
           {"contact", "friction = mu x 1 (Bullet multiplies both bodies' coefficients)"},
           {"friction directions", "SOLVER_USE_2_FRICTION_DIRECTIONS; wheel: first direction set along the rolling direction before each solve, kept with SOLVER_ENABLE_FRICTION_DIRECTION_CACHING; world: plane-space axes of the normal"},
           {"servo", "rate = commanded rate + 40/s x angle error, torque limit 500 N m; settle 0.5 s, hold 0.2 s"},
           {"disks", "M: dynamic sphere (radius 1, 1 kg, frictionless), linear velocity set to the command before each step; N: kinematic sphere placed on its path; contact from the step's manifolds (distance <= 0), sequential-impulse response"}},
          .knobs = {SettingSpec{"iterations", "car", "100", "sequential-impulse solver iterations (btContactSolverInfo::m_numIterations)", SettingSpec::kInteger, 1, 10000, {}}, SettingSpec{"wheel", "car", "sphere", "wheel collision shape", SettingSpec::kChoice, 0, 0, {"sphere", "cylinder"}}, SettingSpec{"friction_dirs", "car", "wheel", "first friction direction: along the wheel's rolling direction, or the engine's default axes", SettingSpec::kChoice, 0, 0, {"wheel", "world"}}}};
}

}  // namespace liftcheck
