#pragma once
#include <ode/ode.h>

#include <cmath>

#include "engines/engine.hpp"
#include "engines/raw_car.hpp"
namespace liftcheck {

/// The wheel-ground contact joints' dSurfaceParameters soft_erp and soft_cfm by default (the
/// settings contact_erp, contact_cfm).
constexpr double kContactSoftErp = 0.2;
constexpr double kContactSoftCfm_m_per_Ns = 1e-9;

/// How an ODE world is stepped: the direct solver (dWorldStep) with liftcheck's constraint
/// settings, or the iterative quick-step solver with Gazebo's SDF physics defaults.
struct OdeStepper {
  bool quick = false;
  int iterations = 50;                       ///< dWorldSetQuickStepNumIterations (quick only)
  double w = 1.3;                            ///< dWorldSetQuickStepW, SOR over-relaxation (quick only)
  double cfm = 1e-10;                        ///< global CFM (dWorldStep needs a little: LCP errors at 0)
  double surface_layer_m = 0.0;              ///< dWorldSetContactSurfaceLayer
  double max_correcting_vel_mps = INFINITY;  ///< dWorldSetContactMaxCorrectingVel

  /// Gazebo's defaults (sdformat physics.sdf: quick, 50 iterations, SOR 1.3, CFM 0, ERP 0.2,
  /// contact_max_correcting_vel 100, contact_surface_layer 0.001), iterations and w from `s`.
  static OdeStepper quick_from(const Settings& s);
  /// Global ERP 0.2 and the settings above.
  void configure(dWorldID world) const;
};

/// An ODE world that runs in any thread alongside other worlds (ODE's multithreading contract,
/// include/ode/threading_impl.h and odeinit.h):
/// - ODE is initialised once per process (dInitODE2) and every thread that creates or steps a
///   world has called dAllocateODEDataForThread (init_ode does both);
/// - the world has a threading implementation of its own: without one, every world posts its
///   step's jobs to ODE's single process-wide self-threaded implementation, whose job list is not
///   synchronised (two worlds stepping at once abort in ReleaseAJob or WaitWakeup);
/// - the quick step's random constraint order is this world's own sequence: dWorldQuickStep draws
///   it from dRandInt, one process-wide generator, so each step holds a process-wide lock, starts
///   the generator from the seed this world's previous step left, and keeps the seed it leaves.
///   A world starts from seed 0, so its numbers are those of a fresh process whatever else runs.
class OdeWorld {
 public:
  OdeWorld(const OdeStepper& stepper, const Eigen::Vector3d& gravity_W_mps2);
  ~OdeWorld();
  OdeWorld(const OdeWorld&) = delete;
  OdeWorld& operator=(const OdeWorld&) = delete;

  dWorldID id() const { return world_; }
  /// One step of dt_s by the stepper's solver (dWorldStep or dWorldQuickStep).
  void step(double dt_s);

 private:
  OdeStepper stepper_;
  dThreadingImplementationID threading_ = nullptr;
  dWorldID world_ = nullptr;
  unsigned long rand_seed_ = 0;  ///< ODE's dRand state after this world's last quick step
};

/// Open Dynamics Engine: a tricycle of rigid bodies, hinge-2 front wheel, contact joints with
/// Coulomb friction (dContactApprox1), dWorldStep.
EngineInfo ode_engine();
/// The same bodies and contacts stepped by dWorldQuickStep with Gazebo's defaults.
EngineInfo ode_quick_engine();
std::unique_ptr<DiskEngine> make_ode_disks(const OdeStepper& stepper = {});
/// The car built by OdeCar, stepped by dSpaceCollide / dWorldStep (dWorldQuickStep for the quick
/// stepper of `s`) / dJointGroupEmpty directly (ode_raw.cpp; benchmarks only).
std::unique_ptr<RawCar> make_raw_ode_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
std::unique_ptr<RawCar> make_raw_ode_quick_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
/// dInitODE2 once per process, dAllocateODEDataForThread once in each calling thread.
void init_ode();
}  // namespace liftcheck
