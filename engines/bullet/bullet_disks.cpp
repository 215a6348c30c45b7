// Two disks in Bullet (double precision): kinematic rigid bodies (CF_KINEMATIC_OBJECT) with
// sphere shapes of radius 1, moved by their world transforms each step; contact from
// contactPairTest (manifolds read after stepSimulation lag a few steps), points with
// distance <= 0.
#include <btBulletDynamicsCommon.h>

#include <memory>

#include "engines/bullet/bullet_car.hpp"
#include "engines/bullet/bullet_core.hpp"
#include "engines/stepped_disks.hpp"

namespace liftcheck {

namespace {

struct Touch : btCollisionWorld::ContactResultCallback {
  bool touching = false;
  btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper*, int, int,
                           const btCollisionObjectWrapper*, int, int) override {
    if (cp.getDistance() <= 0) touching = true;
    return 0;
  }
};

class BulletDisks final : public SteppedDisks {
 public:
  ~BulletDisks() override { teardown(); }

 protected:
  void place(const DiskSetup& setup, const disks::Vec2& cM, const disks::Vec2& cN) override {
    teardown();
    core_ = std::make_unique<BulletCore>();
    world_ = core_->make_world<btDiscreteDynamicsWorld>();
    world_->setGravity(btVector3(0, 0, 0));
    shape_ = std::make_unique<btSphereShape>(setup.radius_m);
    const disks::Vec2 at[2] = {cM, cN};
    for (int i = 0; i < 2; ++i) {
      btRigidBody::btRigidBodyConstructionInfo ci(0.0, nullptr, shape_.get());
      ci.m_startWorldTransform.setIdentity();
      ci.m_startWorldTransform.setOrigin(btVector3(at[i].x(), at[i].y(), 0));
      body_[i] = std::make_unique<btRigidBody>(ci);
      body_[i]->setCollisionFlags(body_[i]->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
      body_[i]->setActivationState(DISABLE_DEACTIVATION);
      world_->addRigidBody(body_[i].get());
    }
  }

  void move(const disks::Vec2& cM_next, const disks::Vec2& cN_next, double dt_s) override {
    const disks::Vec2 next[2] = {cM_next, cN_next};
    for (int i = 0; i < 2; ++i) {
      btTransform tf;
      tf.setIdentity();
      tf.setOrigin(btVector3(next[i].x(), next[i].y(), 0));
      body_[i]->setWorldTransform(tf);
    }
    world_->stepSimulation(dt_s, 1, dt_s);
  }

  disks::Vec2 read_M() const override { return read(0); }
  disks::Vec2 read_N() const override { return read(1); }

  bool in_contact() override {
    Touch t;
    world_->contactPairTest(body_[0].get(), body_[1].get(), t);
    return t.touching;
  }

 private:
  disks::Vec2 read(int i) const {
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
