// Two disks in Bullet (double precision): M a dynamic sphere whose linear velocity is set to the
// commanded one before each step and whose rotation is held (angular factor 0) (Bullet's velocity state; its solver and
// integrator take it from there), N a kinematic sphere placed on its path. Contact from the manifolds that
// stepSimulation's collision pass built on the state at the start of the step (points with
// distance <= 0); the sequential-impulse solver applies the contact response.
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <memory>

#include "engines/bullet/bullet_car.hpp"
#include "engines/bullet/bullet_core.hpp"
#include "engines/driven_disks.hpp"

namespace liftcheck {

namespace {

class BulletDisks final : public DrivenDisks {
 public:
  ~BulletDisks() override { teardown(); }

 protected:
  void build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) override {
    teardown();
    core_ = std::make_unique<BulletCore>();
    world_ = core_->make_world<btDiscreteDynamicsWorld>();
    world_->setGravity(btVector3(0, 0, 0));
    shape_ = std::make_unique<btSphereShape>(setup.radius_m);
    const disks::Vec2 at[2] = {cM0, cN0};
    for (int i = 0; i < 2; ++i) {
      const double mass = i == 0 ? 1.0 : 0.0;
      btVector3 inertia(0, 0, 0);
      if (mass > 0) shape_->calculateLocalInertia(mass, inertia);
      btRigidBody::btRigidBodyConstructionInfo ci(mass, nullptr, shape_.get(), inertia);
      ci.m_startWorldTransform.setIdentity();
      ci.m_startWorldTransform.setOrigin(btVector3(at[i].x(), at[i].y(), 0));
      // Bullet multiplies the two bodies' coefficients: mu_MN x 1, 0 in every scenario.
      ci.m_friction = i == 0 ? setup.mu_MN : 1.0;
      ci.m_linearDamping = 0.0;
      ci.m_angularDamping = 0.0;
      body_[i] = std::make_unique<btRigidBody>(ci);
      body_[i]->setActivationState(DISABLE_DEACTIVATION);
      world_->addRigidBody(body_[i].get());
    }
    body_[1]->setCollisionFlags(body_[1]->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
    body_[0]->setLinearFactor(btVector3(1, 1, 0));  // M stays in the plane
    // M's rotation held about every axis (Bullet's angular factor, as its character controllers
    // hold theirs): the solver sees no rotational freedom, a tangential contact force moves M.
    body_[0]->setAngularFactor(btVector3(0, 0, 0));
  }

  StepContacts step(const disks::Vec2& vM_cmd, const disks::Vec2& cN_next, const disks::Vec2&, double dt_s) override {
    body_[0]->setLinearVelocity(btVector3(vM_cmd.x(), vM_cmd.y(), 0));
    world_->stepSimulation(dt_s, 1, dt_s);
    StepContacts c;
    btDispatcher* d = world_->getDispatcher();
    for (int i = 0; i < d->getNumManifolds(); ++i) {
      const btPersistentManifold* m = d->getManifoldByIndexInternal(i);
      for (int k = 0; k < m->getNumContacts(); ++k) {
        const double dist = m->getContactPoint(k).getDistance();
        if (dist > 0) continue;  // a speculative point short of contact
        c.count += 1;
        c.depth_max_m = std::max(c.depth_max_m, -dist);
      }
    }
    // N moves along its path: a kinematic body is placed; Bullet derives its velocity for the
    // next step from the move.
    btTransform tf;
    tf.setIdentity();
    tf.setOrigin(btVector3(cN_next.x(), cN_next.y(), 0));
    body_[1]->setWorldTransform(tf);
    return c;
  }

  State read() const override {
    const btVector3 w = body_[0]->getAngularVelocity();
    return {at(0), at(1), {w.x(), w.y(), w.z()}};
  }

 private:
  disks::Vec2 at(int i) const {
    const btVector3 p = body_[i]->getWorldTransform().getOrigin();
    return {p.x(), p.y()};
  }
  void teardown() {
    if (world_)
      for (auto& b : body_)
        if (b) world_->removeRigidBody(b.get());
    for (auto& b : body_) b.reset();
    world_.reset();
  }
  std::unique_ptr<BulletCore> core_;
  std::unique_ptr<btDiscreteDynamicsWorld> world_;
  std::unique_ptr<btSphereShape> shape_;
  std::unique_ptr<btRigidBody> body_[2];
};

}  // namespace

std::unique_ptr<DiskEngine> make_bullet_disks() { return std::make_unique<BulletDisks>(); }

}  // namespace liftcheck
