// DART 6 (Dynamic Animation and Robotics Toolkit, the engine behind Gazebo's default physics):
// reduced coordinates (Featherstone articulated bodies), semi-implicit Euler, contacts, joint
// servos and friction solved together as one boxed LCP per step.
//
// Car: one Skeleton. The chassis is a FreeJoint body whose frame is TricycleDef's chassis frame
// (origin at the front-axle centre, x along the tie rod, z up; the box's centre of mass l/2
// behind it, no collision shape). The steering knuckle hangs on a RevoluteJoint about the
// chassis z at that origin, the front wheel on a RevoluteJoint about the knuckle's y at the same
// point, the rear wheels on RevoluteJoints about the chassis y at (-l, +-track/2, 0). Wheels are
// SphereShapes with friction mu; the ground is a static skeleton holding a 200 x 200 x 1 m box
// whose top face is z = 0. Signs: a positive revolute position turns the child counter-clockwise
// about the joint axis, so steering left (about +z) and rolling forward (about +y) are both
// positive, and the steering joint starts at q0.beta itself.
//
// Steering and spin are SERVO actuators: the command is a joint velocity that DART's constraint
// solver enforces together with the contacts, within the joint's force limits.
//
// Disks: M a skeleton on a TranslationalJoint with SERVO actuators (its commanded velocity, z
// held at 0), N a skeleton on a TranslationalJoint with VELOCITY actuators (kinematic: DART
// integrates the commanded velocity that lands it on its path, and contact impulses do not move
// it). Contact comes from the collision result of the step (World::step runs collision on the
// state at the start of the step, after the velocity update and before the position update).
//
// Threads: every run has its own World, whose constraint solver owns its collision detector (FCL's
// or DART's) and LCP solvers, so runs step in parallel. What DART 6.12 keeps per process is read
// only while stepping: the world frame Frame::World() (a static that deliberately records no
// children, Entity::changeParentFrame), the detector factory, and FCL's collision function tables
// (function-local statics). The one process-wide generator it links, dRandInt in DART's copy of
// ODE's LCP code, is used by the PGS fallback only with mRandomizeConstraintOrder, off by default.
#include "engines/dart/dart_engine.hpp"

#include <dart/collision/CollisionObject.hpp>
#include <dart/collision/CollisionResult.hpp>
#include <dart/collision/dart/DARTCollisionDetector.hpp>
#include <dart/config.hpp>
#include <dart/constraint/ConstraintSolver.hpp>
#include <dart/constraint/ContactConstraint.hpp>
#include <dart/dynamics/BodyNode.hpp>
#include <dart/dynamics/BoxShape.hpp>
#include <dart/dynamics/FreeJoint.hpp>
#include <dart/dynamics/RevoluteJoint.hpp>
#include <dart/dynamics/ShapeNode.hpp>
#include <dart/dynamics/Skeleton.hpp>
#include <dart/dynamics/SphereShape.hpp>
#include <dart/dynamics/TranslationalJoint.hpp>
#include <dart/dynamics/WeldJoint.hpp>
#include <dart/simulation/World.hpp>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <memory>
#include <string>

#include "engines/driven_disks.hpp"
#include "engines/rigid_car.hpp"
#include "models/e2.hpp"

