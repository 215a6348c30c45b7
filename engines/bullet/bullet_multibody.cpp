// Bullet 3 (double precision) in reduced coordinates: btMultiBodyDynamicsWorld, the Featherstone
// articulated-body solver with btMultiBodyConstraintSolver for contacts and motors, as PyBullet and
// gz-physics' bullet-featherstone run it.
//
// Car: a floating-base btMultiBody. Base = the chassis box (no collider), centre at the middle of
// the tie rod at axle height, like the rigid-body Bullet car. Link 0 the steering knuckle (revolute
// about the chassis z at the front-axle centre), link 1 the front wheel (revolute about the
// knuckle's y), links 2 and 3 the rear wheels (revolute about the chassis y). Wheels are
// btMultiBodyLinkCollider spheres on a static plane; the knuckle carries a tiny collider that
// collides with nothing, because a joint motor is only put into a solver island through its
// link's collider. Signs: a positive revolute position turns the child counter-clockwise about
// the joint axis, so steering left and rolling forward are both positive, with no negation.
//
// Disks: M the y link of a fixed-base btMultiBody on two prismatic joints (x, then y), so it cannot
// turn, N a kinematic btRigidBody;
// M's damping is the setting `damping` as the car's is (btMultiBody damps every body by default).
#include "engines/bullet/bullet_multibody.hpp"

#include <btBulletDynamicsCommon.h>

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <memory>
#include <string>
#include <vector>

#include "engines/driven_disks.hpp"
#include "engines/bullet/bullet_core.hpp"
#include "engines/rigid_car.hpp"
#include "models/e2.hpp"

namespace liftcheck {

namespace {

/// A btMultiBodyDynamicsWorld with everything it needs and everything put into it, owned
/// together: the destructor takes every object out of the world before the world goes, and the
/// world before the parts it was built on.
class MultiBodyScene {
 public:
  explicit MultiBodyScene(const Eigen::Vector3d& gravity_W_mps2, int iterations) {
    world_->setGravity(btVector3(gravity_W_mps2.x(), gravity_W_mps2.y(), gravity_W_mps2.z()));
    world_->getSolverInfo().m_numIterations = iterations;
  }
  MultiBodyScene(const MultiBodyScene&) = delete;
  MultiBodyScene& operator=(const MultiBodyScene&) = delete;
  ~MultiBodyScene() {
    for (auto& c : constraints_) world_->removeMultiBodyConstraint(c.get());
    for (auto& c : colliders_) world_->removeCollisionObject(c.get());
    for (auto& b : bodies_) world_->removeRigidBody(b.get());
    for (auto& o : statics_) world_->removeCollisionObject(o.get());
    for (auto& m : multibodies_) world_->removeMultiBody(m.get());
    world_.reset();
  }

  btMultiBodyDynamicsWorld& world() const { return *world_; }

  template <class S, class... A>
  S* shape(A&&... args) {
    shapes_.push_back(std::make_unique<S>(std::forward<A>(args)...));
    return static_cast<S*>(shapes_.back().get());
  }

  /// Adds a finalized multibody (its colliders are added with collider()).
  btMultiBody* add(std::unique_ptr<btMultiBody> mb) {
    world_->addMultiBody(mb.get());
    multibodies_.push_back(std::move(mb));
    return multibodies_.back().get();
  }

  /// A collider for link `link` of `mb` (-1: the base), registered with the multibody and the world.
  btMultiBodyLinkCollider* collider(btMultiBody* mb, int link, btCollisionShape* s, double friction, int group,
                                    int mask) {
    auto c = std::make_unique<btMultiBodyLinkCollider>(mb, link);
    c->setCollisionShape(s);
    c->setFriction(friction);
    world_->addCollisionObject(c.get(), group, mask);
    if (link < 0)
      mb->setBaseCollider(c.get());
    else
      mb->getLink(link).m_collider = c.get();
    colliders_.push_back(std::move(c));
    return colliders_.back().get();
  }

  /// A static collision object (no btRigidBody: its constructor bumps a process-wide counter).
  btCollisionObject* fixed(btCollisionShape* s, const btTransform& tf, double friction, int group, int mask) {
    auto o = std::make_unique<btCollisionObject>();
    o->setCollisionShape(s);
    o->setWorldTransform(tf);
    o->setFriction(friction);
    o->setCollisionFlags(o->getCollisionFlags() | btCollisionObject::CF_STATIC_OBJECT);
    world_->addCollisionObject(o.get(), group, mask);
    statics_.push_back(std::move(o));
    return statics_.back().get();
  }

