// The tricycle in ODE (0.16, double precision).
// Chassis: a box body without a geom. Front wheel: hinge-2 joint (axis 1 vertical = steering,
// axis 2 = axle), driven by the joint motors. Rear wheels: hinge joints on the rear axle.
// Wheel-ground contacts: dContactApprox1 (mu is a coefficient, not a force cap), soft ERP/CFM,
// and, with friction_dirs = wheel, the first friction direction along the wheel's rolling direction.
// Signs (tests/test_engine_signs.cpp): ODE reports hinge-2 angles of body 1 (chassis) relative to
// body 2 (wheel), so the steering angle and the spin rate are negated.
#include "engines/ode/ode_car.hpp"

#include <ode/ode.h>

#include <cmath>
#include <fmt/format.h>
#include <mutex>

#include "engines/ode/ode_car_model.hpp"
#include "engines/rigid_car.hpp"

namespace liftcheck {

void init_ode() {
  static std::once_flag once;
  std::call_once(once, [] { dInitODE2(0); });
}

OdeStepper OdeStepper::quick_from(const Settings& s) {
  OdeStepper st;
  st.quick = true;
  st.iterations = std::stoi(s.at("iterations"));
  st.w = std::stod(s.at("w"));
  st.cfm = 0.0;
  st.surface_layer_m = 0.001;
  st.max_correcting_vel_mps = 100.0;
  return st;
}

void OdeStepper::configure(dWorldID world) const {
  dWorldSetERP(world, 0.2);
  dWorldSetCFM(world, cfm);
  dWorldSetContactSurfaceLayer(world, surface_layer_m);
  dWorldSetContactMaxCorrectingVel(world, max_correcting_vel_mps);
  if (quick) {
    // QuickStep reorders its constraints at random from ODE's process-wide generator: every world
    // starts it from the same seed, so the same inputs give the same numbers (as in a fresh process).
    dRandSetSeed(0);
    dWorldSetQuickStepNumIterations(world, iterations);
    dWorldSetQuickStepW(world, w);
  }
}

void OdeStepper::step(dWorldID world, double dt_s) const {
  if (quick) dWorldQuickStep(world, dt_s);
  else dWorldStep(world, dt_s);
}

namespace {

const char* const kServo = "rate = commanded rate + 40/s x angle error, torque limit 500 N m; settle 0.5 s, hold 0.2 s";
const char* const kDisks = "M: dynamic sphere (radius 1, 1 kg) driven by a dJointLMotor (force limit 1e5 N) to the commanded velocity; N: kinematic sphere (dBodySetKinematic) moved along its path; contact joints from dCollide in the step's near callback, frictionless";

SettingSpec wheel_knob() { return {"wheel", "car", "sphere", "wheel collision shape", SettingSpec::kChoice, 0, 0, {"sphere", "cylinder"}}; }
SettingSpec friction_dirs_knob(const char* default_text) {
  return {"friction_dirs", "car", default_text, "first friction direction: along the wheel's rolling direction (dContactFDir1), or ODE's default axes from the normal",
          SettingSpec::kChoice, 0, 0, {"wheel", "world"}};
}

}  // namespace

EngineInfo ode_quick_engine() {
  std::vector<SettingSpec> knobs;
  for (const char* vehicle : {"car", "disks"}) {
    knobs.push_back({"iterations", vehicle, "50", "quick-step iterations (dWorldSetQuickStepNumIterations; Gazebo's default 50)", SettingSpec::kInteger, 1, 10000, {}});
    knobs.push_back({"w", vehicle, "1.3", "successive over-relaxation factor (dWorldSetQuickStepW; Gazebo's sor 1.3)", SettingSpec::kReal, 0.0, 2.0, {}, true});
  }
  knobs.push_back(wheel_knob());
  knobs.push_back(friction_dirs_knob("world"));
  return {.name = "ode-quick",
          .library = "ODE",
          .version = fmt::format("{} ({})", LIFTCHECK_ODE_VERSION, sizeof(dReal) == 8 ? "double" : "single"),
          .description = "ODE as Gazebo runs it: dWorldQuickStep, 50 iterations, SOR 1.3, 1 mm contact surface layer; the same bodies and contacts as ode",
          .color = "#17becf",
          .make_car = [](const Settings& s) { return std::make_unique<OdeCar>(s, OdeStepper::quick_from(s)); },
          .make_disks = [](const Settings& s) { return make_ode_disks(OdeStepper::quick_from(s)); },
          .contact_dynamics = true,
          .settings = {{"stepper", "dWorldQuickStep (iterative SOR/PGS), Gazebo's SDF physics defaults: global ERP 0.2, CFM 0, contact_max_correcting_vel 100 m/s, contact_surface_layer 0.001 m"},
           {"front wheel", "dHinge2Joint, suspension CFM 1e-10; velocity motors on steering and spin"},
           {"rear wheels", "dHingeJoint each"},
           {"contact", "dContactApprox1 | SoftERP 0.2 | SoftCFM 1e-9, up to 4 points per wheel"},
           {"friction directions", "world (Gazebo's default, no fdir1): ODE's axes from the normal; wheel: dContactFDir1 along the rolling direction"},
           {"servo", kServo},
           {"disks", kDisks}},
          .knobs = knobs};
}

EngineInfo ode_engine() {
  return {.name = "ode",
          .library = "ODE",
          .version = fmt::format("{} ({})", LIFTCHECK_ODE_VERSION, sizeof(dReal) == 8 ? "double" : "single"),
          .description = "Open Dynamics Engine: hinge-2 front wheel, contact joints (dContactApprox1), dWorldStep",
          .color = "#1f77b4",
          .make_car = [](const Settings& s) { return std::make_unique<OdeCar>(s); },
          .make_disks = [](const Settings&) { return make_ode_disks(); },
          .contact_dynamics = true,
          .settings = {{"stepper", "dWorldStep (direct LCP solver), global ERP 0.2, CFM 1e-10"},
           {"front wheel", "dHinge2Joint, suspension CFM 1e-10; velocity motors on steering and spin"},
           {"rear wheels", "dHingeJoint each"},
           {"contact", "dContactApprox1 | SoftERP 0.2 | SoftCFM 1e-9, up to 4 points per wheel"},
           {"friction directions", "wheel: dContactFDir1 along the rolling direction (axle x up); world: ODE's default axes from the normal"},
           {"servo", kServo},
           {"iterations", "none: dWorldStep is a direct solver (a setting 'iterations' is rejected)"},
           {"disks", kDisks}},
          .knobs = {wheel_knob(), friction_dirs_knob("wheel")}};
}

}  // namespace liftcheck
