// The fault-injection suite: engines broken on purpose, each of which the validation must flag.
// Every fault is run through the whole default catalogue exactly as `validate` runs an engine;
// it must leave at least one run not as expected, and the test names the metric built to catch it.
// A fault that slips through is a hole in the scenarios, to be closed there, not here.
#include <gtest/gtest.h>

#include <cmath>
#include <deque>
#include <functional>
#include <iostream>

#include "engines/driven_disks.hpp"
#include "engines/ode/ode_car_model.hpp"
#include "engines/ode/ode_disks.hpp"
#include "harness/runner.hpp"
#include "models/e2.hpp"
#include "models/lift.hpp"

using namespace liftcheck;

namespace {

// ---- disk faults ---------------------------------------------------------------------------

/// No physics at all: positions are placed from outside (M moved by its command times dt, N put
/// on its path), contact when the centres are within 2, and no contact response.
class NoPhysicsDisks final : public DrivenDisks {
 protected:
  void build(const DiskSetup&, const disks::Vec2& cM0, const disks::Vec2& cN0) override {
    s_ = {cM0, cN0, Eigen::Vector3d::Zero()};  // placed, never turned
  }
  StepContacts step(const disks::Vec2& vM, const disks::Vec2& cN_next, const disks::Vec2&, double dt) override {
    StepContacts c;
    const double d = (s_.cM - s_.cN).norm();
    if (d <= 2.0) c = {1, 2.0 - d};
    s_.cM += vM * dt;
    s_.cN = cN_next;
    return c;
  }
  State read() const override { return s_; }

 private:
  State s_;
};

/// ODE whose contact report reaches the caller one step late (the physics is untouched).
class LateContactDisks final : public OdeDisks {
 protected:
  StepContacts step(const disks::Vec2& vM, const disks::Vec2& cN_next, const disks::Vec2& vN, double dt) override {
    const StepContacts now = OdeDisks::step(vM, cN_next, vN, dt);
    const StepContacts late = previous_;
    previous_ = now;
    return late;
  }

 private:
  StepContacts previous_;
};

/// ODE with a 2 cm collision margin: each sphere's collision shape is 1 cm larger than the disk.
class MarginDisks final : public OdeDisks {
 protected:
  void build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) override {
    DiskSetup wide = setup;
    wide.radius_m += 0.01;
    OdeDisks::build(wide, cM0, cN0);
  }
};

/// ODE whose contact response starts one step after contact is first seen (reported on time).
class LateResponseDisks final : public OdeDisks {
 protected:
  bool keep_contact(dContact&) override { return seen_before_ || !(seen_before_ = true); }

 private:
  bool seen_before_ = false;
};

/// ODE whose contacts carry a depth 100 times too deep (a units slip): the response overshoots.
class DeepContactDisks final : public OdeDisks {
 protected:
  bool keep_contact(dContact& c) override {
    c.geom.depth *= 100.0;
    return true;
  }
};

// ---- disk faults after contact and before it (issue 21, classes 5 and 6) ---------------------

/// A contact that sticks: ODE's M-N contacts get unbounded Coulomb friction (mu = infinity, where
/// the disks are frictionless); M cannot spin (OdeDisks holds it): M is glued to N where it touched
/// instead of sliding over it.
class StickingContactDisks final : public OdeDisks {
 protected:
  bool keep_contact(dContact& c) override {
    c.surface.mu = dInfinity;
    return true;
  }
};

/// Friction between the disks (Coulomb, mu = 0.5) where they are frictionless; M's spin held or,
/// with `hold_spin` false, left free, as an adapter that forgets to hold it would: M then rolls on
/// N and its path hardly changes, but it turns.
class FrictionDisks final : public OdeDisks {
 public:
  explicit FrictionDisks(bool hold_spin) : OdeDisks(OdeStepper{}, hold_spin) {}

 protected:
  bool keep_contact(dContact& c) override {
    c.surface.mode |= dContactApprox1;  // Coulomb: mu times the normal force
    c.surface.mu = 0.5;
    return true;
  }
};

/// An elastic contact: ODE's restitution at 1 (dContactBounce), where the response is inelastic.
class BouncingContactDisks final : public OdeDisks {
 protected:
  bool keep_contact(dContact& c) override {
    c.surface.mode |= dContactBounce;
    c.surface.bounce = 1.0;
    c.surface.bounce_vel = 0.0;
    return true;
  }
};

/// A velocity motor one step late: each step ODE's motor gets the previous step's command (M
/// starts at rest, so the first step's is zero).
class LateMotorDisks final : public OdeDisks {
 protected:
  StepContacts step(const disks::Vec2& vM, const disks::Vec2& cN_next, const disks::Vec2& vN, double dt) override {
    const disks::Vec2 late = previous_;
    previous_ = vM;
    return OdeDisks::step(late, cN_next, vN, dt);
  }