namespace liftcheck {

namespace {

using dart::dynamics::BodyNode;
using dart::dynamics::CollisionAspect;
using dart::dynamics::DynamicsAspect;
using dart::dynamics::Joint;
using dart::dynamics::ShapeNode;
using dart::dynamics::Skeleton;
using dart::dynamics::SkeletonPtr;

/// Which collision detector the World's constraint solver uses (the setting `detector`).
enum class Detector {
  kShipped,  ///< "fcl": whatever World creates, FCLCollisionDetector with primitives as meshes
  kDart,     ///< "dart": DARTCollisionDetector, analytic spheres and boxes
};

Detector detector_of(const Settings& s) {
  return s.choice("detector") == "dart" ? Detector::kDart : Detector::kShipped;
}

constexpr double kGroundSize_m = 200.0, kGroundThickness_m = 1.0;
constexpr double kDiskMass_kg = 1.0;
// M's SERVO force limit per axis, the adapter's choice (DART's own default is unbounded): enough to
// reach any commanded velocity within one step (1e5 N changes 1 kg's velocity by 100 m/s in 1 ms).
constexpr double kDiskServoForceMax_N = 1e5;

std::shared_ptr<dart::simulation::World> make_world(Detector det, const Eigen::Vector3d& gravity_W_mps2, double dt_s) {
  auto world = dart::simulation::World::create("liftcheck");
  world->setGravity(gravity_W_mps2);
  world->setTimeStep(dt_s);
  if (det == Detector::kDart)
    world->getConstraintSolver()->setCollisionDetector(dart::collision::DARTCollisionDetector::create());
  return world;
}

/// Body properties carrying a name unique in its skeleton (DART renames duplicates and says so).
BodyNode::AspectProperties named(const std::string& name) { return BodyNode::AspectProperties(name); }

ShapeNode* add_shape(BodyNode* body, std::shared_ptr<dart::dynamics::Shape> shape, double mu) {
  ShapeNode* sn = body->createShapeNodeWith<CollisionAspect, DynamicsAspect>(std::move(shape));
  sn->getDynamicsAspect()->setFrictionCoeff(mu);
  sn->getDynamicsAspect()->setRestitutionCoeff(0.0);
  return sn;
}

/// Box inertia (diagonal) about its centre.
Eigen::Matrix3d box_inertia(double m, double a, double b, double c) {
  return Eigen::Vector3d(m * (b * b + c * c) / 12.0, m * (a * a + c * c) / 12.0, m * (a * a + b * b) / 12.0)
      .asDiagonal();
}

class RawDartCar;

class DartCar final : public RigidCar {
  friend class RawDartCar;  // the benchmarks' raw loop on this world

 public:
  explicit DartCar(Settings settings)
      : RigidCar(std::move(settings)),
        det_(detector_of(settings_)),
        wheel_dirs_(settings_.choice("friction_dirs") == "wheel") {}

 protected:
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    world_ = make_world(det_, setup.gravity_W(), setup.dt_s);

    // Ground: a static skeleton with a box whose top face is z = 0.
    SkeletonPtr ground = Skeleton::create("ground");
    auto [gj, gb] = ground->createJointAndBodyNodePair<dart::dynamics::WeldJoint>(nullptr, {}, named("ground"));
    Eigen::Isometry3d below = Eigen::Isometry3d::Identity();
    below.translation() = Eigen::Vector3d(0.0, 0.0, -0.5 * kGroundThickness_m);
    gj->setTransformFromParentBodyNode(below);
    add_shape(
        gb,
        std::make_shared<dart::dynamics::BoxShape>(Eigen::Vector3d(kGroundSize_m, kGroundSize_m, kGroundThickness_m)),
        setup.mu);
    ground->setMobile(false);
    world_->addSkeleton(ground);
    ground_body_ = gb;

    car_ = Skeleton::create("car");
    // Chassis: frame at the front-axle centre, box centre of mass l/2 behind it.
    auto [cj, chassis] = car_->createJointAndBodyNodePair<dart::dynamics::FreeJoint>(nullptr, {}, named("chassis"));
    chassis->setMass(d.chassis_mass_kg);
    const Eigen::Matrix3d Ic = box_inertia(d.chassis_mass_kg, d.l_m, d.track_m, d.chassis_height_m);
    chassis->setMomentOfInertia(Ic(0, 0), Ic(1, 1), Ic(2, 2));
    chassis->setLocalCOM(Eigen::Vector3d(-0.5 * d.l_m, 0.0, 0.0));
    chassis_ = chassis;

