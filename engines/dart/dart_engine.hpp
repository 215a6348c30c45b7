#pragma once
#include "engines/engine.hpp"
#include "engines/raw_car.hpp"
namespace liftcheck {
/// DART 6 as shipped: World with its default constraint solver (boxed LCP, Dantzig with PGS as
/// fallback) and its default collision detector (FCL, primitives approximated by meshes). The
/// tricycle is a Skeleton (free-joint chassis, revolute steering, spin and rear-wheel joints,
/// SERVO actuators); the two disks are skeletons on translational joints.
EngineInfo dart_engine();
/// The same model with DART's own collision detector (DARTCollisionDetector): analytic sphere
/// and box contacts instead of FCL's tessellated spheres.
EngineInfo dart_primitive_engine();
/// The car each configuration builds, stepped by World::step directly (benchmarks only).
std::unique_ptr<RawCar> make_raw_dart_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
std::unique_ptr<RawCar> make_raw_dart_primitive_car(const Settings& s, const CarSetup& setup, const car::Config& q0);
}  // namespace liftcheck
