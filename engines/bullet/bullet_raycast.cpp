// The tricycle as Bullet's btRaycastVehicle (double precision build, BT_USE_DOUBLE_PRECISION).
// Chassis: one box body of the car's total mass that collides with nothing. Wheels: three rays
// (btDefaultVehicleRaycaster) against a static btRigidBody plane; the front wheel at the
// front-axle centre is steered and driven, the rear wheels at the rear axle +-track/2 are passive.
// The vehicle runs as an action after Bullet integrates the chassis: spring-damper suspension
// impulses, then per wheel one side impulse (resolveSingleBilateral, 0.2 of the impulse that
// would cancel that wheel's lateral velocity) and the engine force or brake along the wheel.
//
// Vehicle frame (setCoordinateSystem(1, 2, 0)): x forward, y left, z up, the chassis frame of
// TricycleDef with its origin moved to the centre of mass (the middle of the tie rod at axle
// height). Wheel direction -z, axle -y: Bullet's forward = up x axle = +x, a positive steering
// value turns the wheel left, a positive engine force pushes forward, m_rotation grows forward.
//
// The wheels have no spin state: the steering value is set kinematically, the wheel rotation is
// computed from the chassis velocity. So the spin command regulates the front wheel's forward
// speed through the engine force, and the realized wheel angle is the front wheel's travel along
// its own heading over R (knob wheel_angle: or Bullet's m_rotation, which projects the velocity on
// the chassis axis instead and so turns cos(beta) too slowly on the steered wheel).
#include "engines/bullet/bullet_raycast.hpp"
#include "engines/bullet/bullet_core.hpp"

#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <memory>
#include <mutex>

#include "engines/rigid_car.hpp"

namespace liftcheck {

namespace {

constexpr int kGroupChassis = 4;
constexpr int kFront = 0;
/// Speed loop gain, 1/s: 4 x the harness's 40/s angle servo, so the cascade (angle servo around
/// the speed loop) is critically damped.
constexpr double kSpeedGain = 160.0;

Eigen::Vector3d to_eigen(const btVector3& v) { return {v.x(), v.y(), v.z()}; }

// Every wheel of every vehicle that hits the ground points its m_groundObject at one process-wide
// body, btActionInterface::getFixedBody(): a function-static btRigidBody that each call (each ray
// cast, btRaycastVehicle.cpp) rewrites with the same constants (setMassProps(0, 0): inverse mass and
// inertia 0, CF_STATIC_OBJECT), and that updateFriction then reads (its inverse mass, velocity and
// inertia: all zero) and "pushes" with applyImpulse, which writes nothing at inverse mass 0. The
// values never change, so the unsynchronised stores are benign on any real machine, but concurrent
// stores are still a data race by the C++ memory model. So the static is made once before any
// vehicle exists, and everything of a vehicle that calls it (updateAction, which runs the ray casts
// and the friction, and the ray casts of build) holds one process-wide lock.

/// Access to the protected static.
struct FixedBodyAccess : btActionInterface {
  static btRigidBody& get() { return getFixedBody(); }
};

std::mutex& fixed_body_mutex() {
  static std::mutex m;
  return m;
}

void make_fixed_body_once() {
  static std::once_flag once;
  std::call_once(once, [] { FixedBodyAccess::get(); });
}

/// btRaycastVehicle whose action (ray casts, suspension, friction) holds the fixed body's lock.
class LockedRaycastVehicle final : public btRaycastVehicle {
 public:
  using btRaycastVehicle::btRaycastVehicle;
  void updateAction(btCollisionWorld* world, btScalar dt_s) override {
    std::lock_guard<std::mutex> lock(fixed_body_mutex());
    btRaycastVehicle::updateAction(world, dt_s);
  }
};

class RawRaycastCar;

/// bullet-raycast's knobs, typed once when the car is made.
struct RaycastKnobs {
  bool heading_angle = true;          ///< wheel_angle: the travel along the wheel's heading (else Bullet's m_rotation)
  double suspension_stiffness = 1e4;  ///< per unit chassis mass, 1/s^2
  static RaycastKnobs from(const Settings& s) {
    return {.heading_angle = s.choice("wheel_angle") == "heading",
            .suspension_stiffness = s.number("suspension_stiffness")};
  }
};

/// Why the ground's forces are not booked on the raycast vehicle (its facts say so too).
constexpr const char* kContactForcesNotRead =
    "none to read: btRaycastVehicle's wheels are rays with no contact points; it applies their suspension forces and "
    "side impulses to the chassis itself (the load and momentum checks are skipped, saying so)";

class BulletRaycastCar final : public RigidCar {
  friend class RawRaycastCar;  // the benchmarks' raw loop on this vehicle

