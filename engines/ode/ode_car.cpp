// The tricycle in ODE (0.16, double precision).
// Chassis: a box body without a geom. Front wheel: hinge-2 joint (axis 1 vertical = steering,
// axis 2 = axle), driven by the joint motors. Rear wheels: hinge joints on the rear axle.
// Wheel-ground contacts: dContactApprox1 (mu is a coefficient, not a force cap), soft ERP/CFM (the
// settings contact_erp, ode only, and contact_cfm),
// and, with friction_dirs = wheel, the first friction direction along the wheel's rolling direction.
// Signs (tests/conformance.cpp, ForwardIsPositiveAlphaAndLeftIsPositiveBeta): ODE reports hinge-2 angles of body 1
// (chassis) relative to body 2 (wheel), so the steering angle and the spin rate are negated.
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
  std::call_once(once, [] {
    if (!dInitODE2(0)) throw EngineError("ODE could not be initialised (dInitODE2)");
  });
  // ODE's per-thread data (collision caches where ODE keeps them per thread), once per thread.
  thread_local const bool allocated = dAllocateODEDataForThread(dAllocateMaskAll) != 0;
  if (!allocated) throw EngineError("ODE could not allocate its data for this thread (dAllocateODEDataForThread)");
}

OdeStepper OdeStepper::quick_from(const Settings& s) {
  OdeStepper st;
  st.quick = true;
  st.iterations = s.integer("iterations");
  st.w = s.has("w") ? s.number("w") : 1.3;  // the disks: no w (see ode_quick_engine)
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
    dWorldSetQuickStepNumIterations(world, iterations);
    dWorldSetQuickStepW(world, w);
  }
}

namespace {
/// Held by every quick step: ODE's random generator (dRand, misc.cpp) is one per process.
std::mutex& quick_step_rand_mutex() {
  static std::mutex m;
  return m;
}
}  // namespace

OdeWorld::OdeWorld(const OdeStepper& stepper, const Eigen::Vector3d& gravity_W_mps2) : stepper_(stepper) {
  init_ode();
  threading_ = dThreadingAllocateSelfThreadedImplementation();
  if (!threading_) throw EngineError("ODE could not allocate a threading implementation");
  world_ = dWorldCreate();
  dWorldSetStepThreadingImplementation(world_, dThreadingImplementationGetFunctions(threading_), threading_);
  dWorldSetGravity(world_, gravity_W_mps2.x(), gravity_W_mps2.y(), gravity_W_mps2.z());
  stepper_.configure(world_);
}

OdeWorld::~OdeWorld() {
  // The world frees its call-wait object through its threading implementation: world first.
  if (world_) dWorldDestroy(world_);
  if (threading_) dThreadingFreeImplementation(threading_);
}

void OdeWorld::step(double dt_s) {
  init_ode();  // a world may be stepped in a thread other than the one that made it
  if (!stepper_.quick) {
    dWorldStep(world_, dt_s);
    return;
  }
  std::lock_guard<std::mutex> lock(quick_step_rand_mutex());
  dRandSetSeed(rand_seed_);
  dWorldQuickStep(world_, dt_s);
  rand_seed_ = dRandGetSeed();
}