    const double I_wheel = 0.4 * d.wheel_mass_kg * d.R_m * d.R_m;  // solid sphere
    // friction_dirs = wheel: the first friction direction is the rolling direction, x of the body
    // that steers the wheel (the knuckle for the front wheel, the chassis for the rear ones);
    // world: DART's default, a direction derived from the contact normal alone.
    const bool wheel_dirs = wheel_dirs_;
    const auto wheel_body = [&](BodyNode* b, const BodyNode* heading) {
      b->setMass(d.wheel_mass_kg);
      b->setMomentOfInertia(I_wheel, I_wheel, I_wheel);
      ShapeNode* sn = add_shape(b, std::make_shared<dart::dynamics::SphereShape>(d.R_m), setup.mu);
      if (wheel_dirs) {
        sn->getDynamicsAspect()->setFirstFrictionDirection(Eigen::Vector3d::UnitX());
        sn->getDynamicsAspect()->setFirstFrictionDirectionFrame(heading);
      }
    };

    dart::dynamics::RevoluteJoint::Properties steer_p;
    steer_p.mName = "steer";
    steer_p.mAxis = Eigen::Vector3d::UnitZ();
    auto [sj, knuckle] =
        car_->createJointAndBodyNodePair<dart::dynamics::RevoluteJoint>(chassis, steer_p, named("knuckle"));
    knuckle->setMass(d.knuckle_mass_kg);
    knuckle->setMomentOfInertia(d.knuckle_inertia_kgm2(), d.knuckle_inertia_kgm2(), d.knuckle_inertia_kgm2());
    steer_ = sj;

    dart::dynamics::RevoluteJoint::Properties spin_p;
    spin_p.mName = "spin";
    spin_p.mAxis = Eigen::Vector3d::UnitY();
    auto [wj, front] =
        car_->createJointAndBodyNodePair<dart::dynamics::RevoluteJoint>(knuckle, spin_p, named("front wheel"));
    wheel_body(front, knuckle);
    spin_ = wj;
    wheels_[0] = front;

    for (int side = 0; side < 2; ++side) {
      dart::dynamics::RevoluteJoint::Properties rp;
      rp.mName = side == 0 ? "rear left" : "rear right";
      rp.mAxis = Eigen::Vector3d::UnitY();
      rp.mT_ParentBodyToJoint.translation() = Eigen::Vector3d(-d.l_m, (side == 0 ? 0.5 : -0.5) * d.track_m, 0.0);
      auto [rj, rb] =
          car_->createJointAndBodyNodePair<dart::dynamics::RevoluteJoint>(chassis, rp, named(rp.mName + " wheel"));
      wheel_body(rb, chassis);
      wheels_[1 + side] = rb;
      rear_[side] = rj;
    }

    for (Joint* j : {steer_, spin_}) j->setActuatorType(Joint::SERVO);
    // The brake of a braked run: each rear joint a SERVO actuator commanded to zero velocity, force
    // limited to the brake's torque (as the spin's is); free (DART's FORCE actuator, no force) otherwise.
    if (setup.rear_brake)
      for (Joint* j : rear_) j->setActuatorType(Joint::SERVO);

    // The car at q0: the chassis frame at the front-axle centre, at axle height.
    Eigen::Isometry3d T0 = Eigen::Isometry3d::Identity();
    T0.linear() = Eigen::AngleAxisd(q0.phi_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T0.translation() = Eigen::Vector3d(q0.x_m, q0.y_m, d.R_m);
    cj->setPositions(dart::dynamics::FreeJoint::convertToPositions(T0));
    steer_->setPosition(0, q0.beta_rad);
    world_->addSkeleton(car_);
  }

  void actuate(const FrontRates& rates, const ServoDef& servo) override {
    const double spin_radps = rates.spin_radps[0], steer_radps = rates.steer_radps[0];
    spin_->setForceLowerLimit(0, -servo.spin_torque_max_Nm);
    spin_->setForceUpperLimit(0, servo.spin_torque_max_Nm);
    steer_->setForceLowerLimit(0, -servo.steer_torque_max_Nm);
    steer_->setForceUpperLimit(0, servo.steer_torque_max_Nm);
    spin_->setCommand(0, spin_radps);
    steer_->setCommand(0, steer_radps);
    if (rear_[0]->getActuatorType() == Joint::SERVO)
      for (Joint* j : rear_) {
        j->setForceLowerLimit(0, -servo.rear_brake_torque_max_Nm);
        j->setForceUpperLimit(0, servo.rear_brake_torque_max_Nm);
        j->setCommand(0, 0.0);  // SERVO commands are consumed by each step
      }
  }