  /// A rigid body of zero mass (made kinematic by the caller).
  btRigidBody* body(btCollisionShape* s, const btTransform& tf, double friction, int group, int mask) {
    btRigidBody::btRigidBodyConstructionInfo ci(0.0, nullptr, s, btVector3(0, 0, 0));
    ci.m_startWorldTransform = tf;
    ci.m_friction = friction;
    bodies_.push_back(std::make_unique<btRigidBody>(ci));
    world_->addRigidBody(bodies_.back().get(), group, mask);
    return bodies_.back().get();
  }

  btMultiBodyJointMotor* motor(btMultiBody* mb, int link, double max_impulse) {
    constraints_.push_back(std::make_unique<btMultiBodyJointMotor>(mb, link, 0.0, max_impulse));
    world_->addMultiBodyConstraint(constraints_.back().get());
    return static_cast<btMultiBodyJointMotor*>(constraints_.back().get());
  }

 private:
  // Declaration order is destruction order reversed: the world first, the parts it uses last.
  std::unique_ptr<btDefaultCollisionConfiguration> config_ = std::make_unique<btDefaultCollisionConfiguration>();
  std::unique_ptr<btCollisionDispatcher> dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
  std::unique_ptr<btBroadphaseInterface> broadphase_ = std::make_unique<btDbvtBroadphase>();
  std::unique_ptr<btMultiBodyConstraintSolver> solver_ = std::make_unique<btMultiBodyConstraintSolver>();
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btMultiBody>> multibodies_;
  std::vector<std::unique_ptr<btMultiBodyLinkCollider>> colliders_;
  std::vector<std::unique_ptr<btRigidBody>> bodies_;
  std::vector<std::unique_ptr<btCollisionObject>> statics_;
  std::vector<std::unique_ptr<btMultiBodyConstraint>> constraints_;
  std::unique_ptr<btMultiBodyDynamicsWorld> world_ =
      std::make_unique<btMultiBodyDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(), config_.get());
};

constexpr int kGroupWheel = 1, kGroupGround = 2;
constexpr int kKnuckle = 0, kFront = 1, kRearLeft = 2, kRearRight = 3, kLinks = 4;
// Bullet's default linear and angular damping. btMultiBody's constructor stores it as the float
// literal 0.04f (0.039999999106 in double); both vehicles set the setting's value instead, so a
// record's "damping" is what Bullet applied.
constexpr double kDefaultDamping = 0.04;
constexpr int kDefaultIterations = 10;  // btContactSolverInfo's default

Eigen::Vector3d eig(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

class RawMultiBodyCar;

/// bullet-multibody's car knobs, typed once when the car is made.
struct MultiBodyKnobs {
  int iterations = 10;    ///< btContactSolverInfo::m_numIterations
  double damping = 0.04;  ///< btMultiBody linear and angular damping
  static MultiBodyKnobs from(const Settings& s) {
    return {.iterations = s.integer("iterations"), .damping = s.number("damping")};
  }
};

class MultiBodyCar final : public RigidCar {
  friend class RawMultiBodyCar;  // the benchmarks' raw loop on this multibody

 private:
  const MultiBodyKnobs knobs_;

 public:
  explicit MultiBodyCar(Settings settings) : RigidCar(std::move(settings)), knobs_(MultiBodyKnobs::from(settings_)) {}

 protected:
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    scene_.reset();
    scene_ = std::make_unique<MultiBodyScene>(setup.gravity_W(), knobs_.iterations);
    dt_s_ = setup.dt_s;

    // Ground plane z = 0; Bullet multiplies both bodies' friction coefficients: mu x 1.
    ground_ = scene_->fixed(scene_->shape<btStaticPlaneShape>(btVector3(0, 0, 1), 0.0), btTransform::getIdentity(),
                            setup.mu, kGroupGround, kGroupWheel);

    btVector3 box_inertia(0, 0, 0);
    btBoxShape(btVector3(0.5 * d.l_m, 0.5 * d.track_m, 0.5 * d.chassis_height_m))
        .calculateLocalInertia(d.chassis_mass_kg, box_inertia);
    auto* wheel_shape = scene_->shape<btSphereShape>(d.R_m);
    btVector3 wheel_inertia(0, 0, 0);
    wheel_shape->calculateLocalInertia(d.wheel_mass_kg, wheel_inertia);
    const btVector3 knuckle_inertia(d.knuckle_inertia_kgm2(), d.knuckle_inertia_kgm2(), d.knuckle_inertia_kgm2());
    const btQuaternion same(0, 0, 0, 1);
    const btVector3 zero(0, 0, 0), up(0, 0, 1), axle(0, 1, 0);

    auto mb =
        std::make_unique<btMultiBody>(kLinks, d.chassis_mass_kg, box_inertia, /*fixedBase=*/false, /*canSleep=*/false);
    // Pivot offsets are from the parent's centre of mass: the base's is the middle of the tie rod.
    mb->setupRevolute(kKnuckle, d.knuckle_mass_kg, knuckle_inertia, -1, same, up, btVector3(0.5 * d.l_m, 0, 0), zero,
                      true);
    mb->setupRevolute(kFront, d.wheel_mass_kg, wheel_inertia, kKnuckle, same, axle, zero, zero, true);
    mb->setupRevolute(kRearLeft, d.wheel_mass_kg, wheel_inertia, -1, same, axle,
                      btVector3(-0.5 * d.l_m, 0.5 * d.track_m, 0), zero, true);
    mb->setupRevolute(kRearRight, d.wheel_mass_kg, wheel_inertia, -1, same, axle,
                      btVector3(-0.5 * d.l_m, -0.5 * d.track_m, 0), zero, true);
    mb->finalizeMultiDof();
    const double damping = knobs_.damping;
    mb->setLinearDamping(damping);
    mb->setAngularDamping(damping);

    // The car at q0: q0 is the front-axle centre, the chassis centre is l/2 behind it.
    const double c = std::cos(q0.phi_rad), s = std::sin(q0.phi_rad);
    const btVector3 base_pos(q0.x_m - 0.5 * d.l_m * c, q0.y_m - 0.5 * d.l_m * s, d.R_m);
    mb->setBaseWorldTransform(
        btTransform(btQuaternion(up, q0.phi_rad), base_pos));  // stores world-to-base as the inverse
    mb->setJointPos(kKnuckle, q0.beta_rad);                    // the joint position is the steering angle itself
    mb_ = scene_->add(std::move(mb));

    // The knuckle's collider only puts the steering motor into an island: it collides with nothing.
    scene_->collider(mb_, kKnuckle, scene_->shape<btSphereShape>(0.01), 0.0, 0, 0);
    for (int link : {kFront, kRearLeft, kRearRight})
      scene_->collider(mb_, link, wheel_shape, 1.0, kGroupWheel, kGroupGround);
    btAlignedObjectArray<btQuaternion> world_to_local;
    btAlignedObjectArray<btVector3> local_origin;
    mb_->forwardKinematics(world_to_local, local_origin);
    mb_->updateCollisionObjectWorldTransforms(world_to_local, local_origin);

    steer_motor_ = scene_->motor(mb_, kKnuckle, 0.0);
    spin_motor_ = scene_->motor(mb_, kFront, 0.0);
    // The brake (a braked run only): a zero-speed motor on each rear wheel's joint.
    rear_motor_[0] = rear_motor_[1] = nullptr;
    if (setup.rear_brake)
      rear_motor_[0] = scene_->motor(mb_, kRearLeft, 0.0), rear_motor_[1] = scene_->motor(mb_, kRearRight, 0.0);
  }

  void actuate(const FrontRates& rates, const ServoDef& servo) override {
    const double spin_radps = rates.spin_radps[0], steer_radps = rates.steer_radps[0];
    // A btMultiBodyJointMotor limits the impulse per step, not the torque.
    spin_motor_->setVelocityTarget(spin_radps);
    spin_motor_->setMaxAppliedImpulse(servo.spin_torque_max_Nm * dt_s_);
    steer_motor_->setVelocityTarget(steer_radps);
    steer_motor_->setMaxAppliedImpulse(servo.steer_torque_max_Nm * dt_s_);
    for (btMultiBodyJointMotor* m : rear_motor_)
      if (m) m->setMaxAppliedImpulse(servo.rear_brake_torque_max_Nm * dt_s_);
  }

  void step(double dt_s) override {
    scene_->world().stepSimulation(dt_s, 1, dt_s);
    ground_force_W_ = impulse_from_ground(*scene_->world().getDispatcher(), ground_) / dt_s;
  }

  /// btMultiBodyConstraintSolver's contact impulses, written back into the manifold points.
  std::optional<Eigen::Vector3d> ground_force_W() const override { return ground_force_W_; }

  RigidCarState read() const override {
    // Link velocities in each link's own frame (origin at its centre of mass, here the wheel
    // centre), from the base velocity and the joint rates. The solver made them satisfy the
    // contacts at the configuration the step started from; read at the configuration after it,
    // a wheel turning with the chassis yaw rate w shows a contact velocity of about v w dt.
    btVector3 omega[kLinks + 1], vel[kLinks + 1];
    mb_->compTreeLinkVelocities(omega, vel);
    const btVector3 front = mb_->localPosToWorld(kFront, btVector3(0, 0, 0));
    const btMatrix3x3 base_rot(mb_->getWorldToBaseRot().inverse());
    RigidCarState st{};
    st.spin_joint_rad[0] = e2::wrap_angle(mb_->getJointPos(kFront));
    st.steer_rad[0] = mb_->getJointPos(kKnuckle);
    st.x_m = front.x();
    st.y_m = front.y();
    st.z_m = front.z();
    st.phi_rad = std::atan2(base_rot[1][0], base_rot[0][0]);
    st.rear_z_m = std::min(mb_->localPosToWorld(kRearLeft, btVector3(0, 0, 0)).z(),
                           mb_->localPosToWorld(kRearRight, btVector3(0, 0, 0)).z());
    const int links[3] = {kFront, kRearLeft, kRearRight};
    for (int w = 0; w < 3; ++w) {
      const int i = links[w];
      st.wheels[w] = {eig(mb_->localDirToWorld(i, vel[i + 1])), eig(mb_->localDirToWorld(i, omega[i + 1])),
                      eig(mb_->localDirToWorld(i, btVector3(0, 1, 0)).normalized()),  // the revolute axis
                      mb_->localPosToWorld(i, btVector3(0, 0, 0)).z()};
    }
    st.v_chassis_W = eig(mb_->getBaseVel());  // the base's centre of mass, world frame
    return st;
  }

 private:
  const btCollisionObject* ground_ = nullptr;
  Eigen::Vector3d ground_force_W_ = Eigen::Vector3d::Zero();
  std::unique_ptr<MultiBodyScene> scene_;
  btMultiBody* mb_ = nullptr;
  btMultiBodyJointMotor *steer_motor_ = nullptr, *spin_motor_ = nullptr;
  btMultiBodyJointMotor* rear_motor_[2] = {nullptr, nullptr};  ///< the brake, in braked runs only
  double dt_s_ = 1e-3;
};

/// Two disks: M the last link of a fixed-base multibody on two prismatic joints, x then y (as a
/// robot's planar base is built: PyBullet's two sliders), so it moves in the plane and cannot turn;
/// its joint velocities are set to the command before each step. N a kinematic rigid body placed
/// on its path after each step.
class MultiBodyDisks final : public DrivenDisks {
 public:
  MultiBodyDisks(int iterations, double damping) : iterations_(iterations), damping_(damping) {}