namespace {

const char* const kServo =
    "rate = commanded rate + 40/s x angle error, torque limit 1.5 mu N R of the driven wheel (106 N m for the default "
    "car); settle 0.5 s, hold 0.2 s";
const char* const kDisks =
    "M: dynamic sphere (radius 1, 1 kg) whose linear velocity is set to the command before each step "
    "(dBodySetLinearVel); N: kinematic sphere (dBodySetKinematic) moved along its path; contact joints from dCollide "
    "in the step's near callback, frictionless";

SettingSpec wheel_knob() {
  return {{.key = "wheel",
           .kind = ParamKind::kChoice,
           .default_text = "sphere",
           .help = "wheel collision shape",
           .choices = {"sphere", "cylinder"}},
          Vehicle::kCar};
}
// The wheel-ground contact joints' softness (dSurfaceParameters soft_erp and soft_cfm, with
// dContactSoftERP | dContactSoftCFM), as Gazebo's users set a surface's <contact><ode><soft_erp>
// and <soft_cfm> (SDFormat's defaults 0.2 and 0; the defaults here are this car's 0.2 and 1e-9).
// CFM is in m/(N s): CFM = 1 / (dt kp + kd) for a contact spring kp and damper kd (ODE's manual,
// "How To Use ERP and CFM").
SettingSpec contact_cfm_knob() {
  return {{.key = "contact_cfm",
           .kind = ParamKind::kNumber,
           .default_text = fmt::format("{:g}", kContactSoftCfm_m_per_Ns),
           .unit = "m/(N s)",
           .help = "constraint force mixing of the wheel-ground contact joints (dSurfaceParameters soft_cfm with "
                   "dContactSoftCFM; Gazebo's <surface><contact><ode><soft_cfm>, default 0)",
           .min = 0.0,
           .max = 1.0},
          Vehicle::kCar};
}
// ERP corrects only the depth beyond the world's contact surface layer (ODE's contact joint:
// depth - contact_surface_layer, nothing below it). At the default contact_cfm ode-quick's wheels
// never sink through its 1 mm layer, so there soft_erp alone changes nothing (only a much softer
// contact_cfm lets them through): ode only (dWorldStep, no layer).
SettingSpec contact_erp_knob() {
  return {{.key = "contact_erp",
           .kind = ParamKind::kNumber,
           .default_text = fmt::format("{:g}", kContactSoftErp),
           .unit = "1",
           .help = "error reduction of the wheel-ground contact joints (dSurfaceParameters soft_erp with "
                   "dContactSoftERP; Gazebo's <surface><contact><ode><soft_erp>, default 0.2)",
           .min = 0.0,
           .max = 1.0},
          Vehicle::kCar};
}
SettingSpec friction_dirs_knob(const char* default_text) {
  return {{.key = "friction_dirs",
           .kind = ParamKind::kChoice,
           .default_text = default_text,
           .help = "first friction direction: along the wheel's rolling direction (dContactFDir1), or ODE's default "
                   "axes from the normal",
           .choices = {"wheel", "world"}},
          Vehicle::kCar};
}

}  // namespace

