// Simbody 3.7 (SimTK; the multibody engine of OpenSim and one of Gazebo classic's four): reduced
// coordinates (mobilizers), compliant Hunt-Crossley contact with a Stribeck-like friction law
// regularised below a transition velocity, error-controlled integration between liftcheck's steps.
// simbody_sim.cpp holds every Simbody call; this file puts it behind RigidCar and DrivenDisks.
//
// Car: the tricycle as a tree: a Free mobilizer for the chassis (frame at the front-axle centre,
// box centre of mass l/2 behind, no contact surface), a Pin for the steering knuckle about the
// chassis z, Pins for the wheels about their axles; sphere wheels with a ContactSurface on a
// ground HalfSpace (Gazebo's SimbodyPhysics builds the same). The servos are Simbody's prescribed
// motion: a Motion::Steady on the spin and on the steering mobility, its rate the servo's command
// over each step, written into the state with System::prescribeU; Simbody computes the torque,
// unlimited: the other engines' 1.5 mu N R limit is not applied. Measured over the default suite,
// the spin servo's largest torque (MobilizedBody::getOneTau at each step's end) is 39 N m on
// car.slope against the limit's 106 N m, and 7.2 N m against 10.6 N m on the mu = 0.1 scenarios:
// the limit would not have acted.
//
// Disks: M on a Translation mobilizer (it cannot turn), its velocity set at each step as Gazebo's
// SimbodyJoint::SetVelocity sets a mobility's speed; N on a Translation mobilizer whose speeds a
// Motion::Steady prescribes (kinematic). Contact: the ContactTrackerSubsystem's active contacts on
// the state at the start of the step.
//
// Threads: every run builds its own MultibodySystem; Simbody keeps no process-wide mutable state
// for it (the contact clique counter, unused here, is atomic).
#include "engines/simbody/simbody_engine.hpp"

#include <fmt/format.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "engines/driven_disks.hpp"
#include "engines/rigid_car.hpp"
#include "engines/simbody/simbody_sim.hpp"
#include "models/e2.hpp"

namespace liftcheck {

namespace {

constexpr double kDiskMass_kg = 1.0;

/// A configuration's defaults: Gazebo's (sdformat physics.sdf's <simbody> element and
/// SimbodyPhysics.cc).
struct SimbodyPreset {
  const char* name;
  simbody::ContactDef contact;
  simbody::IntegratorDef integrator;
};
constexpr const char* kIntegrators[] = {"semi_explicit_euler2", "rk_merson", "rk3"};

/// The contact settings; the disks, frictionless, keep Gazebo's transition velocity.
simbody::ContactDef contact_of(const Settings& s) {
  simbody::ContactDef c{.stiffness_Pa = s.number("stiffness_Pa"),
                        .dissipation_s_per_m = s.number("dissipation_s_per_m")};
  if (s.has("transition_velocity_mps")) c.transition_velocity_mps = s.number("transition_velocity_mps");
  return c;
}
simbody::IntegratorDef integrator_of(const Settings& s) {
  return {.method = s.choice("integrator"), .accuracy = s.number("accuracy")};
}

/// Simbody's exceptions (an integrator that cannot meet its accuracy, a singular state) are the
/// run's engine errors.
template <class F>
auto guarded(F f) {
  try {
    return f();
  } catch (const EngineError&) {
    throw;
  } catch (const std::exception& e) {
    throw EngineError(fmt::format("Simbody: {}", e.what()));
  }
}

/// Why the ground's forces are not booked on Simbody (its facts say so too).
constexpr const char* kContactForcesNotRead =
    "not read: Simbody's compliant contact gives the force at an instant (CompliantContactSubsystem::getContactForce), "
    "while the error-controlled integrator takes each step in substeps of its own, so the impulse the load and "
    "momentum checks book over a step is not the instant's force times dt (the checks are skipped, saying so)";

class SimbodyCar final : public RigidCar {
 public:
  explicit SimbodyCar(Settings settings) : RigidCar(std::move(settings)) {}

 protected:
  std::string ground_force_absent_why() const override { return kContactForcesNotRead; }
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    const simbody::CarDef def{.R_m = d.R_m,
                              .l_m = d.l_m,
                              .track_m = d.track_m,
                              .chassis_height_m = d.chassis_height_m,
                              .chassis_mass_kg = d.chassis_mass_kg,
                              .wheel_mass_kg = d.wheel_mass_kg,
                              .knuckle_mass_kg = d.knuckle_mass_kg,
                              .knuckle_inertia_kgm2 = d.knuckle_inertia_kgm2(),
                              .mu = setup.mu,
                              .gravity_W_mps2 = setup.gravity_W(),
                              .x0_m = q0.x_m,
                              .y0_m = q0.y_m,
                              .phi0_rad = q0.phi_rad,
                              .beta0_rad = q0.beta_rad,
                              .contact = contact_of(settings_),
                              .integrator = integrator_of(settings_),
                              .rear_brake = setup.rear_brake};
    sim_ = guarded([&] { return std::make_unique<simbody::CarSim>(def); });
  }