 private:
  const RaycastKnobs knobs_;

 public:
  explicit BulletRaycastCar(Settings settings) : RigidCar(std::move(settings)), knobs_(RaycastKnobs::from(settings_)) {}
  ~BulletRaycastCar() override { teardown(); }

  bool wheels_spin() const override { return false; }
  std::string ground_force_absent_why() const override { return kContactForcesNotRead; }

 protected:
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    teardown();
    vehicle_.reset();
    raycaster_.reset();
    chassis_.reset();
    ground_.reset();
    world_.reset();
    core_ = std::make_unique<BulletCore>();
    world_ = core_->make_world<btDiscreteDynamicsWorld>();
    world_->setGravity(btVector3(setup.gravity_W().x(), setup.gravity_W().y(), setup.gravity_W().z()));
    const double g = -setup.gravity_W().z();  // the component along the ground's normal loads the suspension
    heading_angle_ = knobs_.heading_angle;
    const double k = knobs_.suspension_stiffness;
    R_ = d.R_m;
    mass_ = d.chassis_mass_kg + 3 * d.wheel_mass_kg + d.knuckle_mass_kg;  // one body: the whole car
    mu_ = setup.mu;

    // Ground plane z = 0: a static btRigidBody (the raycaster accepts rigid bodies only).
    ground_shape_ = std::make_unique<btStaticPlaneShape>(btVector3(0, 0, 1), 0);
    ground_ =
        std::make_unique<btRigidBody>(btRigidBody::btRigidBodyConstructionInfo(0.0, nullptr, ground_shape_.get()));
    world_->addRigidBody(ground_.get());  // static filter: hit by the wheel rays (default filter)

    // Chassis: centre of mass at the middle of the tie rod at axle height, level, heading phi.
    const double c = std::cos(q0.phi_rad), s = std::sin(q0.phi_rad);
    const btVector3 com(q0.x_m - c * 0.5 * d.l_m, q0.y_m - s * 0.5 * d.l_m, d.R_m);
    chassis_shape_ = std::make_unique<btBoxShape>(btVector3(0.5 * d.l_m, 0.5 * d.track_m, 0.5 * d.chassis_height_m));
    btVector3 inertia(0, 0, 0);
    chassis_shape_->calculateLocalInertia(mass_, inertia);
    btRigidBody::btRigidBodyConstructionInfo ci(mass_, nullptr, chassis_shape_.get(), inertia);
    ci.m_startWorldTransform = btTransform(btQuaternion(btVector3(0, 0, 1), q0.phi_rad), com);
    ci.m_linearDamping = 0;
    ci.m_angularDamping = 0;
    chassis_ = std::make_unique<btRigidBody>(ci);
    chassis_->setActivationState(DISABLE_DEACTIVATION);
    world_->addRigidBody(chassis_.get(), kGroupChassis, 0);  // mask 0: no contacts, and the rays skip it