 private:
  disks::Vec2 previous_ = disks::Vec2::Zero();
};

// ---- car faults ----------------------------------------------------------------------------

Settings ode_defaults() { return find_engine("ode")->defaults(Vehicle::kCar); }

/// Wheels that slip 1% along the rolling direction: the contact's surface moves along the first
/// friction direction at 1% of the wheel's ground speed (dContactMotion1).
class SlippingCar final : public OdeCar {
 public:
  SlippingCar() : OdeCar(ode_defaults()) {}

 protected:
  void contact_surface(dContact& c, dBodyID wheel) const override {
    const dReal* v = dBodyGetLinearVel(wheel);
    c.surface.mode |= dContactMotion1;
    c.surface.motion1 = 0.01 * (v[0] * c.fdir1[0] + v[1] * c.fdir1[1]);
  }
};

/// The same 1% slip in a configuration with listed known failures (ode-quick, whose friction
/// already creeps by up to 1.9 mm/s): judged under that configuration's name, so its known
/// failures apply, the fault must still be flagged as worse than known.
Settings quick_defaults() { return find_engine("ode-quick")->defaults(Vehicle::kCar); }
class QuickSlippingCar final : public OdeCar {
 public:
  QuickSlippingCar() : OdeCar(quick_defaults(), OdeStepper::quick_from(quick_defaults())) {}

 protected:
  void contact_surface(dContact& c, dBodyID wheel) const override {
    const dReal* v = dBodyGetLinearVel(wheel);
    c.surface.mode |= dContactMotion1;  // along ODE's own first friction direction (no fdir1 here)
    c.surface.motion1 = 0.01 * std::hypot(v[0], v[1]);
  }
};

/// Lateral grip that leaks: force-dependent slip across the rolling direction (dContactSlip2,
/// 1 mm/s per newton).
class LeakyCar final : public OdeCar {
 public:
  LeakyCar() : OdeCar(ode_defaults()) {}

 protected:
  void contact_surface(dContact& c, dBodyID) const override {
    c.surface.mode |= dContactSlip2;
    c.surface.slip2 = 1e-3;
  }
};

/// Friction fixed to the world axes (ODE's default pyramid axes instead of the wheel's).
std::unique_ptr<CarEngine> world_friction_car() {
  Settings s = ode_defaults();
  s["friction_dirs"] = "world";
  return std::make_unique<OdeCar>(s);
}

/// A heading that lags half a step: each reported heading is the mean of this step's and the last.
class LaggingCar final : public OdeCar {
 public:
  LaggingCar() : OdeCar(ode_defaults()) {}

 protected:
  RigidCarState read() const override {
    RigidCarState s = OdeCar::read();
    const double now = s.phi_rad;
    if (has_previous_) s.phi_rad = now + 0.5 * std::remainder(previous_phi_ - now, 2.0 * M_PI);
    previous_phi_ = now;
    has_previous_ = true;
    return s;
  }

 private:
  mutable double previous_phi_ = 0.0;
  mutable bool has_previous_ = false;
};

/// A car pushed forward by 20 kN from t = 1 s: a blow-up, which the stepping loop must stop as an
/// error saying what and when, not score as a bad circle.
class RunawayCar final : public OdeCar {
 public:
  RunawayCar() : OdeCar(ode_defaults()) {}

 protected:
  void step(double dt_s) override {
    if ((t_s_ += dt_s) > 1.5) dBodyAddRelForce(chassis(), 2e4, 0, 0);  // settling takes 0.5 s
    OdeCar::step(dt_s);
  }

 private:
  double t_s_ = 0.0;
};

/// ODE whose contact depth is a million times too deep: M is shot away at the first touch.
class ExplodingContactDisks final : public OdeDisks {
 protected:
  bool keep_contact(dContact& c) override {
    c.geom.depth *= 1e6;
    return true;
  }
};

// ---- car faults of time, gravity, friction and the pose's instant (issue 21) ----------------

/// A pose reported one engine step late (a previous step's transform, as motion-state
/// interpolation or a read before the step's sync gives): the wheel and steering angles are this
/// step's, the chassis pose the step before's.
class StalePoseCar final : public OdeCar {
 public:
  StalePoseCar() : OdeCar(ode_defaults()) {}

 protected:
  RigidCarState read() const override {
    RigidCarState s = OdeCar::read();
    const double now[3] = {s.x_m, s.y_m, s.phi_rad};
    if (has_previous_) s.x_m = previous_[0], s.y_m = previous_[1], s.phi_rad = previous_[2];
    std::copy(now, now + 3, previous_);
    has_previous_ = true;
    return s;
  }
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    has_previous_ = false;
    OdeCar::build(setup, d, q0);
  }

 private:
  mutable double previous_[3] = {0.0, 0.0, 0.0};
  mutable bool has_previous_ = false;
};