  void step(double) override {
    world_->step();
    ground_force_W_.setZero();
    for (const dart::collision::Contact& c : world_->getLastCollisionResult().getContacts()) {
      const bool ground1 = on_ground(c.collisionObject1), ground2 = on_ground(c.collisionObject2);
      if (ground1 == ground2) continue;
      ground_force_W_ += ground1 ? -c.force : c.force;  // Contact::force acts on the first object's body
    }
  }

  /// The force of the step just taken that DART's contact constraints wrote into the last
  /// collision result's contacts (Contact::force, on the first object's body, world frame).
  std::optional<Eigen::Vector3d> ground_force_W() const override { return ground_force_W_; }

  bool on_ground(const dart::collision::CollisionObject* o) const {
    const dart::dynamics::ShapeNode* n = o->getShapeFrame()->asShapeNode();
    return n && n->getBodyNodePtr() == ground_body_;
  }

  RigidCarState read() const override {
    const Eigen::Isometry3d Tc = chassis_->getWorldTransform();
    const Eigen::Vector3d front = wheels_[0]->getWorldTransform().translation();
    RigidCarState st{};
    st.spin_joint_rad[0] = e2::wrap_angle(spin_->getPosition(0));
    st.steer_rad[0] = steer_->getPosition(0);
    st.x_m = front.x();
    st.y_m = front.y();
    st.z_m = front.z();
    st.phi_rad = std::atan2(Tc.linear()(1, 0), Tc.linear()(0, 0));
    st.rear_z_m =
        std::min(wheels_[1]->getWorldTransform().translation().z(), wheels_[2]->getWorldTransform().translation().z());
    for (int w = 0; w < 3; ++w) {
      const BodyNode* b = wheels_[w];
      const Eigen::Isometry3d T = b->getWorldTransform();
      // The wheel's frame origin is its centre: the body's linear velocity is the hub's.
      st.wheels[w] = {b->getLinearVelocity(), b->getAngularVelocity(),
                      (T.linear() * Eigen::Vector3d::UnitY()).normalized(), T.translation().z()};
    }
    st.v_chassis_W = chassis_->getCOMLinearVelocity();
    return st;
  }

 private:
  Detector det_;
  std::shared_ptr<dart::simulation::World> world_;
  const dart::dynamics::BodyNode* ground_body_ = nullptr;
  Eigen::Vector3d ground_force_W_ = Eigen::Vector3d::Zero();
  SkeletonPtr car_;
  BodyNode* chassis_ = nullptr;
  BodyNode* wheels_[3] = {nullptr, nullptr, nullptr};
  Joint* steer_ = nullptr;
  Joint* spin_ = nullptr;
  Joint* rear_[2] = {nullptr, nullptr};  ///< the rear wheels' joints (SERVO at zero speed in a braked run)
  /// friction_dirs: the first friction direction along the rolling direction (typed once when the car is made).
  const bool wheel_dirs_;
};

/// Two disks: M on a translational joint with SERVO actuators, N on one with VELOCITY actuators.
class DartDisks final : public DrivenDisks {
 public:
  explicit DartDisks(const Settings& s) : det_(detector_of(s)), servo_force_max_N_(s.number("servo_force_limit_N")) {}