    // Suspension: stiffness and damping per unit chassis mass (Bullet multiplies the spring-damper
    // force by the chassis mass). Every connection point lies c above the centre of mass; each
    // wheel's rest length exceeds c by its static sag under its share of the weight (front 1/2,
    // rear 1/4 each), so at rest the chassis sits level at axle height and the wheels at z = R.
    btRaycastVehicle::btVehicleTuning tuning;
    tuning.m_suspensionStiffness = k;
    tuning.m_suspensionCompression = tuning.m_suspensionDamping = std::sqrt(3.0 * k);
    tuning.m_frictionSlip = setup.mu;
    tuning.m_maxSuspensionForce = 1e6;
    const double conn = d.R_m / 3.0;
    raycaster_ = std::make_unique<btDefaultVehicleRaycaster>(world_.get());
    make_fixed_body_once();
    vehicle_ = std::make_unique<LockedRaycastVehicle>(tuning, chassis_.get(), raycaster_.get());
    vehicle_->setCoordinateSystem(1, 2, 0);
    const btVector3 down(0, 0, -1), axle(0, -1, 0);
    const struct {
      btVector3 at;
      double load_share;
      bool front;
    } wheels[3] = {{{0.5 * d.l_m, 0, conn}, 0.5, true},
                   {{-0.5 * d.l_m, 0.5 * d.track_m, conn}, 0.25, false},
                   {{-0.5 * d.l_m, -0.5 * d.track_m, conn}, 0.25, false}};
    for (const auto& w : wheels) {
      const double rest = conn + w.load_share * g / k;
      tuning.m_maxSuspensionTravelCm = 100.0 * (rest + d.R_m);  // never binds: the ray is rest + R long
      vehicle_->addWheel(w.at, down, axle, rest, d.R_m, tuning, w.front);
    }
    world_->addVehicle(vehicle_.get());

    vehicle_->resetSuspension();
    for (int i = 0; i < 3; ++i) {
      btWheelInfo& w = vehicle_->getWheelInfo(i);
      w.m_wheelsSuspensionForce = 0;
      w.m_skidInfo = 1;
      {
        std::lock_guard<std::mutex> lock(fixed_body_mutex());
        vehicle_->rayCast(w);
      }
      vehicle_->updateWheelTransform(i, false);
      rotation_[i] = prev_rotation_[i] = 0.0;
    }
    steer_ = q0.beta_rad;
    vehicle_->setSteeringValue(steer_, kFront);
    vehicle_->updateWheelTransform(kFront, false);
    spin_cmd_ = steer_rate_ = 0.0;
    dt_ = setup.dt_s;
    steps_ = 0;
  }

  void actuate(const FrontRates& rates, const ServoDef& servo) override {
    const double spin_radps = rates.spin_radps[0], steer_radps = rates.steer_radps[0];
    spin_cmd_ = spin_radps;
    steer_rate_ = steer_radps;
    servo_now_ = servo;
  }

  void step(double dt_s) override {
    dt_ = dt_s;
    // Steering: kinematic, the commanded rate integrated over the step.
    steer_ += steer_rate_ * dt_s;
    vehicle_->setSteeringValue(steer_, kFront);

    const long settle_steps = std::lround(servo_now_.settle_s / dt_s);
    if (steps_ < settle_steps) {
      // Settling (the first settle_s after build): all wheels braked, no engine force (a wheel
      // with engine force 0 and brake 0 would roll freely).
      const double brake = mu_ * mass_ * world_->getGravity().length() * dt_s;  // impulse cap per step
      for (int i = 0; i < 3; ++i) {
        vehicle_->setBrake(brake, i);
        vehicle_->applyEngineForce(0, i);
      }
    } else {
      // The brake of a braked run: the rear wheels' rolling friction capped by the brake's torque
      // (btWheelInfo::m_brake is the impulse cap of a step: torque / R x dt); free otherwise.
      const double rear_brake = servo_now_.rear_brake_torque_max_Nm / R_ * dt_s;
      for (int i = 0; i < 3; ++i) vehicle_->setBrake(i == kFront ? 0.0 : rear_brake, i);
      // Speed loop on the front wheel's forward speed along its own heading.
      const double v_forward = forward_speed();
      const double f_max = servo_now_.spin_torque_max_Nm / R_;
      const double f = mass_ * kSpeedGain * (spin_cmd_ * R_ - v_forward);
      vehicle_->applyEngineForce(std::clamp(f, -f_max, f_max), kFront);
    }

    world_->stepSimulation(dt_s, 1, dt_s);
    ++steps_;

    for (int i = 0; i < 3; ++i) {
      vehicle_->updateWheelTransform(i, false);
      prev_rotation_[i] = rotation_[i];
    }
    // The wheel angle: Bullet's own rotation update, m_rotation += (v_hardpoint . fwd) dt / R,
    // with fwd the chassis axis (m_rotation) or, for the steered wheel, its own heading.
    for (int i = 0; i < 3; ++i) rotation_[i] = vehicle_->getWheelInfo(i).m_rotation;
    if (heading_angle_) {
      const btWheelInfo& w = vehicle_->getWheelInfo(kFront);
      const btVector3 v =
          chassis_->getVelocityInLocalPoint(w.m_raycastInfo.m_hardPointWS - chassis_->getCenterOfMassPosition());
      rotation_[kFront] = prev_rotation_[kFront] + v.dot(wheel_forward(kFront)) * dt_s / R_;
    }
  }