/// An internal step 1% longer than the dt it was given (a fixed internal step, a substepping
/// misuse): the engine's time runs 1% fast against the caller's clock.
class LongStepCar final : public OdeCar {
 public:
  LongStepCar() : OdeCar(ode_defaults()) {}

 protected:
  void step(double dt_s) override { OdeCar::step(1.01 * dt_s); }
};

/// ODE's car built from a setup or a car that `edit` has changed: what an adapter that misreads its
/// request builds.
class MisbuiltCar final : public OdeCar {
 public:
  using Edit = std::function<void(CarSetup&, TricycleDef&)>;
  explicit MisbuiltCar(Edit edit) : OdeCar(ode_defaults()), edit_(std::move(edit)) {}

 protected:
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    CarSetup s = setup;
    TricycleDef built = d;
    edit_(s, built);
    OdeCar::build(s, built, q0);
  }

 private:
  Edit edit_;
};

/// Gravity not tilted: the engine keeps (0, 0, -g) whatever direction the scenario gives.
void upright_gravity(CarSetup& s, TricycleDef&) { s.gravity_dir_W = -Eigen::Vector3d::UnitZ(); }
/// Gravity 5% weak: the engine builds its world with 0.95 g.
void weak_gravity(CarSetup& s, TricycleDef&) { s.gravity_mps2 *= 0.95; }
/// A body's mass left out: the steering knuckle (2 kg of the car's 48) built with a milligram (ODE's
/// mass functions want a positive mass), as an adapter that forgot it would build it. Coulomb's
/// slide does not depend on the mass; the load the ground carries does.
void knuckle_mass_left_out(CarSetup&, TricycleDef& d) { d.knuckle_mass_kg = 1e-6; }

/// Friction `factor` times the scenario's mu (a combine rule or a unit slip): 0.8 is an effective
/// friction 20% below the stated one; 10 a car that keeps its grip past the limit.
class ScaledFrictionCar final : public OdeCar {
 public:
  explicit ScaledFrictionCar(double factor) : OdeCar(ode_defaults()), factor_(factor) {}

 protected:
  void contact_surface(dContact& c, dBodyID) const override { c.surface.mu *= factor_; }

 private:
  double factor_;
};

/// A servo `steps` engine steps off in time: it aims the steering (`steering`) or the drive at the
/// command of t + steps dt instead of t, as a steering servo a step early (+1) or a drive motor a
/// step late (-1) would; the other angle is servoed on time.
class ShiftedServoCar final : public OdeCar {
 public:
  ShiftedServoCar(bool steering, double steps) : OdeCar(ode_defaults()), steering_(steering), steps_(steps) {}

 protected:
  double servo_instant_s(double t_s, bool steering) const override {
    return steering == steering_ ? t_s + steps_ * setup_.dt_s : t_s;
  }

 private:
  bool steering_;
  double steps_;
};

/// No contact physics at all: the car placed on the exact lift of the commanded path, claiming to
/// be a rigid-body engine whose wheels realize the command and never slip.
class KinematicCar final : public CarEngine {
 public:
  void reset(const CarSetup& setup, const car::Config& q0) override { setup_ = setup, q0_ = q0; }
  std::vector<car::TimedConfig> drive(const car::BasePath& path) override {
    car::LiftDef def;
    def.sample_dt_s = setup_.sample_dt_s;
    simulated_s_ += path.duration_s();
    return car::lift(setup_.car, path, q0_, def);
  }
  std::vector<WheelSlip> slip() const override {
    return {WheelSlip{"front"}, WheelSlip{"rear left"}, WheelSlip{"rear right"}};
  }
  double simulated_s() const override { return simulated_s_; }

 private:
  CarSetup setup_;
  car::Config q0_;
  double simulated_s_ = 0.0;
};

/// A car placed kinematically, as an engine that switches a vehicle to a kinematic body where it
/// expects no sliding: the commanded wheel rates move it along the exact flows of the no-slip
/// connection (H_beta half a step, H_alpha, H_beta half a step), so its wheels roll without
/// slipping and its pose is the lift of its shape. Its contact report holds the static load its
/// suspension would carry, the car's weight, and no force along the ground.
class PlacedCar final : public RigidCar {
 public:
  PlacedCar() : RigidCar(Settings{}) {}

