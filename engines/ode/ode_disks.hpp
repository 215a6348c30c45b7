// Two disks in ODE: M a dynamic sphere whose linear velocity is set to its command before each
// step and whose rotation an angular motor holds, N a kinematic sphere moved along its path; contact joints from
// dCollide in the near callback of each step (frictionless, the world's ERP and CFM).
#pragma once

#include <ode/ode.h>

#include <memory>

#include "engines/driven_disks.hpp"
#include "engines/ode/ode_car.hpp"

namespace liftcheck {

class OdeDisks : public DrivenDisks {
 public:
  explicit OdeDisks(const OdeStepper& stepper = {}) : stepper_(stepper) {}
  /// Test hook (the fault-injection suite): M's spin left free.
  OdeDisks(const OdeStepper& stepper, bool hold_spin) : stepper_(stepper), hold_spin_(hold_spin) {}
  ~OdeDisks() override;

 protected:
  void build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) override;
  StepContacts step(const disks::Vec2& vM_cmd, const disks::Vec2& cN_next, const disks::Vec2& vN, double dt_s) override;
  State read() const override;

  /// Last word on an M-N contact before its joint is made: false makes none (the fault-injection
  /// suite changes contacts here); liftcheck's model keeps every contact as built.
  virtual bool keep_contact(dContact&) { return true; }
  dWorldID world() const { return world_; }
  dBodyID body_M() const { return M_; }

 private:
  static void near_callback(void* data, dGeomID o1, dGeomID o2);
  void destroy();
  std::unique_ptr<OdeWorld> sim_;
  dWorldID world_ = nullptr;  ///< sim_'s world
  dSpaceID space_ = nullptr;
  dJointGroupID contacts_ = nullptr;
  dBodyID M_ = nullptr, N_ = nullptr;
  StepContacts seen_;
  OdeStepper stepper_;
  bool hold_spin_ = true;
  double mu_MN_ = 0.0;  ///< DiskSetup::mu_MN
};

}  // namespace liftcheck