  RigidCarState read() const override {
    const btMatrix3x3& Rc = chassis_->getWorldTransform().getBasis();
    const btVector3 omega = chassis_->getAngularVelocity();
    RigidCarState s{};
    s.spin_joint_rad[0] = std::remainder(rotation_[kFront], 2 * M_PI);
    s.steer_rad[0] = vehicle_->getSteeringValue(kFront);
    const btVector3 p = vehicle_->getWheelTransformWS(kFront).getOrigin();
    s.x_m = p.x();
    s.y_m = p.y();
    s.z_m = p.z();
    s.phi_rad = std::atan2(Rc[1][0], Rc[0][0]);
    s.rear_z_m =
        std::min(vehicle_->getWheelTransformWS(1).getOrigin().z(), vehicle_->getWheelTransformWS(2).getOrigin().z());
    for (int i = 0; i < 3; ++i) {
      const btVector3 hub = vehicle_->getWheelTransformWS(i).getOrigin();
      const btVector3 v = chassis_->getVelocityInLocalPoint(hub - chassis_->getCenterOfMassPosition());
      const btVector3 axle = wheel_axle(i);
      // The cosmetic spin: the wheel angle's change over the last step.
      const double spin = steps_ > 0 ? (rotation_[i] - prev_rotation_[i]) / dt_ : 0.0;
      s.wheels[i] = {to_eigen(v), to_eigen(omega + axle * spin), to_eigen(axle), hub.z()};
    }
    return s;
  }

 private:
  /// The wheel's axle, pointing left (unit, world): the wheel transform's y column (Bullet's
  /// wheel basis is steering x spin x [left, forward, up] in the right/up/forward index slots).
  btVector3 wheel_axle(int i) const {
    return vehicle_->getWheelTransformWS(i).getBasis().getColumn(vehicle_->getRightAxis()).normalized();
  }

  /// The wheel's rolling direction on the ground: Bullet's m_forwardWS = normal x (-axle), the
  /// axle first projected into the ground plane.
  btVector3 wheel_forward(int i) const {
    const btVector3 n = vehicle_->getWheelInfo(i).m_raycastInfo.m_contactNormalWS;
    btVector3 right = -wheel_axle(i);
    right -= n * right.dot(n);
    return n.cross(right.normalized()).normalized();
  }

  /// The front wheel's forward speed: the chassis velocity at its centre along its heading, with
  /// the steering value just set (the wheel transform is updated for it).
  double forward_speed() {
    vehicle_->updateWheelTransform(kFront, false);
    const btVector3 hub = vehicle_->getWheelTransformWS(kFront).getOrigin();
    const btVector3 v = chassis_->getVelocityInLocalPoint(hub - chassis_->getCenterOfMassPosition());
    return v.dot(wheel_forward(kFront));
  }

  void teardown() {
    if (!world_) return;
    if (vehicle_) world_->removeVehicle(vehicle_.get());
    if (chassis_) world_->removeRigidBody(chassis_.get());
    if (ground_) world_->removeRigidBody(ground_.get());
  }