 protected:
  void build(const CarSetup& setup, const TricycleDef&, const car::Config& q0) override {
    car_ = setup.car, q_ = q0, spin_rad_ = 0.0, spin_radps_ = steer_radps_ = 0.0;
  }
  void actuate(const FrontRates& rates, const ServoDef&) override {
    spin_radps_ = rates.spin_radps[0], steer_radps_ = rates.steer_radps[0];
  }
  void step(double dt_s) override {
    q_ = car::flow_beta(car::flow_alpha(car_, car::flow_beta(q_, 0.5 * steer_radps_ * dt_s), spin_radps_ * dt_s),
                        0.5 * steer_radps_ * dt_s);
    spin_rad_ += spin_radps_ * dt_s;
  }
  RigidCarState read() const override {
    RigidCarState s{};
    s.spin_joint_rad[0] = e2::wrap_angle(spin_rad_), s.steer_rad[0] = q_.beta_rad;
    s.x_m = q_.x_m, s.y_m = q_.y_m, s.z_m = s.rear_z_m = car_.R_m, s.phi_rad = q_.phi_rad;
    const double R = car_.R_m, phi = q_.phi_rad, phi_rate = R * spin_radps_ * std::sin(q_.beta_rad) / car_.l_m;
    const Eigen::Vector3d z = Eigen::Vector3d::UnitZ();
    const auto heading = [](double a) { return Eigen::Vector3d(std::cos(a), std::sin(a), 0.0); };
    const auto axle = [](double a) { return Eigen::Vector3d(-std::sin(a), std::cos(a), 0.0); };
    // (3.3): the front wheel rolls at R alpha' along its heading phi + beta; the rear-axle centre
    // moves along phi at R alpha' cos(beta), each rear hub -+ (track/2) phi' beside it.
    const double front_mps = R * spin_radps_, rear_mps = front_mps * std::cos(q_.beta_rad);
    s.wheels[0] = {front_mps * heading(phi + q_.beta_rad),
                   spin_radps_ * axle(phi + q_.beta_rad) + (phi_rate + steer_radps_) * z, axle(phi + q_.beta_rad), R};
    for (int side : {1, 2}) {
      const double v = rear_mps - (side == 1 ? 1.0 : -1.0) * 0.5 * def_.track_m * phi_rate;
      s.wheels[side] = {v * heading(phi), v / R * axle(phi) + phi_rate * z, axle(phi), R};
    }
    s.v_chassis_W = 0.5 * (front_mps * heading(phi + q_.beta_rad) + rear_mps * heading(phi));  // midway
    return s;
  }
  std::optional<Eigen::Vector3d> ground_force_W() const override {
    return Eigen::Vector3d(0.0, 0.0, -car_mass_kg(def_) * setup_.gravity_W().z());
  }

 private:
  car::CarDef car_;
  car::Config q_;
  double spin_rad_ = 0.0, spin_radps_ = 0.0, steer_radps_ = 0.0;
};

/// Placed kinematically (PlacedCar) wherever the path's exact lift asks less than half the grip
/// (the front-axle centre's largest acceleration below mu g / 2), and ODE's car elsewhere and for
/// four wheels.
class KinematicAtLowGripCar final : public CarEngine {
 public:
  void reset(const CarSetup& setup, const car::Config& q0) override { setup_ = setup, q0_ = q0; }
  std::vector<car::TimedConfig> drive(const car::BasePath& path) override {
    used_ = setup_.wheels == 3 && grip_use(path) < 0.5 ? static_cast<CarEngine*>(&placed_) : &ode_;
    used_->reset(setup_, q0_);
    return used_->drive(path);
  }
  std::vector<WheelSlip> slip() const override { return used_->slip(); }
  double simulated_s() const override { return placed_.simulated_s() + ode_.simulated_s(); }
  GroundLoad ground_load() const override { return used_->ground_load(); }

 private:
  /// The largest acceleration of the front-axle centre along the exact lift, over mu g (second
  /// differences at 10 ms).
  double grip_use(const car::BasePath& path) const {
    car::LiftDef def;
    def.sample_dt_s = 0.01;
    const std::vector<car::TimedConfig> q = car::lift(setup_.car, path, q0_, def);
    double a_max = 0.0;
    for (size_t k = 1; k + 1 < q.size(); ++k) {
      const double h = q[k + 1].t_s - q[k].t_s;
      const Eigen::Vector2d a(q[k + 1].q.x_m - 2 * q[k].q.x_m + q[k - 1].q.x_m,
                              q[k + 1].q.y_m - 2 * q[k].q.y_m + q[k - 1].q.y_m);
      a_max = std::max(a_max, a.norm() / (h * h));
    }
    return a_max / (setup_.mu * setup_.gravity_mps2);
  }
  CarSetup setup_;
  car::Config q0_;
  PlacedCar placed_;
  OdeCar ode_{ode_defaults()};
  CarEngine* used_ = &ode_;
};

/// ODE's car whose contact report breaks after 1 s of stepping: a NaN in its x component, or no
/// forces at all.
class BrokenReportCar final : public OdeCar {
 public:
  explicit BrokenReportCar(bool nan) : OdeCar(ode_defaults()), nan_(nan) {}

