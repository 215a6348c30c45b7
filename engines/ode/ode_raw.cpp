// The benchmarks' raw ODE loop: OdeCar's bodies, joints and contact callback, stepped by direct
// API calls with the motors set once (engines/raw_car.hpp).
#include <ode/ode.h>

#include "engines/ode/ode_car.hpp"
#include "engines/ode/ode_car_model.hpp"

namespace liftcheck {

class OdeRawCar final : public RawCar {
 public:
  OdeRawCar(const Settings& s, const OdeStepper& stepper, const CarSetup& setup, const car::Config& q0)
      : car_(s, stepper), dt_s_(setup.dt_s) {
    car_.reset(setup, q0);
  }

  void run(long steps, double spin_radps) override {
    const ServoDef& servo = car_.servo_;  // the run's own limits (ServoDef::for_car)
    // Body 1 (chassis) relative to body 2 (wheel): rates negated, as OdeCar::actuate does.
    dJointSetHinge2Param(car_.steer_joint_[0], dParamVel, 0.0);
    dJointSetHinge2Param(car_.steer_joint_[0], dParamFMax, servo.steer_torque_max_Nm);
    dJointSetHinge2Param(car_.steer_joint_[0], dParamVel2, -spin_radps);
    dJointSetHinge2Param(car_.steer_joint_[0], dParamFMax2, servo.spin_torque_max_Nm);
    const bool quick = car_.stepper_.quick;
    for (long k = 0; k < steps; ++k) {
      dSpaceCollide(car_.space_, &car_, &OdeCar::near_callback);
      if (quick)
        dWorldQuickStep(car_.world_, dt_s_);
      else
        dWorldStep(car_.world_, dt_s_);
      dJointGroupEmpty(car_.contacts_);
    }
  }

  Eigen::Vector2d front_xy_m() const override {
    const dReal* p = dBodyGetPosition(car_.front_[0]);
    return {p[0], p[1]};
  }

 private:
  OdeCar car_;
  double dt_s_;
};

std::unique_ptr<RawCar> make_raw_ode_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<OdeRawCar>(s, OdeStepper{}, setup, q0);
}

std::unique_ptr<RawCar> make_raw_ode_quick_car(const Settings& s, const CarSetup& setup, const car::Config& q0) {
  return std::make_unique<OdeRawCar>(s, OdeStepper::quick_from(s), setup, q0);
}

}  // namespace liftcheck