 protected:
  void build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) override {
    world_ = make_world(det_, Eigen::Vector3d::Zero(), setup.dt_s);
    const auto disk = [&](const char* name, const disks::Vec2& c, Joint::ActuatorType type, ShapeNode** shape) {
      SkeletonPtr sk = Skeleton::create(name);
      auto [j, b] = sk->createJointAndBodyNodePair<dart::dynamics::TranslationalJoint>(nullptr, {}, named(name));
      b->setMass(kDiskMass_kg);
      const double I = 0.4 * kDiskMass_kg * setup.radius_m * setup.radius_m;
      b->setMomentOfInertia(I, I, I);
      // Friction mu_MN on both (DART takes the smaller of the two): 0, frictionless, in every scenario.
      *shape = add_shape(b, std::make_shared<dart::dynamics::SphereShape>(setup.radius_m), setup.mu_MN);
      j->setPositions(Eigen::Vector3d(c.x(), c.y(), 0.0));
      j->setActuatorType(type);
      if (type == Joint::SERVO)
        for (std::size_t i = 0; i < 3; ++i) {
          j->setForceLowerLimit(i, -servo_force_max_N_);
          j->setForceUpperLimit(i, servo_force_max_N_);
        }
      world_->addSkeleton(sk);
      return j;
    };
    m_joint_ = disk("M", cM0, Joint::SERVO, &m_shape_);
    n_joint_ = disk("N", cN0, Joint::VELOCITY, &n_shape_);
    dt_s_ = setup.dt_s;
  }

  StepContacts step(const disks::Vec2& vM_cmd, const disks::Vec2& cN_next, const disks::Vec2&, double dt_s) override {
    if (dt_s != dt_s_) {  // the last, shorter step of a horizon that is not a whole number of steps
      world_->setTimeStep(dt_s);
      dt_s_ = dt_s;
    }
    m_joint_->setCommands(Eigen::Vector3d(vM_cmd.x(), vM_cmd.y(), 0.0));
    // N: the velocity that lands it on its path at the end of the step.
    const Eigen::Vector3d pN = n_joint_->getPositions();
    n_joint_->setCommands(Eigen::Vector3d((cN_next.x() - pN.x()) / dt_s, (cN_next.y() - pN.y()) / dt_s, 0.0));
    world_->step();
    StepContacts c;
    for (const auto& contact : world_->getLastCollisionResult().getContacts()) {
      const auto* a = contact.collisionObject1->getShapeFrame();
      const auto* b = contact.collisionObject2->getShapeFrame();
      const bool pair = (a == m_shape_ && b == n_shape_) || (a == n_shape_ && b == m_shape_);
      if (!pair || contact.penetrationDepth < 0.0) continue;
      c.count += 1;
      c.depth_max_m = std::max(c.depth_max_m, contact.penetrationDepth);
    }
    return c;
  }

  State read() const override {
    const Eigen::VectorXd pm = m_joint_->getPositions(), pn = n_joint_->getPositions();
    return {{pm.x(), pm.y()}, {pn.x(), pn.y()}, m_joint_->getChildBodyNode()->getAngularVelocity()};
  }

