#pragma once
#include "engines/engine.hpp"
namespace liftcheck {
/// Bullet (double precision) in reduced coordinates: btMultiBodyDynamicsWorld (Featherstone) with a
/// floating-base btMultiBody tricycle, revolute links, btMultiBodyJointMotor servos and Bullet's
/// defaults otherwise (btMultiBody damping 0.04, 10 solver iterations); the two disks in the same
/// world type.
EngineInfo bullet_multibody_engine();
}  // namespace liftcheck
