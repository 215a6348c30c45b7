// The collision configuration, dispatcher, broadphase and solver every Bullet world here needs,
// owned together and outliving the world built on them.
#pragma once

#include <btBulletDynamicsCommon.h>

#include <Eigen/Dense>
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

/// The impulse the solver applied, in the step just taken, to whatever touches `ground` at the
/// manifold points between them: the normal (m_appliedImpulse along m_normalWorldOnB, which points
/// from the manifold's body 1 towards body 0) and the two friction impulses along their directions,
/// each acting with + on body 0 and - on body 1. Bullet's sequential-impulse solvers write them
/// back into the manifold points under warm starting, their default.
inline Eigen::Vector3d impulse_from_ground(btDispatcher& d, const btCollisionObject* ground) {
  btVector3 sum(0, 0, 0);
  for (int i = 0; i < d.getNumManifolds(); ++i) {
    const btPersistentManifold* m = d.getManifoldByIndexInternal(i);
    const bool ground0 = m->getBody0() == ground, ground1 = m->getBody1() == ground;
    if (ground0 == ground1) continue;
    const double sign = ground1 ? 1.0 : -1.0;  // the other body is body 0 when the ground is body 1
    for (int k = 0; k < m->getNumContacts(); ++k) {
      const btManifoldPoint& p = m->getContactPoint(k);
      sum += sign * (p.m_normalWorldOnB * p.m_appliedImpulse + p.m_lateralFrictionDir1 * p.m_appliedImpulseLateral1 +
                     p.m_lateralFrictionDir2 * p.m_appliedImpulseLateral2);
    }
  }
  return {sum.x(), sum.y(), sum.z()};
}

}  // namespace liftcheck