 private:
  Detector det_;
  double servo_force_max_N_;  ///< M's SERVO force limit on each axis
  std::shared_ptr<dart::simulation::World> world_;
  Joint* m_joint_ = nullptr;
  Joint* n_joint_ = nullptr;
  ShapeNode* m_shape_ = nullptr;
  ShapeNode* n_shape_ = nullptr;
  double dt_s_ = 1e-3;
};

std::string detector_name(Detector det) { return det == Detector::kDart ? "dart" : "fcl"; }

std::vector<std::pair<std::string, std::string>> settings_for(Detector det) {
  using dart::constraint::ContactConstraint;
  const std::string detector = fmt::format(
      "--set detector for cars and disks (default {}): fcl, FCLCollisionDetector as World creates it (primitive shape "
      "type MESH: spheres tessellated into "
      "polyhedra; DART's own contact points); dart, DARTCollisionDetector set on the constraint solver (analytic "
      "sphere-box and sphere-sphere contacts)",
      detector_name(det));
  return {
      {"stepper",
       "dart::simulation::World::step: Featherstone forward dynamics, semi-implicit Euler (velocities, then positions "
       "with the new velocities), fixed dt"},
      {"constraint solver",
       "BoxedLcpConstraintSolver as shipped: Dantzig boxed LCP, PGS as fallback; contacts, servos and friction in one "
       "LCP per step"},
      {"contact parameters",
       fmt::format("ContactConstraint defaults: error reduction {:g}, max error reduction velocity {:g} m/s, error "
                   "allowance {:g} m, CFM {:g}; restitution 0",
                   ContactConstraint::getErrorReductionParameter(), ContactConstraint::getMaxErrorReductionVelocity(),
                   ContactConstraint::getErrorAllowance(), ContactConstraint::getConstraintForceMixing())},
      {"collision detector", detector},
      {"friction",
       "Coulomb, wheel and ground shapes both set to mu (so the pair has mu whichever way DART combines them), "
       "friction pyramid with two directions; the first one is set by friction_dirs"},
      {"friction directions",
       "world (DART's default): derived from the contact normal alone, so fixed to the world axes; wheel: "
       "DynamicsAspect first friction direction x of the knuckle (front) or chassis (rear), the rolling direction"},
      {"joints",
       "Skeleton: FreeJoint chassis (frame at the front-axle centre, a box of the scenario's chassis_mass, centre of "
       "mass l/2 behind, no collision shape); RevoluteJoint steering knuckle (knuckle_mass, isotropic inertia "
       "knuckle_mass x 2e-3 m^2) about the chassis z; RevoluteJoint front wheel about the knuckle's y; RevoluteJoint "
       "rear wheels about the chassis y; sphere wheels of wheel_mass"},
      {"ground", "static skeleton (WeldJoint, not mobile): a 200 x 200 x 1 m BoxShape with its top face at z = 0"},
      {"servo",
       "Joint::SERVO actuators on steering and spin (command = joint velocity, solved with the contacts), force limits "
       "+-(1.5 mu N R of the driven wheel: 106 N m for the default car); rate = commanded rate + 40/s x angle error; "
       "settle 0.5 s, hold 0.2 s"},
      {"disks",
       "M: skeleton on a TranslationalJoint with SERVO actuators (radius 1, 1 kg, frictionless, no gravity), commands "
       "= the commanded velocity (z 0), force limits +-servo_force_limit_N on each axis (--set, default 1e5 N; DART's "
       "own default is unbounded); N: skeleton on a TranslationalJoint with VELOCITY actuators (kinematic) commanded "
       "to land on its path each step; contact from World::getLastCollisionResult() (the collision pass at the start "
       "of the step), depth >= 0"},
      {"disk friction",
       "M is driven by SERVO actuators solved with the contacts in one LCP, and the same servo that presses M into "
       "N holds its commanded velocity along N's surface: friction between the disks (mu 0.5, disks.oblique) moves "
       "M's end by 4.9e-5 m (FCL) and 5.7e-4 m (DART's detector), against 2.7 m on ODE, so with this actuation a "
       "friction fault hardly shows in M's path; M's spin is held by its TranslationalJoint"},
      {"contact forces",
       "Contact::force of every wheel-ground contact in World::getLastCollisionResult(), which DART's contact "
       "constraints write (the normal and friction impulses over dt), summed each step (the load and momentum "
       "checks)"},
  };
}

/// The benchmarks' raw loop (engines/raw_car.hpp): DartCar's world and skeletons, the servo
/// commands set once, World::step directly.
class RawDartCar final : public RawCar {
 public:
  RawDartCar(const Settings& s, const CarSetup& setup, const car::Config& q0) : car_(s) { car_.reset(setup, q0); }

  void run(long steps, double spin_radps) override {
    const ServoDef& servo = car_.servo_;  // the run's own limits (ServoDef::for_car)
    car_.spin_->setForceLowerLimit(0, -servo.spin_torque_max_Nm);
    car_.spin_->setForceUpperLimit(0, servo.spin_torque_max_Nm);
    car_.steer_->setForceLowerLimit(0, -servo.steer_torque_max_Nm);
    car_.steer_->setForceUpperLimit(0, servo.steer_torque_max_Nm);
    for (long k = 0; k < steps; ++k) {
      // SERVO commands are consumed by each step: set them before every step, as DartCar::actuate is.
      car_.spin_->setCommand(0, spin_radps);
      car_.steer_->setCommand(0, 0.0);
      car_.world_->step();
    }
  }