EngineInfo ode_quick_engine() {
  std::vector<SettingSpec> knobs;
  for (const Vehicle vehicle : kVehicles)
    knobs.push_back({{.key = "iterations",
                      .kind = ParamKind::kInteger,
                      .default_text = "50",
                      .unit = "1",
                      .help = "quick-step iterations (dWorldSetQuickStepNumIterations; Gazebo's default 50)",
                      .min = 1,
                      .max = 10000},
                     vehicle,
                     SettingRole::kSolverIterations});
  // The disk M is velocity-set: its one frictionless contact row converges at any over-relaxation,
  // so w changes nothing for the disks and is a car setting only (an ignored setting is refused).
  knobs.push_back({{.key = "w",
                    .kind = ParamKind::kNumber,
                    .default_text = "1.3",
                    .unit = "1",
                    .help = "successive over-relaxation factor (dWorldSetQuickStepW; Gazebo's sor 1.3)",
                    .min = 0.0,
                    .min_exclusive = true,
                    .max = 2.0},
                   Vehicle::kCar});
  knobs.push_back(wheel_knob());
  knobs.push_back(friction_dirs_knob("world"));
  knobs.push_back(contact_cfm_knob());
  return {.name = "ode-quick",
          .library = "ODE",
          .version = fmt::format("{} ({})", LIFTCHECK_ODE_VERSION, sizeof(dReal) == 8 ? "double" : "single"),
          .description =
              "ODE as Gazebo runs it: dWorldQuickStep, 50 iterations, SOR 1.3, 1 mm contact surface layer; the same "
              "bodies and contacts as ode",
          .color = "#17becf",
          .make_car = [](const Settings& s) { return std::make_unique<OdeCar>(s, OdeStepper::quick_from(s)); },
          .make_disks = [](const Settings& s) { return make_ode_disks(OdeStepper::quick_from(s)); },
          .contact_dynamics = true,
          .settings = {{"stepper",
                        "dWorldQuickStep (iterative SOR/PGS), Gazebo's SDF physics defaults: global ERP 0.2, CFM 0, "
                        "contact_max_correcting_vel 100 m/s, contact_surface_layer 0.001 m"},
                       {"front wheel",
                        "dHinge2Joint, suspension CFM 1e-10; velocity motors on steering and spin; no knuckle body: "
                        "the knuckle's mass and inertia ride on the wheel body"},
                       {"rear wheels", "dHingeJoint each"},
                       {"contact",
                        "dContactApprox1 | dContactSoftERP | dContactSoftCFM, up to 4 points per wheel; soft_erp 0.2 "
                        "(it corrects only depth beyond the 1 mm surface layer, which the wheels reach only with a "
                        "much softer contact_cfm: no setting), soft_cfm --set contact_cfm (default 1e-9)"},
                       {"friction directions",
                        "world (Gazebo's default, no fdir1): ODE's axes from the normal; wheel: dContactFDir1 along "
                        "the rolling direction"},
                       {"contact forces",
                        "dJointSetFeedback on every wheel-ground contact joint, f1 (the force on the wheel) summed "
                        "each step (the load and momentum checks)"},
                       {"servo", kServo},
                       {"disks", kDisks},
                       {"threads",
                        "each world has its own ODE threading implementation; dWorldQuickStep draws its random "
                        "constraint order (dRandInt) from ODE's one process-wide generator, so concurrent runs take "
                        "turns at it (a process-wide lock around each quick step), each world continuing its own "
                        "sequence from seed 0: the numbers do not depend on what else runs"}},
          .knobs = knobs,
          .four_wheels = true,
          .brakes = true,
          .make_raw_car = make_raw_ode_quick_car};
}

namespace {
std::vector<SettingSpec> ode_knobs() {
  return {wheel_knob(), friction_dirs_knob("wheel"), contact_erp_knob(), contact_cfm_knob()};
}
}  // namespace

EngineInfo ode_engine() {
  return {
      .name = "ode",
      .library = "ODE",
      .version = fmt::format("{} ({})", LIFTCHECK_ODE_VERSION, sizeof(dReal) == 8 ? "double" : "single"),
      .description = "Open Dynamics Engine: hinge-2 front wheel, contact joints (dContactApprox1), dWorldStep",
      .color = "#1f77b4",
      .make_car = [](const Settings& s) { return std::make_unique<OdeCar>(s); },
      .make_disks = [](const Settings&) { return make_ode_disks(); },
      .contact_dynamics = true,
      .settings =
          {{"stepper", "dWorldStep (direct LCP solver), global ERP 0.2, CFM 1e-10"},
           {"front wheel", "dHinge2Joint, suspension CFM 1e-10; velocity motors on steering and spin"},
           {"rear wheels", "dHingeJoint each"},
           {"contact",
            "dContactApprox1 | dContactSoftERP | dContactSoftCFM, up to 4 points per wheel; soft_erp --set contact_erp "
            "(default 0.2), soft_cfm --set contact_cfm (default 1e-9)"},
           {"friction directions",
            "wheel: dContactFDir1 along the rolling direction (axle x up); world: ODE's default axes from the normal"},
           {"contact forces",
            "dJointSetFeedback on every wheel-ground contact joint, f1 (the force on the wheel) summed "
            "each step (the load and momentum checks)"},
           {"servo", kServo},
           {"iterations", "none: dWorldStep is a direct solver (a setting 'iterations' is rejected)"},
           {"disks", kDisks},
           {"threads",
            "each world has its own ODE threading implementation (ODE's default one is shared by every world and not "
            "synchronised); every thread that steps a world calls dAllocateODEDataForThread first: runs step in "
            "parallel"}},
      .knobs = ode_knobs(),
      .four_wheels = true,
      .brakes = true,
      .make_raw_car = make_raw_ode_car};
}

}  // namespace liftcheck
