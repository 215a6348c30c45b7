#pragma once
#include "engines/engine.hpp"
namespace liftcheck {
/// Bullet (double precision) btRaycastVehicle as the tricycle: one steered, driven front wheel and
/// two passive rear wheels on a chassis that collides with nothing; cars only.
EngineInfo bullet_raycast_engine();
}  // namespace liftcheck