  void actuate(const FrontRates& rates, const ServoDef&) override {
    guarded([&] {
      sim_->command(rates.spin_radps[0], rates.steer_radps[0]);
      return 0;
    });
  }

  void step(double dt_s) override {
    guarded([&] {
      sim_->step(dt_s);
      return 0;
    });
  }

  RigidCarState read() const override {
    const simbody::CarOut o = sim_->read();
    RigidCarState st{};
    st.spin_joint_rad[0] = e2::wrap_angle(o.spin_joint_rad);
    st.steer_rad[0] = o.steer_rad;
    st.x_m = o.front_W.x();
    st.y_m = o.front_W.y();
    st.z_m = o.front_W.z();
    st.phi_rad = o.phi_rad;
    st.rear_z_m = o.rear_z_m;
    for (int w = 0; w < 3; ++w)
      st.wheels[w] = {o.wheels[w].v_hub_W, o.wheels[w].omega_W, o.wheels[w].axle_W, o.wheels[w].hub_z_m};
    return st;
  }

 private:
  std::unique_ptr<simbody::CarSim> sim_;
};

class SimbodyDisks final : public DrivenDisks {
 public:
  explicit SimbodyDisks(Settings s) : settings_(std::move(s)) {}

 protected:
  void build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) override {
    const simbody::DisksDef def{.radius_m = setup.radius_m,
                                .mass_kg = kDiskMass_kg,
                                .mu_MN = setup.mu_MN,
                                .cM0_m = cM0,
                                .cN0_m = cN0,
                                .contact = contact_of(settings_),
                                .integrator = integrator_of(settings_)};
    sim_ = guarded([&] { return std::make_unique<simbody::DisksSim>(def); });
  }

  StepContacts step(const disks::Vec2& vM_cmd, const disks::Vec2& cN_next, const disks::Vec2&, double dt_s) override {
    // N: the velocity that lands it on its path at the end of the step.
    const disks::Vec2 vN = (cN_next - sim_->cN()) / dt_s;
    const simbody::DisksContacts c = guarded([&] { return sim_->step(vM_cmd, vN, dt_s); });
    StepContacts out;
    out.count = c.count;
    out.depth_max_m = c.depth_max_m;
    out.distance_min_m = c.distance_min_m;
    return out;
  }

  State read() const override { return {sim_->cM(), sim_->cN(), sim_->wM_radps()}; }

 private:
  Settings settings_;
  std::unique_ptr<simbody::DisksSim> sim_;
};

/// A number knob of both vehicles or of one.
void add_number(std::vector<SettingSpec>& knobs, const char* key, double value, const char* unit, std::string help,
                double min, double max, std::initializer_list<Vehicle> vehicles) {
  for (const Vehicle vehicle : vehicles)
    knobs.push_back({{.key = key,
                      .kind = ParamKind::kNumber,
                      .default_text = fmt::format("{:g}", value),
                      .unit = unit,
                      .help = help,
                      .min = min,
                      .max = max},
                     vehicle});
}

std::vector<SettingSpec> knobs_for(const SimbodyPreset& p) {
  std::vector<SettingSpec> knobs;
  for (const Vehicle vehicle : kVehicles)
    knobs.push_back({{.key = "integrator",
                      .kind = ParamKind::kChoice,
                      .default_text = p.integrator.method,
                      .help = "Simbody integrator between two steps, all error-controlled: semi_explicit_euler2 "
                              "(SemiExplicitEuler2Integrator, Gazebo's), rk_merson (RungeKuttaMersonIntegrator, "
                              "Simbody's general-purpose choice), rk3 (RungeKutta3Integrator)",
                      .choices = {std::begin(kIntegrators), std::end(kIntegrators)}},
                     vehicle});
  const auto both = {Vehicle::kCar, Vehicle::kDisks};
  add_number(knobs, "accuracy", p.integrator.accuracy, "1",
             "Integrator::setAccuracy: the relative error the integrator's step-size control keeps to", 1e-9, 0.1,
             both);
  add_number(knobs, "stiffness_Pa", p.contact.stiffness_Pa, "Pa",
             "ContactMaterial stiffness of every contact surface (Hertz plane-strain modulus; two surfaces combine "
             "in series)",
             1e4, 1e13, both);
  add_number(knobs, "dissipation_s_per_m", p.contact.dissipation_s_per_m, "s/m",
             "ContactMaterial dissipation (Hunt-Crossley)", 0.0, 1e4, both);
  // The disks are frictionless in every scenario: the transition velocity changes nothing there.
  add_number(knobs, "transition_velocity_mps", p.contact.transition_velocity_mps, "m/s",
             "CompliantContactSubsystem::setTransitionVelocity: below this slip speed friction is regularised "
             "(Gazebo's <max_transient_velocity>)",
             1e-6, 1.0, {Vehicle::kCar});
  return knobs;
}