  Eigen::Vector2d front_xy_m() const override { return car_.wheels_[0]->getWorldTransform().translation().head<2>(); }

 private:
  DartCar car_;
};

/// The settings of a configuration whose detector by default is `det`.
std::vector<SettingSpec> knobs_for(Detector det) {
  std::vector<SettingSpec> knobs;
  for (const Vehicle vehicle : kVehicles)
    knobs.push_back({{.key = "detector",
                      .kind = ParamKind::kChoice,
                      .default_text = detector_name(det),
                      .help = "collision detector of the World's constraint solver "
                              "(ConstraintSolver::setCollisionDetector): fcl, the FCLCollisionDetector "
                              "World creates by default, which meshes primitive shapes; dart, DARTCollisionDetector, "
                              "DART's own analytic detector for spheres and boxes",
                      .choices = {"fcl", "dart"}},
                     vehicle});
  knobs.push_back({{.key = "friction_dirs",
                    .kind = ParamKind::kChoice,
                    .default_text = "world",
                    .help = "first friction direction: DART's default from the contact normal (world-fixed), or along "
                            "the wheel's rolling direction (DynamicsAspect::setFirstFrictionDirection)",
                    .choices = {"world", "wheel"}},
                   Vehicle::kCar});
  knobs.push_back({{.key = "servo_force_limit_N",
                    .kind = ParamKind::kNumber,
                    .default_text = fmt::format("{:g}", kDiskServoForceMax_N),
                    .unit = "N",
                    .help = "force limit of disk M's SERVO actuator on each translational axis "
                            "(Joint::setForceLowerLimit/setForceUpperLimit at -+ the value; "
                            "DART's own default is unbounded)",
                    .min = 0.0,
                    .min_exclusive = true},
                   Vehicle::kDisks});
  return knobs;
}

EngineInfo make_info(Detector det) {
  const bool prim = det == Detector::kDart;
  return {.name = prim ? "dart-primitive" : "dart",
          .library = "DART",
          .version = DART_VERSION,
          .description = prim ? "DART with its own collision detector (DARTCollisionDetector): analytic sphere "
                                "contacts; Skeleton tricycle, SERVO actuators, Dantzig LCP"
                              : "DART as shipped: FCL collision detection with spheres as meshes, Dantzig LCP; "
                                "Skeleton tricycle, SERVO actuators",
          .color = prim ? "#e377c2" : "#8c564b",
          .make_car = [](const Settings& s) { return std::make_unique<DartCar>(s); },
          .make_disks = [](const Settings& s) { return std::make_unique<DartDisks>(s); },
          .contact_dynamics = true,
          .settings = settings_for(det),
          .knobs = knobs_for(det),
          .brakes = true,
          .make_raw_car = prim ? make_raw_dart_primitive_car : make_raw_dart_car,
          // As shipped, FCL's contacts between meshed spheres took 34 of the default suite's
          // worker seconds in the sweeps and the outcome grid, where all 40 sweep points fail
          // (dart-primitive's all but 8) and 20 of the 84 cases (dart-primitive's 19): its runs
          // and the map; the sweeps and the grid with --all-points.
          .points = prim ? SuitePoints::kAll : SuitePoints::kMap};
}

}  // namespace

std::unique_ptr<RawCar> make_raw_dart_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<RawDartCar>(s, setup, q0);
}
std::unique_ptr<RawCar> make_raw_dart_primitive_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<RawDartCar>(s, setup, q0);
}

EngineInfo dart_engine() { return make_info(Detector::kShipped); }
EngineInfo dart_primitive_engine() { return make_info(Detector::kDart); }

}  // namespace liftcheck