 protected:
  std::optional<Eigen::Vector3d> ground_force_W() const override {
    std::optional<Eigen::Vector3d> f = OdeCar::ground_force_W();
    if (stepped_s_ < 1.0) return f;
    if (!nan_) return std::nullopt;
    f->x() = NAN;
    return f;
  }

 private:
  bool nan_;
};

/// ODE's car whose wheel contacts' first friction row lies along the contact point's slip (the
/// wheel's material point's velocity along the ground) and none across it wherever it slips
/// faster than 1 mm/s: a sliding contact's friction then opposes its slip with mu N, Coulomb's
/// isotropic law, and a rolling one keeps the wheel's rows. Without `along_slip` the rows stay fixed on the wheel, each
/// bounded by mu N apart: the per-axis friction pyramid (ODE as shipped).
class FrictionRowsCar final : public OdeCar {
 public:
  explicit FrictionRowsCar(bool along_slip) : OdeCar(ode_defaults()), along_slip_(along_slip) {}

 protected:
  void contact_surface(dContact& c, dBodyID wheel) const override {
    if (!along_slip_) return;
    dVector3 v;
    dBodyGetPointVel(wheel, c.geom.pos[0], c.geom.pos[1], c.geom.pos[2], v);
    const Eigen::Vector3d n(c.geom.normal[0], c.geom.normal[1], c.geom.normal[2]);
    Eigen::Vector3d slip(v[0], v[1], v[2]);
    slip -= slip.dot(n) * n;
    if (slip.norm() < 1e-3) return;
    slip.normalize();
    c.surface.mode |= dContactFDir1 | dContactMu2;
    c.surface.mu2 = 0.0;  // nothing across the slip: the friction force lies along it, mu N
    for (int k = 0; k < 3; ++k) c.fdir1[k] = slip[k];
  }

 private:
  bool along_slip_;
};

/// ODE's car that declares brakes and ignores them: its rear wheels roll freely in a braked run.
class BrakeIgnoredCar final : public OdeCar {
 public:
  BrakeIgnoredCar() : OdeCar(ode_defaults()) {}

 protected:
  void actuate(const FrontRates& rates, const ServoDef& servo) override {
    ServoDef unbraked = servo;
    unbraked.rear_brake_torque_max_Nm = 0.0;
    OdeCar::actuate(rates, unbraked);
  }
};

/// A broken engine that claims contact dynamics, like the rigid-body engines it imitates.
EngineInfo fault(const std::string& name) {
  EngineInfo e;
  e.name = name;
  e.version = "0";
  e.description = "fault injection";
  e.contact_dynamics = true;
  return e;
}

EngineInfo disk_fault(const std::string& name, std::function<std::unique_ptr<DiskEngine>()> make) {
  EngineInfo e = fault(name);
  e.make_disks = [make](const Settings&) { return make(); };
  return e;
}

/// A car fault, judged under the name of the configuration it breaks when `judged_as` is given
/// (so that configuration's known failures apply, and the fault must show beyond them).
EngineInfo car_fault(const std::string& name, std::function<std::unique_ptr<CarEngine>()> make,
                     const std::string& judged_as = "") {
  EngineInfo e = fault(judged_as.empty() ? name : judged_as);
  e.description = "fault injection: " + name;
  e.make_car = [make](const Settings&) { return make(); };
  return e;
}

/// Every scenario of the catalogue at its defaults, as `validate` runs them.
std::vector<RunRecord> validate(const EngineInfo& e) {
  std::vector<RunRecord> runs;
  for (const Scenario& s : scenarios()) runs.push_back(run_scenario(s, e));
  return runs;
}

/// The runs not as expected, and whether `metric` failed in `scenario`.
struct Flagged {
  int unexpected = 0;
  bool metric_failed = false;
  std::string summary;
};

Flagged judge(const EngineInfo& e, const std::string& scenario, const std::string& metric) {
  Flagged v;
  for (const RunRecord& r : validate(e)) {
    if (r.status == Status::kSkip) continue;
    // A negative control fails on every engine with contact dynamics: the expectations list it for
    // each real configuration; a fault engine is judged as the configuration it breaks would be.
    if (find_scenario(r.scenario)->negative_control && r.status == Status::kFail) continue;
    if (!r.as_expected()) {
      ++v.unexpected;
      v.summary += r.scenario + ": " + r.message + "\n";
    }
    // Where the run is a listed known failure, the metric must fail beyond its listing.
    if (r.scenario == scenario)
      for (const Metric& m : r.metrics)
        if (m.name == metric && !m.pass) {
          std::cout << "  " << e.description << ": " << metric << " in " << scenario << " error " << m.compared_error()
                    << " (" << (m.kind == TolKind::kRelative ? "relative" : "absolute") << ") against tolerance "
                    << m.tolerance << (r.expectation ? " (a listed known failure of the configuration it breaks)" : "")
                    << "\n";
          bool beyond = !r.expectation.has_value();
          for (const auto& b : r.decision.beyond) beyond = beyond || b.substr(0, b.find(' ')) == metric;
          v.metric_failed = v.metric_failed || beyond;
        }
  }
  return v;
}

