#pragma once
#include "engines/engine.hpp"
#include "engines/raw_car.hpp"
namespace liftcheck {
/// Bullet (double precision): a tricycle of rigid bodies, btHinge2Constraint front wheel with the
/// suspension locked, hinge rear wheels, contact friction with two friction directions.
EngineInfo bullet_engine();
std::unique_ptr<DiskEngine> make_bullet_disks();
/// The car this configuration builds, stepped by stepSimulation directly (benchmarks only).
std::unique_ptr<RawCar> make_raw_bullet_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
}  // namespace liftcheck
