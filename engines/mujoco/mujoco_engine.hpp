#pragma once
#include "engines/engine.hpp"
namespace liftcheck {
/// MuJoCo as shipped: Euler, pyramidal cone, Newton solver, contact solref 0.02 1, solimp 0.9 0.95 0.001.
EngineInfo mujoco_engine();
/// MuJoCo's defaults plus the noslip post-solver (noslip_iterations, the remedy its documentation names for slip).
EngineInfo mujoco_noslip_engine();
/// MuJoCo with the stiffest contact its refsafe allows (solref 2 dt), elliptic cone and impratio 10.
EngineInfo mujoco_stiff_engine();
}  // namespace liftcheck