/// The fault is flagged by validate, and `metric` in `scenario` is among what flags it.
void expect_flagged(const EngineInfo& e, const std::string& scenario, const std::string& metric) {
  const Flagged v = judge(e, scenario, metric);
  EXPECT_GT(v.unexpected, 0) << e.description << " slipped through every scenario";
  EXPECT_TRUE(v.metric_failed) << e.description << ": " << metric << " in " << scenario
                               << " did not flag it; flagged:\n"
                               << v.summary;
}

}  // namespace

TEST(Faults, DiskEngineWithoutPhysics) {
  const Flagged v = judge(disk_fault("no-physics", [] { return std::make_unique<NoPhysicsDisks>(); }), "disks.repel",
                          "penetration_max");
  // Every disk scenario in which the disks meet must fail it (without contact, an engine that
  // realises the commanded velocity exactly is indistinguishable from placing M by hand).
  for (const char* name : {"disks.repel", "disks.linear", "disks.forced"}) {
    const RunRecord r =
        run_scenario(*find_scenario(name), disk_fault("no-physics", [] { return std::make_unique<NoPhysicsDisks>(); }));
    EXPECT_EQ(r.status, Status::kFail) << name << ": " << r.message;
  }
}

TEST(Faults, DiskContactReportedOneStepLate) {
  expect_flagged(disk_fault("late-contact", [] { return std::make_unique<LateContactDisks>(); }), "disks.repel",
                 "contact_missed");
}

TEST(Faults, DiskCollisionMarginOf2cm) {
  expect_flagged(disk_fault("margin", [] { return std::make_unique<MarginDisks>(); }), "disks.repel",
                 "contact_report_gap");
}

TEST(Faults, DiskContactResponseOneStepLate) {
  expect_flagged(disk_fault("late-response", [] { return std::make_unique<LateResponseDisks>(); }), "disks.repel",
                 "overlap_growth");
}

TEST(Faults, DiskContactDepthHundredfold) {
  expect_flagged(disk_fault("deep-contact", [] { return std::make_unique<DeepContactDisks>(); }), "disks.repel",
                 "contact_depth_error");
}

TEST(Faults, DiskContactSticks) {
  expect_flagged(disk_fault("sticking-contact", [] { return std::make_unique<StickingContactDisks>(); }),
                 "disks.oblique", "contact_path_error");
}

TEST(Faults, FrictionBetweenTheDisks) {
  expect_flagged(disk_fault("disk-friction", [] { return std::make_unique<FrictionDisks>(true); }), "disks.oblique",
                 "contact_path_error");
}

TEST(Faults, FrictionBetweenTheDisksWithMsSpinFree) {
  expect_flagged(disk_fault("disk-friction-spin-free", [] { return std::make_unique<FrictionDisks>(false); }),
                 "disks.oblique", "spin_M_max");
}

TEST(Faults, DiskContactBounces) {
  expect_flagged(disk_fault("bouncing-contact", [] { return std::make_unique<BouncingContactDisks>(); }),
                 "disks.oblique", "contact_duration");
}

TEST(Faults, DiskVelocityMotorOneStepLate) {
  expect_flagged(disk_fault("late-motor", [] { return std::make_unique<LateMotorDisks>(); }), "disks.repel",
                 "step_displacement");
}

TEST(Faults, WheelsSlipOnePercentAlongTheRollingDirection) {
  expect_flagged(car_fault(
                     "slip-1pct", [] { return std::make_unique<SlippingCar>(); }, "ode"),
                 "car.circle", "slip_along_max");
}

TEST(Faults, SlipWorseThanAKnownFailureIsFlagged) {
  const EngineInfo e = car_fault("ode-quick", [] { return std::make_unique<QuickSlippingCar>(); });
  expect_flagged(e, "car.circle", "slip_along_max");
  // And car.circle itself, a listed known failure on ode-quick, is what flags it: its slip is
  // above the ceiling the expectations give.
  const RunRecord r = run_scenario(*find_scenario("car.circle"), e);
  ASSERT_TRUE(r.expectation.has_value());
  EXPECT_FALSE(r.as_expected()) << r.message;
  bool above = false;
  for (const auto& p : r.decision.beyond)
    above = above ||
            (p.substr(0, p.find(' ')) == "slip_along_max" && p.find("above its known ceiling") != std::string::npos);
  EXPECT_TRUE(above) << r.message;
}

