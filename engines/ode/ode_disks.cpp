#include "engines/ode/ode_disks.hpp"

#include <algorithm>

#include "engines/ode/ode_car.hpp"

namespace liftcheck {

namespace {
constexpr double kMassM_kg = 1.0;
}  // namespace

OdeDisks::~OdeDisks() { destroy(); }

void OdeDisks::build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) {
  destroy();
  mu_MN_ = setup.mu_MN;
  sim_ = std::make_unique<OdeWorld>(stepper_, Eigen::Vector3d::Zero());
  world_ = sim_->id();
  space_ = dSimpleSpaceCreate(nullptr);
  contacts_ = dJointGroupCreate(0);
  const disks::Vec2 at[2] = {cM0, cN0};
  dBodyID* body[2] = {&M_, &N_};
  for (int i = 0; i < 2; ++i) {
    *body[i] = dBodyCreate(world_);
    dMass m;
    dMassSetSphereTotal(&m, kMassM_kg, setup.radius_m);
    dBodySetMass(*body[i], &m);
    dBodySetPosition(*body[i], at[i].x(), at[i].y(), 0.0);
    dGeomSetBody(dCreateSphere(space_, setup.radius_m), *body[i]);
  }
  dBodySetKinematic(N_);
  // M's rotation is held by an angular motor about the world's three axes (dAMotorUser, target 0,
  // unbounded torque), ODE's joint for holding a body's orientation: the solver sees M as a body
  // that cannot turn, so a tangential contact force moves it instead of spinning it.
  if (hold_spin_) {
    dJointID hold = dJointCreateAMotor(world_, nullptr);
    dJointAttach(hold, M_, nullptr);
    dJointSetAMotorMode(hold, dAMotorUser);
    dJointSetAMotorNumAxes(hold, 3);
    dJointSetAMotorAxis(hold, 0, 0, 1, 0, 0);
    dJointSetAMotorAxis(hold, 1, 0, 0, 1, 0);
    dJointSetAMotorAxis(hold, 2, 0, 0, 0, 1);
    for (int p : {dParamFMax1, dParamFMax2, dParamFMax3}) dJointSetAMotorParam(hold, p, dInfinity);
  }
  // M is velocity-commanded: its linear velocity is set to the command before each step (as Bullet's
  // is) and ODE's integrator and contact joints take it from there. A dJointLMotor would not do: its
  // three world-axis rows are force-bounded each on its own, so against a contact (unbounded) the
  // row that saturates yields while the others hold their command, and M sticks to N along them.
}

void OdeDisks::near_callback(void* data, dGeomID o1, dGeomID o2) {
  auto* self = static_cast<OdeDisks*>(data);
  dContact contact[4];
  const int n = dCollide(o1, o2, 4, &contact[0].geom, sizeof(dContact));
  for (int i = 0; i < n; ++i) {
    // Coulomb friction mu_MN (dContactApprox1: mu a coefficient of the normal force, not a force
    // cap, as the car's wheels have it); 0 in every scenario: only the normal response.
    contact[i].surface.mode = self->mu_MN_ > 0.0 ? dContactApprox1 : 0;
    contact[i].surface.mu = self->mu_MN_;
    const bool keep = self->keep_contact(contact[i]);
    self->seen_.count += 1;
    self->seen_.depth_max_m = std::max(self->seen_.depth_max_m, static_cast<double>(contact[i].geom.depth));
    if (!keep) continue;
    dJointID j = dJointCreateContact(self->world_, self->contacts_, &contact[i]);
    dJointAttach(j, dGeomGetBody(contact[i].geom.g1), dGeomGetBody(contact[i].geom.g2));
  }
}

DrivenDisks::StepContacts OdeDisks::step(const disks::Vec2& vM_cmd, const disks::Vec2& cN_next, const disks::Vec2&,
                                         double dt_s) {
  dBodySetLinearVel(M_, vM_cmd.x(), vM_cmd.y(), 0.0);
  // N is kinematic: ODE integrates the velocity that lands it on its path at the end of the step.
  const dReal* p = dBodyGetPosition(N_);
  dBodySetLinearVel(N_, (cN_next.x() - p[0]) / dt_s, (cN_next.y() - p[1]) / dt_s, 0.0);
  seen_ = {};
  dSpaceCollide(space_, this, &OdeDisks::near_callback);
  sim_->step(dt_s);
  dJointGroupEmpty(contacts_);
  return seen_;
}

DrivenDisks::State OdeDisks::read() const {
  const dReal* m = dBodyGetPosition(M_);
  const dReal* n = dBodyGetPosition(N_);
  const dReal* w = dBodyGetAngularVel(M_);
  return {{m[0], m[1]}, {n[0], n[1]}, {w[0], w[1], w[2]}};
}

void OdeDisks::destroy() {
  if (contacts_) dJointGroupDestroy(contacts_);
  if (space_) dSpaceDestroy(space_);
  sim_.reset();
  contacts_ = nullptr;
  space_ = nullptr;
  world_ = nullptr;
}

std::unique_ptr<DiskEngine> make_ode_disks(const OdeStepper& stepper) { return std::make_unique<OdeDisks>(stepper); }

}  // namespace liftcheck