  // Declaration order = reverse destruction order: the vehicle and bodies go before the world.
  std::unique_ptr<BulletCore> core_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::unique_ptr<btCollisionShape> ground_shape_, chassis_shape_;
  std::unique_ptr<btRigidBody> ground_, chassis_;
  std::unique_ptr<btDefaultVehicleRaycaster> raycaster_;
  std::unique_ptr<btRaycastVehicle> vehicle_;
  bool heading_angle_ = true;
  double R_ = 0.3, mass_ = 1.0, mu_ = 1.0, dt_ = 1e-3;
  double steer_ = 0.0, steer_rate_ = 0.0, spin_cmd_ = 0.0;
  double rotation_[3] = {0, 0, 0}, prev_rotation_[3] = {0, 0, 0};
  ServoDef servo_now_;
  long steps_ = 0;
};

/// The benchmarks' raw loop (engines/raw_car.hpp): BulletRaycastCar's world and vehicle, the steering
/// left at the start beta, stepSimulation directly. Held: every wheel braked. Driven: the engine
/// force of a game's speed loop on Bullet's own vehicle speed (getCurrentSpeedKmHour, the chassis
/// velocity along its forward axis), M x 160/s x (target - speed), capped like the adapter's.
class RawRaycastCar final : public RawCar {
 public:
  RawRaycastCar(const Settings& s, const CarSetup& setup, const car::Config& q0) : car_(s), dt_s_(setup.dt_s) {
    car_.reset(setup, q0);
  }

  void run(long steps, double spin_radps) override {
    const ServoDef& servo = car_.servo_;  // the run's own limits (ServoDef::for_car)
    btRaycastVehicle& v = *car_.vehicle_;
    btDiscreteDynamicsWorld& world = *car_.world_;
    if (spin_radps == 0.0) {
      const double brake = car_.mu_ * car_.mass_ * world.getGravity().length() * dt_s_;
      for (int i = 0; i < 3; ++i) {
        v.setBrake(brake, i);
        v.applyEngineForce(0, i);
      }
      for (long k = 0; k < steps; ++k) world.stepSimulation(dt_s_, 1, dt_s_);
      return;
    }
    for (int i = 0; i < 3; ++i) v.setBrake(0, i);
    const double target_mps = spin_radps * car_.R_, f_max = servo.spin_torque_max_Nm / car_.R_;
    for (long k = 0; k < steps; ++k) {
      const double f = car_.mass_ * kSpeedGain * (target_mps - v.getCurrentSpeedKmHour() / 3.6);
      v.applyEngineForce(std::clamp(f, -f_max, f_max), kFront);
      world.stepSimulation(dt_s_, 1, dt_s_);
    }
  }

  Eigen::Vector2d front_xy_m() const override {
    car_.vehicle_->updateWheelTransform(kFront, false);
    const btVector3 p = car_.vehicle_->getWheelTransformWS(kFront).getOrigin();
    return {p.x(), p.y()};
  }

 private:
  BulletRaycastCar car_;
  double dt_s_;
};

}  // namespace

std::unique_ptr<RawCar> make_raw_bullet_raycast_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<RawRaycastCar>(s, setup, q0);
}