TEST(Faults, LateralGripLeaks) {
  expect_flagged(car_fault(
                     "leaky-grip", [] { return std::make_unique<LeakyCar>(); }, "ode"),
                 "car.circle", "slip_across_max");
}

TEST(Faults, FrictionFixedToWorldAxes) {
  expect_flagged(car_fault("world-friction", world_friction_car, "ode"), "car.covariance", "spread_xy");
}

TEST(Faults, HeadingLagsHalfAStep) {
  expect_flagged(car_fault(
                     "heading-lag", [] { return std::make_unique<LaggingCar>(); }, "ode"),
                 "car.circle", "heading_residual");
}

// The pose one engine step late: at every sample the chassis is one step's travel (v dt, 0.5 mm
// at 0.5 m/s and 1 ms) behind the lift of the wheel angles of that same sample.
TEST(Faults, PoseReportedOneStepLate) {
  const EngineInfo e = car_fault(
      "stale-pose", [] { return std::make_unique<StalePoseCar>(); }, "ode");
  expect_flagged(e, "car.circle", "realized_lift_error");
  expect_flagged(e, "car.cycle", "realized_lift_error");
}

// Time at the wrong rate: the Coulomb slide's acceleration scales with the square of the clock
// ratio (+2% for a step 1% long, against a tolerance of 0.2%).
TEST(Faults, EngineStepOnePercentLongerThanDt) {
  expect_flagged(car_fault(
                     "long-step", [] { return std::make_unique<LongStepCar>(); }, "ode"),
                 "car.coulomb", "slide_accel");
}

TEST(Faults, GravityNotTilted) {
  expect_flagged(car_fault(
                     "upright-gravity", [] { return std::make_unique<MisbuiltCar>(upright_gravity); }, "ode"),
                 "car.coulomb", "slide_accel");
}

// Gravity 5% weak: the slide's g (sin - mu cos) is 5% short, the ground carries 5% less than the
// car's weight in every car scenario, at rest and over the drive (Newton's third law, from ODE's
// own contact joint feedback), and the parked car's grip holds 5% less than m g sin(theta).
TEST(Faults, GravityFivePercentWeak) {
  const EngineInfo e = car_fault(
      "weak-gravity", [] { return std::make_unique<MisbuiltCar>(weak_gravity); }, "ode");
  expect_flagged(e, "car.coulomb", "slide_accel");
  expect_flagged(e, "car.circle", "load_at_rest");
  expect_flagged(e, "car.circle", "load_over_drive");
  expect_flagged(e, "car.cycle", "load_over_drive");
  expect_flagged(e, "car.slope", "hold_at_rest");
}

// 2 kg of 48 left out: the ground carries 4.2% less than the declared weight.
TEST(Faults, KnuckleMassLeftOut) {
  const EngineInfo e = car_fault(
      "knuckle-massless", [] { return std::make_unique<MisbuiltCar>(knuckle_mass_left_out); }, "ode");
  expect_flagged(e, "car.circle", "load_at_rest");
  expect_flagged(e, "car.slope", "load_over_drive");
}

// mu 0.24 for 0.3 on the 0.5 rad slope: the slide accelerates 24% faster.
TEST(Faults, EffectiveFrictionTwentyPercentBelowMu) {
  expect_flagged(car_fault(
                     "low-friction", [] { return std::make_unique<ScaledFrictionCar>(0.8); }, "ode"),
                 "car.coulomb", "slide_accel");
}

// The kinematic car follows the lift where its centre of mass needs 2.7 mu g, and never slides
// down a slope steeper than its friction angle.
TEST(Faults, KinematicCarOnTheExactLift) {
  const EngineInfo e = car_fault("kinematic", [] { return std::make_unique<KinematicCar>(); });
  expect_flagged(e, "car.beyond-grip", "com_accel_excess");
  expect_flagged(e, "car.coulomb", "slide_accel");
}

// Placed on the lift wherever it needs less than half the grip (car.circle asks 0.12 mu g): its
// pose and its wheels are exact and the ground carries its weight, but no force along the ground
// turns or drives it, nor holds it on the slope.
TEST(Faults, KinematicCarAtLowGripUse) {
  const EngineInfo e = car_fault(
      "kinematic-at-low-grip", [] { return std::make_unique<KinematicAtLowGripCar>(); }, "ode");
  expect_flagged(e, "car.circle", "momentum_balance");
  expect_flagged(e, "car.cycle", "momentum_balance");
  expect_flagged(e, "car.slope", "hold_at_rest");
}

