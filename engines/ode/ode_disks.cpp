// Two disks in ODE: kinematic bodies (dBodySetKinematic) with sphere geoms of radius 1 in the
// plane z = 0, moved by setting their velocities for one dWorldStep; contact from dCollide.
#include <ode/ode.h>

#include <mutex>

#include "engines/ode/ode_car.hpp"
#include "engines/stepped_disks.hpp"

namespace liftcheck {

namespace {

class OdeDisks final : public SteppedDisks {
 public:
  ~OdeDisks() override { destroy(); }

 protected:
  void place(const DiskSetup& setup, const disks::Vec2& cM, const disks::Vec2& cN) override {
    static std::once_flag once;
    std::call_once(once, [] { dInitODE2(0); });
    destroy();
    world_ = dWorldCreate();
    dWorldSetGravity(world_, 0, 0, 0);
    for (int i = 0; i < 2; ++i) {
      body_[i] = dBodyCreate(world_);
      dBodySetKinematic(body_[i]);
      geom_[i] = dCreateSphere(nullptr, setup.radius_m);
      dGeomSetBody(geom_[i], body_[i]);
    }
    dBodySetPosition(body_[0], cM.x(), cM.y(), 0.0);
    dBodySetPosition(body_[1], cN.x(), cN.y(), 0.0);
  }

  void move(const disks::Vec2& cM_next, const disks::Vec2& cN_next, double dt_s) override {
    const disks::Vec2 next[2] = {cM_next, cN_next};
    for (int i = 0; i < 2; ++i) {
      const dReal* p = dBodyGetPosition(body_[i]);
      dBodySetLinearVel(body_[i], (next[i].x() - p[0]) / dt_s, (next[i].y() - p[1]) / dt_s, 0.0);
    }
    dWorldStep(world_, dt_s);
  }

  disks::Vec2 read_M() const override { return read(0); }
  disks::Vec2 read_N() const override { return read(1); }

  bool in_contact() override {
    dContactGeom c;
    return dCollide(geom_[0], geom_[1], 1, &c, sizeof(dContactGeom)) > 0;
  }

 private:
  disks::Vec2 read(int i) const {
    const dReal* p = dBodyGetPosition(body_[i]);
    return {p[0], p[1]};
  }
  void destroy() {
    for (auto& g : geom_)
      if (g) dGeomDestroy(g), g = nullptr;
    if (world_) dWorldDestroy(world_), world_ = nullptr;
  }
  dWorldID world_ = nullptr;
  dBodyID body_[2] = {nullptr, nullptr};
  dGeomID geom_[2] = {nullptr, nullptr};
};

}  // namespace

std::unique_ptr<DiskEngine> make_ode_disks() { return std::make_unique<OdeDisks>(); }

}  // namespace liftcheck