std::vector<std::pair<std::string, std::string>> settings_for(const SimbodyPreset& p) {
  return {
      {"stepper",
       fmt::format("Integrator::stepTo(t + dt, t + dt) each step, as Gazebo's SimbodyPhysics::UpdatePhysics; {} at "
                   "accuracy {:g} between steps (error-controlled: it takes as many internal steps as it needs)",
                   p.integrator.method, p.integrator.accuracy)},
      {"contact",
       fmt::format("CompliantContactSubsystem with a ContactTrackerSubsystem: Hunt-Crossley on every surface, "
                   "ContactMaterial stiffness {:g} Pa, dissipation {:g} s/m, static = dynamic friction = mu, "
                   "viscous 0; transition velocity {:g} m/s",
                   p.contact.stiffness_Pa, p.contact.dissipation_s_per_m, p.contact.transition_velocity_mps)},
      {"friction",
       "Simbody's compliant friction: a continuous law of the slip speed, regularised below the transition velocity "
       "(no stiction), so a constant tangential load makes the contact creep at a speed that scales with it"},
      {"joints",
       "MobilizedBody::Free chassis (frame at the front-axle centre, box of chassis_mass, centre of mass l/2 behind, "
       "no contact surface); MobilizedBody::Pin knuckle about the chassis z; Pin front wheel about the knuckle's y; "
       "Pin rear wheels about the chassis y; solid sphere wheels of wheel_mass"},
      {"ground", "a ContactGeometry::HalfSpace on Ground, turned to fill z < 0 (as Gazebo's plane)"},
      {"contact forces", kContactForcesNotRead},
      {"servo",
       "Motion::Steady on the spin and on the steering mobility (Simbody's prescribed motion), its rate set each step "
       "to commanded rate + 40/s x angle error and written into the state (System::prescribeU); the torque it takes "
       "is Simbody's and not limited (the other engines' 1.5 mu N R limit would not act: the default suite's "
       "largest spin torque is 39 N m of 106 on car.slope, 7.2 of 10.6 at mu = 0.1); settle 0.5 s, hold 0.2 s"},
      {"disks",
       "M: sphere (radius 1, 1 kg, no gravity) on a MobilizedBody::Translation (it cannot turn), its speeds set each "
       "step (Gazebo's SimbodyJoint::SetVelocity); N: the same on a Translation whose speeds a Motion::Steady "
       "prescribes to land on its path each step; contact: the "
       "tracker's active contacts at the step's start, or the one the step entered, with its separation at the start"},
  };
}

EngineInfo make_info(const SimbodyPreset& p) {
  return {.name = p.name,
          .library = "Simbody",
          .version = "3.7",
          .description =
              "Simbody as Gazebo classic runs it: SemiExplicitEuler2 at accuracy 1e-3, compliant contact "
              "1e8 Pa, dissipation 100 s/m, transition velocity 0.01 m/s",
          .color = "#637939",
          .make_car = [](const Settings& s) { return std::make_unique<SimbodyCar>(s); },
          .make_disks = [](const Settings& s) { return std::make_unique<SimbodyDisks>(s); },
          .contact_dynamics = true,
          .settings = settings_for(p),
          .knobs = knobs_for(p),
          .brakes = true,
          // Hundreds of microseconds a step (error-controlled integration of stiff compliant
          // contact): its runs and the map's default point only, as the npm configurations.
          .points = SuitePoints::kRuns};
}

}  // namespace

EngineInfo simbody_engine() {
  // sdformat's <simbody> defaults: accuracy 0.001, max_transient_velocity 0.01, contact stiffness
  // 1e8, dissipation 100 (SimbodyPhysics::Load reads them; its integrator is SemiExplicitEuler2).
  return make_info({"simbody", {1e8, 100.0, 0.01}, {"semi_explicit_euler2", 1e-3}});
}

}  // namespace liftcheck
