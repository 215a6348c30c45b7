#pragma once
#include "engines/engine.hpp"
namespace liftcheck {
/// Open Dynamics Engine: a tricycle of rigid bodies, hinge-2 front wheel, contact joints with
/// Coulomb friction (dContactApprox1), dWorldStep.
EngineInfo ode_engine();
std::unique_ptr<DiskEngine> make_ode_disks();
/// dInitODE2, once per process.
void init_ode();
}  // namespace liftcheck
