// The collision configuration, dispatcher, broadphase and solver every Bullet world here needs,
// owned together and outliving the world built on them.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <memory>

namespace liftcheck {

struct BulletCore {
  std::unique_ptr<btDefaultCollisionConfiguration> config = std::make_unique<btDefaultCollisionConfiguration>();
  std::unique_ptr<btCollisionDispatcher> dispatcher = std::make_unique<btCollisionDispatcher>(config.get());
  std::unique_ptr<btBroadphaseInterface> broadphase = std::make_unique<btDbvtBroadphase>();
  std::unique_ptr<btSequentialImpulseConstraintSolver> solver = std::make_unique<btSequentialImpulseConstraintSolver>();

  /// A world of type W (btDiscreteDynamicsWorld or a subclass) on these parts.
  template <class W>
  std::unique_ptr<W> make_world() const {
    return std::make_unique<W>(dispatcher.get(), broadphase.get(), solver.get(), config.get());
  }
};

}  // namespace liftcheck