 protected:
  void build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) override {
    scene_.reset();
    scene_ = std::make_unique<MultiBodyScene>(Eigen::Vector3d::Zero(), iterations_);
    auto* sphere = scene_->shape<btSphereShape>(setup.radius_m);
    btVector3 inertia(0, 0, 0);
    sphere->calculateLocalInertia(1.0, inertia);
    auto mb = std::make_unique<btMultiBody>(2, 1.0, btVector3(1, 1, 1), /*fixedBase=*/true, /*canSleep=*/false);
    const btQuaternion same(0, 0, 0, 1);
    const btVector3 zero(0, 0, 0);
    // The x slider carries no mass of its own: M's 1 kg and its inertia are the y slider's link.
    mb->setupPrismatic(0, 0.0, zero, -1, same, btVector3(1, 0, 0), zero, zero, true);
    mb->setupPrismatic(1, 1.0, inertia, 0, same, btVector3(0, 1, 0), zero, zero, true);
    mb->finalizeMultiDof();
    mb->setLinearDamping(damping_);
    mb->setAngularDamping(damping_);
    mb->setJointPos(0, cM0.x());
    mb->setJointPos(1, cM0.y());
    m_ = scene_->add(std::move(mb));
    // Bullet multiplies the two bodies' friction coefficients: mu_MN x 1, 0 in every scenario.
    m_collider_ =
        scene_->collider(m_, 1, sphere, setup.mu_MN, btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
    btAlignedObjectArray<btQuaternion> world_to_local;
    btAlignedObjectArray<btVector3> local_origin;
    m_->updateCollisionObjectWorldTransforms(world_to_local, local_origin);

    n_ = scene_->body(sphere, btTransform(btQuaternion(0, 0, 0, 1), btVector3(cN0.x(), cN0.y(), 0)), 1.0,
                      btBroadphaseProxy::DefaultFilter, btBroadphaseProxy::AllFilter);
    n_->setCollisionFlags(n_->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    n_->setActivationState(DISABLE_DEACTIVATION);
  }

  StepContacts step(const disks::Vec2& vM_cmd, const disks::Vec2& cN_next, const disks::Vec2&, double dt_s) override {
    m_->setJointVel(0, vM_cmd.x());
    m_->setJointVel(1, vM_cmd.y());
    scene_->world().stepSimulation(dt_s, 1, dt_s);
    StepContacts c;
    btDispatcher* d = scene_->world().getDispatcher();
    for (int i = 0; i < d->getNumManifolds(); ++i) {
      const btPersistentManifold* m = d->getManifoldByIndexInternal(i);
      const bool pair = (m->getBody0() == m_collider_ && m->getBody1() == n_) ||
                        (m->getBody0() == n_ && m->getBody1() == m_collider_);
      if (!pair) continue;
      for (int k = 0; k < m->getNumContacts(); ++k) {
        const double dist = m->getContactPoint(k).getDistance();
        if (dist > 0) continue;  // a speculative point short of contact
        c.count += 1;
        c.depth_max_m = std::max(c.depth_max_m, -dist);
      }
    }
    // N moves along its path: a kinematic body is placed; Bullet derives its velocity for the
    // next step from the move.
    n_->setWorldTransform(btTransform(btQuaternion(0, 0, 0, 1), btVector3(cN_next.x(), cN_next.y(), 0)));
    return c;
  }

  State read() const override {
    const btVector3 pn = n_->getWorldTransform().getOrigin();
    // The links' angular velocities as Bullet computes them from the joint rates (base, x, y).
    m_->compTreeLinkVelocities(omega_.data(), vel_.data());
    const btVector3 w = m_->localDirToWorld(1, omega_[2]);
    return {{m_->getJointPos(0), m_->getJointPos(1)}, {pn.x(), pn.y()}, {w.x(), w.y(), w.z()}};
  }

 private:
  int iterations_;
  double damping_;  ///< btMultiBody linear and angular damping of M
  std::unique_ptr<MultiBodyScene> scene_;
  btMultiBody* m_ = nullptr;
  btMultiBodyLinkCollider* m_collider_ = nullptr;
  mutable std::array<btVector3, 3> omega_, vel_;  ///< read()'s scratch: base, x link, y link
  btRigidBody* n_ = nullptr;
};

/// The benchmarks' raw loop (engines/raw_car.hpp): MultiBodyCar's world and multibody, the joint
/// motors set once, stepSimulation directly.
class RawMultiBodyCar final : public RawCar {
 public:
  RawMultiBodyCar(const Settings& s, const CarSetup& setup, const car::Config& q0) : car_(s), dt_s_(setup.dt_s) {
    car_.reset(setup, q0);
  }

  void run(long steps, double spin_radps) override {
    const ServoDef& servo = car_.servo_;  // the run's own limits (ServoDef::for_car)
    car_.spin_motor_->setVelocityTarget(spin_radps);
    car_.spin_motor_->setMaxAppliedImpulse(servo.spin_torque_max_Nm * dt_s_);
    car_.steer_motor_->setVelocityTarget(0.0);
    car_.steer_motor_->setMaxAppliedImpulse(servo.steer_torque_max_Nm * dt_s_);
    btMultiBodyDynamicsWorld& world = car_.scene_->world();
    for (long k = 0; k < steps; ++k) world.stepSimulation(dt_s_, 1, dt_s_);
  }

  Eigen::Vector2d front_xy_m() const override {
    const btVector3 p = car_.mb_->localPosToWorld(kFront, btVector3(0, 0, 0));
    return {p.x(), p.y()};
  }

 private:
  MultiBodyCar car_;
  double dt_s_;
};

/// btMultiBody's velocity damping of `vehicle`: the car's multibody, or disk M's.
SettingSpec damping_knob(Vehicle vehicle) {
  return {{.key = "damping",
           .kind = ParamKind::kNumber,
           .default_text = fmt::format("{:g}", kDefaultDamping),
           .unit = "1",
           .help = "btMultiBody linear and angular damping (btMultiBody::setLinearDamping, setAngularDamping; Bullet's "
                   "default 0.04)",
           .min = 0,
           .max = 1},
          vehicle,
          SettingRole::kDamping};
}

}  // namespace

std::unique_ptr<RawCar> make_raw_bullet_multibody_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<RawMultiBodyCar>(s, setup, q0);
}

