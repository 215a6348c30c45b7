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
           {"servo", "rate = commanded rate + 40/s x angle error, torque limit 500 N m; settle 0.5 s, hold 0.2 s"},
           {"iterations", "none: dWorldStep is a direct solver (a setting 'iterations' is rejected)"},
           {"disks", "M: dynamic sphere (radius 1, 1 kg) driven by a dJointLMotor (force limit 1e5 N) to the commanded velocity; N: kinematic sphere (dBodySetKinematic) moved along its path; contact joints from dCollide in the step's near callback, frictionless"}},
          .knobs = {SettingSpec{"wheel", "car", "sphere", "wheel collision shape", SettingSpec::kChoice, 0, 0, {"sphere", "cylinder"}}, SettingSpec{"friction_dirs", "car", "wheel", "first friction direction: along the wheel's rolling direction, or the engine's default axes", SettingSpec::kChoice, 0, 0, {"wheel", "world"}}}};
}

}  // namespace liftcheck
