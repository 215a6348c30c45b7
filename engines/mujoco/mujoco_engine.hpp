#pragma once
#include "engines/engine.hpp"
#include "engines/raw_car.hpp"
namespace liftcheck {
/// MuJoCo as shipped: Euler, pyramidal cone, Newton solver, contact solref 0.02 1, solimp 0.9 0.95 0.001.
EngineInfo mujoco_engine();
/// MuJoCo's defaults plus the noslip post-solver (noslip_iterations, the remedy its documentation names for slip).
EngineInfo mujoco_noslip_engine();
/// MuJoCo with the stiffest contact its refsafe allows (solref 2 dt), elliptic cone and impratio 10.
EngineInfo mujoco_stiff_engine();
/// The car each configuration builds, stepped by mj_step directly (benchmarks only).
std::unique_ptr<RawCar> make_raw_mujoco_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
std::unique_ptr<RawCar> make_raw_mujoco_noslip_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
std::unique_ptr<RawCar> make_raw_mujoco_stiff_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
}  // namespace liftcheck