EngineInfo bullet_multibody_engine() {
  return {
      .name = "bullet-multibody",
      .library = "Bullet",
      .version = fmt::format("{} (double)", LIFTCHECK_BULLET_VERSION),
      .description =
          "Bullet Featherstone btMultiBody: floating-base tricycle, revolute links, joint motors, Bullet's defaults "
          "(damping 0.04, 10 iterations)",
      .color = "#d62728",
      .make_car = [](const Settings& s) { return std::make_unique<MultiBodyCar>(s); },
      .make_disks =
          [](const Settings& s) { return std::make_unique<MultiBodyDisks>(kDefaultIterations, s.number("damping")); },
      .contact_dynamics = true,
      .settings =
          {{"precision", "double (bullet-float64)"},
           {"stepper",
            "btMultiBodyDynamicsWorld, btMultiBodyConstraintSolver (sequential impulse), stepSimulation(dt, 1, dt)"},
           {"joints",
            "floating-base btMultiBody (chassis box, no collider); revolute links: steering knuckle (knuckle_mass, "
            "isotropic inertia knuckle_mass x 2e-3 m^2; carries a 0.01 m collider that collides with nothing, so its "
            "motor enters an island), front wheel on the knuckle, two rear wheels on the base"},
           {"motors",
            "btMultiBodyJointMotor velocity targets on the knuckle (steering) and the front wheel (spin), max impulse "
            "per step = torque limit x dt"},
           {"contact",
            "btMultiBodyLinkCollider spheres on a static plane; friction = mu x 1 (Bullet multiplies both bodies' "
            "coefficients); other btContactSolverInfo fields at Bullet's defaults"},
           {"contact forces",
            "read each step from the wheel-ground manifold points, where btMultiBodyConstraintSolver writes the normal "
            "and both friction impulses back, over dt (the load and momentum checks)"},
           {"friction directions",
            "two (SOLVER_USE_2_FRICTION_DIRECTIONS, set by btMultiBodyDynamicsWorld): world plane-space axes of the "
            "contact normal; custom directions are ignored by btMultiBodyConstraintSolver, so they cannot follow the "
            "wheel"},
           {"damping",
            "btMultiBody linear and angular damping (setLinearDamping, setAngularDamping) of the car and of disk M: "
            "--set damping (default 0.04, Bullet's)"},
           {"servo",
            "rate = commanded rate + 40/s x angle error, torque limit 1.5 mu N R of the driven wheel (106 N m for the "
            "default car); settle 0.5 s, hold 0.2 s"},
           {"disks",
            "M: the y link of a fixed-base btMultiBody on two prismatic joints, x (no mass) then y (radius 1, 1 kg, "
            "frictionless collider), as PyBullet's planar bases are built: it cannot turn; joint velocities set to "
            "the command before each step; N: kinematic btRigidBody sphere placed on its path; contact from "
            "the step's manifolds (distance <= 0), multibody solver response, 10 iterations"}},
      .knobs = {SettingSpec{{.key = "iterations",
                             .kind = ParamKind::kInteger,
                             .default_text = std::to_string(kDefaultIterations),
                             .unit = "1",
                             .help = "solver iterations (btContactSolverInfo::m_numIterations)",
                             .min = 1,
                             .max = 10000},
                            Vehicle::kCar,
                            SettingRole::kSolverIterations},
                damping_knob(Vehicle::kCar), damping_knob(Vehicle::kDisks)},
      .brakes = true,
      .make_raw_car = make_raw_bullet_multibody_car};
}

}  // namespace liftcheck
