#include "engines/analytic/analytic.hpp"

#include "models/disk_contact.hpp"

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
    simulated_s_ += path.duration_s();
    return car::lift(setup_.car, path, q0_, def);
  }
  bool exact_by_construction() const override { return true; }
  GroundLoad ground_load() const override {
    return {.absent_why = "the exact lift (4.1) is kinematics: it has no contact forces"};
  }
  std::vector<WheelSlip> slip() const override { return {}; }  // rolls without slipping by construction
  double simulated_s() const override { return simulated_s_; }

 private:
  CarSetup setup_;
  car::Config q0_;
  double simulated_s_ = 0.0;
};

class AnalyticDisks final : public DiskEngine {
 public:
  DiskRun run(const DiskSetup& setup, const DiskProblem& pb) override {
    disks::LiftDef def;
    def.sample_dt_s = setup.sample_dt_s;
    const disks::LiftResult r = disks::lift(pb.rule, pb.path, pb.cM0, pb.T_s, def);
    simulated_s_ += pb.T_s;
    DiskRun out;
    out.t_contact_s = r.t_contact_s;
    out.min_distance = r.min_distance;
    out.trace = r.trace;
    if (!r.t_contact_s) return out;
    // Past the first contact the lift goes on with the frictionless, inelastic contact response.
    const disks::ResponseResult c = disks::lift_with_response(pb.rule, pb.path, pb.cM0, 0.0, pb.T_s, def);
    out.t_contact_s = c.t_contact_s;
    out.contact_state = disks::Sample{*c.t_contact_s, c.cM_contact, pb.path.position(*c.t_contact_s)};
    out.t_release_s = c.t_release_s;
    out.trace = c.trace;
    return out;
  }
  double simulated_s() const override { return simulated_s_; }

 private:
  double simulated_s_ = 0.0;
};

}  // namespace

EngineInfo analytic_engine() {
  return {
      .name = "analytic",
      .library = "liftcheck",
      .version = "1",
      .description =
          "the exact models: car by the horizontal lift (4.1), disks by the lift (21) with root-found contact",
      .color = "#1a1a1a",
      .is_reference = true,
      .make_car = [](const Settings&) { return std::make_unique<AnalyticCar>(); },
      .make_disks = [](const Settings&) { return std::make_unique<AnalyticDisks>(); },
      .contact_dynamics = false,
      .settings =
          {{"car integrator", "Boost.Odeint runge_kutta_dopri5, dense output, abs and rel tolerance 1e-13"},
           {"disk integrator",
            "Boost.Odeint runge_kutta_dopri5 at 1e-12; first contact by TOMS 748 on the dense output; after contact "
            "the frictionless, inelastic response (M on |c_M - c_N| = 2 until its command points away from N)"},
           {"wheels",
            "3 or 4: the lift of the commanded (alpha, beta) is the reference for both (a four-wheel car's alpha is "
            "its front-axle centre's rolling angle, beta its virtual steering angle); gravity and its tilt do not "
            "enter the kinematics"}},
      .four_wheels = true};
}

}  // namespace liftcheck