EngineInfo bullet_raycast_engine() {
  return {
      .name = "bullet-raycast",
      .library = "Bullet",
      .version = fmt::format("{} (double)", LIFTCHECK_BULLET_VERSION),
      .description =
          "Bullet btRaycastVehicle: ray-cast wheels on a spring-damper suspension, per-wheel side impulses, engine "
          "force on the front wheel",
      .color = "#9467bd",
      .make_car = [](const Settings& s) { return std::make_unique<BulletRaycastCar>(s); },
      .make_disks = {},
      .contact_dynamics = true,
      .settings =
          {{"precision", "double (bullet-float64)"},
           {"stepper",
            "btDiscreteDynamicsWorld, stepSimulation(dt, 1, dt); the vehicle is an action run after integration"},
           {"contact forces", kContactForcesNotRead},
           {"vehicle",
            "btRaycastVehicle with btDefaultVehicleRaycaster, setCoordinateSystem(1, 2, 0); 3 wheels: front (steered, "
            "driven) at the front-axle centre, rear (passive; setBrake in a braked run) at the rear axle +-track/2; "
            "wheel direction -z, axle -y"},
           {"chassis",
            "box l x track x height of the car's total mass (chassis + 3 wheels + knuckle), centre of mass at the "
            "middle of the tie rod at axle height, collides with nothing; ground: static btRigidBody plane"},
           {"suspension",
            "stiffness k per unit chassis mass (knob), damping sqrt(3k) per unit mass in compression and relaxation "
            "(173 at k = 1e4), max force 1e6 N; connection points R/3 above the centre of mass, rest lengths R/3 + "
            "static sag (g/(2k) front, g/(4k) rear), so the chassis starts level and at rest with wheel centres at z = "
            "R; max travel rest + R (never binds)"},
           {"friction",
            "one Jacobi side-impulse pass per wheel per step (resolveSingleBilateral with Bullet's hard-coded 0.2 "
            "damping, 0.2 of the impulse that cancels the wheel's lateral velocity): not a no-slip model, the lateral "
            "slip carries the centripetal force; m_frictionSlip = mu caps the combined impulse at mu x suspension "
            "force x dt; roll influence 0.1 (Bullet default)"},
           {"speed",
            "engine force on the front wheel F = M x 160/s x (spin command x R - forward speed of the front wheel "
            "centre along the wheel's heading), capped at the servo's torque limit / R (1.5 mu N of the front wheel: "
            "353 N for the default car); no feed-forward; 160/s = 4 x the 40/s angle servo: the cascade is critically "
            "damped"},
           {"steering",
            "kinematic: setSteeringValue with the commanded steering rate integrated over each step (left positive)"},
           {"hold",
            "for the first settle_s (0.5 s) after build all three wheels are braked (setBrake, impulse cap mu M g dt "
            "per wheel) with engine force 0; afterwards no brakes"},
           {"wheel angle",
            "no spin state (along-slip not measured): heading = the front wheel's travel along its own heading / R, "
            "integrated like Bullet's m_rotation; m_rotation = Bullet's own value, which projects the velocity on the "
            "chassis axis, so the steered wheel turns cos(beta) too slowly; the spin reported for the slip metrics is "
            "the angle's change per step (m_deltaRotation before Bullet's 0.99 decay)"},
           {"stability",
            "the suspension is explicit: at k = 1e4 the run diverges for dt >= 2 ms (a period-2 oscillation from about "
            "1.8 ms); smaller k allows larger steps"},
           {"threads",
            "Bullet writes the same constants into one function-static btRigidBody (btActionInterface::getFixedBody, "
            "the vehicle's ground object) from every vehicle on every ray cast and reads it in the friction pass: the "
            "body is made once before the first vehicle, and each vehicle's action (ray casts, suspension, friction) "
            "holds a process-wide lock, so concurrent runs take turns at it; the numbers do not depend on what else "
            "runs"}},
      .knobs = {SettingSpec{{.key = "suspension_stiffness",
                             .kind = ParamKind::kNumber,
                             .default_text = "10000",
                             .unit = "1",
                             .help = "suspension stiffness per unit chassis mass, 1/s^2 "
                                     "(btVehicleTuning::m_suspensionStiffness); damping follows as sqrt(3k)",
                             .min = 0,
                             .min_exclusive = true,
                             .max = 1e6},
                            Vehicle::kCar},
                SettingSpec{{.key = "wheel_angle",
                             .kind = ParamKind::kChoice,
                             .default_text = "heading",
                             .help = "the realized wheel angle: the front wheel's travel along its heading / R, or "
                                     "Bullet's m_rotation (travel along the chassis axis / R)",
                             .choices = {"heading", "m_rotation"}},
                            Vehicle::kCar}},
      .brakes = true,
      .make_raw_car = make_raw_bullet_raycast_car};
}

}  // namespace liftcheck
