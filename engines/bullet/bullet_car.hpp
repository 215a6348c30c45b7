#pragma once
#include "engines/engine.hpp"
namespace liftcheck {
/// Bullet (double precision): a tricycle of rigid bodies, btHinge2Constraint front wheel with the
/// suspension locked, hinge rear wheels, contact friction with two friction directions.
EngineInfo bullet_engine();
std::unique_ptr<DiskEngine> make_bullet_disks();
}  // namespace liftcheck
