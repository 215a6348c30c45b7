#pragma once
#include "engines/engine.hpp"
#include "engines/raw_car.hpp"
namespace liftcheck {
/// Bullet (double precision) btRaycastVehicle as the tricycle: one steered, driven front wheel and
/// two passive rear wheels on a chassis that collides with nothing; cars only.
EngineInfo bullet_raycast_engine();
/// The car this configuration builds, stepped by stepSimulation directly (benchmarks only).
std::unique_ptr<RawCar> make_raw_bullet_raycast_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
}  // namespace liftcheck
