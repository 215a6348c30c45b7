#pragma once
#include <ode/ode.h>

#include "engines/engine.hpp"
namespace liftcheck {

/// How an ODE world is stepped: the direct solver (dWorldStep) with liftcheck's constraint
/// settings, or the iterative quick-step solver with Gazebo's SDF physics defaults.
struct OdeStepper {
  bool quick = false;
  int iterations = 50;                    ///< dWorldSetQuickStepNumIterations (quick only)
  double w = 1.3;                         ///< dWorldSetQuickStepW, SOR over-relaxation (quick only)
  double cfm = 1e-10;                     ///< global CFM (dWorldStep needs a little: LCP errors at 0)
  double surface_layer_m = 0.0;           ///< dWorldSetContactSurfaceLayer
  double max_correcting_vel_mps = INFINITY;  ///< dWorldSetContactMaxCorrectingVel

  /// Gazebo's defaults (sdformat physics.sdf: quick, 50 iterations, SOR 1.3, CFM 0, ERP 0.2,
  /// contact_max_correcting_vel 100, contact_surface_layer 0.001), iterations and w from `s`.
  static OdeStepper quick_from(const Settings& s);
  /// Global ERP 0.2 and the settings above.
  void configure(dWorldID world) const;
  void step(dWorldID world, double dt_s) const;
};

/// Open Dynamics Engine: a tricycle of rigid bodies, hinge-2 front wheel, contact joints with
/// Coulomb friction (dContactApprox1), dWorldStep.
EngineInfo ode_engine();
/// The same bodies and contacts stepped by dWorldQuickStep with Gazebo's defaults.
EngineInfo ode_quick_engine();
std::unique_ptr<DiskEngine> make_ode_disks(const OdeStepper& stepper = {});
/// dInitODE2, once per process.
void init_ode();
}  // namespace liftcheck