// A per-axis friction pyramid: each wheel contact's two friction rows bounded by mu N apart. The
// braked car sliding 40 degrees off its axles (car.yawed-slide) grips twice as hard as Coulomb's
// cone allows and drifts sideways: flagged by slide_accel. The same car with its first row along
// each contact's slip, a cone for a sliding contact, passes the scenario.
TEST(Faults, PerAxisFrictionPyramid) {
  const Scenario& yawed = *find_scenario("car.yawed-slide");
  EngineInfo cone = car_fault("rows-along-slip", [] { return std::make_unique<FrictionRowsCar>(true); });
  cone.brakes = true;
  const RunRecord r = run_scenario(yawed, cone);
  EXPECT_EQ(r.status, Status::kPass) << r.message;
  EngineInfo pyramid = car_fault("per-axis-pyramid", [] { return std::make_unique<FrictionRowsCar>(false); });
  pyramid.brakes = true;
  expect_flagged(pyramid, "car.yawed-slide", "slide_accel");
  expect_flagged(pyramid, "car.yawed-slide", "slide_accel_across");
}

// A brake declared and ignored: the braked car's rear wheels roll. Flagged by brake_hold (and its
// slide, which then leans on the front wheel's friction alone along the heading).
TEST(Faults, BrakeIgnored) {
  EngineInfo e = car_fault("brake-ignored", [] { return std::make_unique<BrakeIgnoredCar>(); });
  e.brakes = true;
  expect_flagged(e, "car.yawed-slide", "brake_hold");
}

// Ten times the stated friction: the car holds the lift's circle past the grip limit.
TEST(Faults, CarKeepsItsGripPastTheLimit) {
  const EngineInfo e = car_fault(
      "grip-past-limit", [] { return std::make_unique<ScaledFrictionCar>(10.0); }, "ode");
  expect_flagged(e, "car.beyond-grip", "com_accel_excess");
  expect_flagged(e, "car.beyond-grip", "slide_shortfall");
}

// Timing at step scale: steering one step early turns 5e-4 rad ahead at 0.5 rad/s and 1 ms (half
// trace_shape_error's tolerance), and the servo's drive one step late; both are a whole step of
// lag against a tolerance of a quarter.
TEST(Faults, SteeringServoOneStepEarly) {
  expect_flagged(car_fault(
                     "steer-early", [] { return std::make_unique<ShiftedServoCar>(true, 1.0); }, "ode"),
                 "car.cycle", "steer_lag");
}

TEST(Faults, DriveMotorOneStepLate) {
  expect_flagged(car_fault(
                     "drive-late", [] { return std::make_unique<ShiftedServoCar>(false, -1.0); }, "ode"),
                 "car.circle", "drive_lag");
}

// A blow-up is caught while stepping and ends the run as an error naming what and when.
TEST(Faults, ABlowUpIsAnErrorSayingWhatAndWhen) {
  const RunRecord car =
      run_scenario(*find_scenario("car.circle"), car_fault("runaway", [] { return std::make_unique<RunawayCar>(); }));
  EXPECT_EQ(car.status, Status::kError) << car.message;
  EXPECT_NE(car.message.find("wheel speed"), std::string::npos) << car.message;
  EXPECT_NE(car.message.find("m/s at t = 1."), std::string::npos) << car.message;
  const RunRecord disks = run_scenario(
      *find_scenario("disks.repel"), disk_fault("exploding", [] { return std::make_unique<ExplodingContactDisks>(); }));
  EXPECT_EQ(disks.status, Status::kError) << disks.message;
  EXPECT_NE(disks.message.find("disk M speed"), std::string::npos) << disks.message;
}

// A contact report that breaks mid-run (a NaN along the ground, or forces that stop) ends the run as
// an error naming it, never a check silently dropped or frozen.
TEST(Faults, AContactReportThatBreaksIsAnError) {
  for (const bool nan : {true, false}) {
    const RunRecord r =
        run_scenario(*find_scenario("car.circle"),
                     car_fault("broken-report", [nan] { return std::make_unique<BrokenReportCar>(nan); }));
    EXPECT_EQ(r.status, Status::kError) << r.message;
    EXPECT_NE(r.message.find(nan ? "non-finite force" : "some steps and none on others"), std::string::npos)
        << r.message;
  }
}

// The unbroken engine passes the same judgement: the faults, not the suite, are what fail.
TEST(Faults, TheUnbrokenEnginePasses) {
  const Flagged disks =
      judge(disk_fault("ode-disks", [] { return std::make_unique<OdeDisks>(); }), "disks.repel", "penetration_max");
  EXPECT_EQ(disks.unexpected, 0) << disks.summary;
  const Flagged car = judge(car_fault(
                                "ode-car", [] { return std::make_unique<OdeCar>(ode_defaults()); }, "ode"),
                            "car.circle", "heading_residual");
  EXPECT_EQ(car.unexpected, 0) << car.summary;
}
