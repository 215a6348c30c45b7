#include "engines/analytic/analytic.hpp"

namespace liftcheck {

namespace {

class AnalyticCar final : public CarEngine {
 public:
  void reset(const CarSetup& setup, const car::Config& q0) override {
    setup_ = setup;
    q0_ = q0;
  }
  std::vector<car::TimedConfig> drive(const car::BasePath& path) override {
    car::LiftDef def;
    def.sample_dt_s = setup_.sample_dt_s;
    return car::lift(setup_.car, path, q0_, def);
  }

 private:
  CarSetup setup_;
  car::Config q0_;
};

}  // namespace

EngineInfo analytic_engine() {
  return {"analytic", "1", "horizontal lift (4.1), Boost.Odeint dopri5 at 1e-13",
          [] { return std::make_unique<AnalyticCar>(); }, false,
          {{"integrator", "Boost.Odeint runge_kutta_dopri5, dense output, abs and rel tolerance 1e-13"}}};
}

}  // namespace liftcheck
