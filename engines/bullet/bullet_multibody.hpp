#pragma once
#include "engines/engine.hpp"
#include "engines/raw_car.hpp"
namespace liftcheck {
/// Bullet (double precision) in reduced coordinates: btMultiBodyDynamicsWorld (Featherstone) with a
/// floating-base btMultiBody tricycle, revolute links, btMultiBodyJointMotor servos and Bullet's
/// defaults otherwise (btMultiBody damping 0.04, 10 solver iterations); the two disks in the same
/// world type.
EngineInfo bullet_multibody_engine();
/// The car this configuration builds, stepped by stepSimulation directly (benchmarks only).
std::unique_ptr<RawCar> make_raw_bullet_multibody_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
}  // namespace liftcheck
