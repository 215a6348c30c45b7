// The fixed-steering circle (Fecko, appendix D), and the same circle driven past the grip limit.
#include <cmath>
#include <fmt/format.h>
#include <map>

#include "models/holonomy.hpp"
#include "models/lift.hpp"
#include "scenarios/car_common.hpp"
#include "scenarios/fit.hpp"

namespace liftcheck {

using namespace car_common;

namespace {

// ---- car.circle ----------------------------------------------------------------------------

Outcome run_circle(const Params& p, CarEngine& engine) {
  const CarSetup setup = setup_from(p);
  const Config q0 = start_from(p);
  if (std::abs(q0.beta_rad) < 1e-3)
    throw InputError("car.circle needs |beta| >= 0.001 rad: beta = 0 drives a straight line");
  const double d_alpha = p.num("drive") / setup.car.R_m;
  const car::BasePath path({{d_alpha, 0.0}}, 0.0, q0.beta_rad, setup.drive);
  if (path.duration_s() / setup.sample_dt_s < 8.0)
    throw InputError(
        fmt::format("car.circle needs at least 8 samples of the drive to fit its circle: sample_dt = {:g} s is too "
                    "coarse for {:.3g} s",
                    setup.sample_dt_s, path.duration_s()));
  const auto trace = drive_checked(engine, setup, q0, path);
  Outcome traced;
  add_trace_check(traced, engine, setup, path, q0, trace);

  std::vector<Eigen::Vector2d> front, rear;
  for (const auto& s : trace) {
    front.emplace_back(s.q.x_m, s.q.y_m);
    rear.push_back(car::rear_axle_W(setup.car, s.q));
  }
  const CircleFit ff = fit_circle(front), rf = fit_circle(rear);
  const car::Circle fe = car::front_circle(setup.car, q0), re = car::rear_circle(setup.car, q0);
  const Config end_exact = car::flow_alpha(setup.car, q0, d_alpha);
  const Config& end = trace.back().q;

  Outcome o = traced;
  o.values["front_radius"] = {fe.radius_m, ff.radius_m};
  o.values["rear_radius"] = {re.radius_m, rf.radius_m};
  o.values["center_x"] = {fe.cx_m, ff.cx_m};
  o.values["center_y"] = {fe.cy_m, ff.cy_m};
  o.values["final_offset"] = {0.0, std::hypot(end.x_m - end_exact.x_m, end.y_m - end_exact.y_m)};
  // The reference integrates the heading through the whole turn: its round-off and integration
  // error (1e-13 a step) grow with the angle turned, so its tolerance is per full turn (at l = 1 mm
  // the 10 m circle turns 2955 rad: 4.5e-9 rad, 1.5e-12 of it). Every engine's is the angle's.
  const double turns = std::abs(end_exact.phi_rad - q0.phi_rad) / (2.0 * std::numbers::pi);
  o.values["final_heading_error"] = {.expected = 0.0,
                                     .measured = std::abs(e2::wrap_angle(end.phi_rad - end_exact.phi_rad)),
                                     .tolerance_factor = engine.exact_by_construction() ? std::max(1.0, turns) : 1.0};
  // Appendix D: at fixed steering the front wheel moves along the circle about the exact centre,
  // so the tie rod's heading is the radius direction turned by +-pi/2 - beta0 (the rear wheels
  // roll along the rod). The engine's heading is checked against its own position at every sample.
  double heading_residual = 0.0;
  const double turn = q0.beta_rad > 0.0 ? kHalfPi : -kHalfPi;
  for (const auto& smp : trace) {
    const double expected_phi = std::atan2(smp.q.y_m - fe.cy_m, smp.q.x_m - fe.cx_m) + turn - q0.beta_rad;
    heading_residual = std::max(heading_residual, std::abs(e2::wrap_angle(smp.q.phi_rad - expected_phi)));
  }
  // Engines integrate the heading step by step: first order in dt, so the tolerance (data at
  // 1 ms) scales with dt / 1 ms.
  o.values["heading_residual"] = {.expected = 0.0, .measured = heading_residual, .tolerance_factor = setup.dt_s / 1e-3};
  add_realized_lift(o, engine, setup, path, trace);
  o.values["com_accel_excess"] = {
      .expected = 0.0, .measured = com_accel_excess(setup, trace), .informational = engine.exact_by_construction()};
  // Lateral acceleration of the front wheel against the friction limit: the kinematic model holds
  // only while v^2 / (r g) is well below mu.
  const double grip_use = setup.drive.speed_mps * setup.drive.speed_mps / (fe.radius_m * setup.gravity_mps2) / setup.mu;
  o.details = {{detail_key::kTrace, trace_json(trace)},
               {detail_key::kReference, reference_json(setup, path, q0)},
               {"front_fit_rms_m", ff.rms_residual_m},
               {"rear_fit_rms_m", rf.rms_residual_m},
               {"path_length_m", p.num("drive")},
               {detail_key::kGripUse, grip_use},
               {detail_key::kErrors, error_split(setup.car, trace, end_exact)}};
  add_slip(o, engine);
  return o;
}

/// The drive car.slip and car.beyond-grip both judge.
constexpr const char* kPastGripDrive = "circle past the grip limit";

/// car.beyond-grip: the circle driven faster than the grip allows (v^2/(r g) > mu). Coulomb's law
/// bounds the centre of mass's horizontal acceleration by mu g, so the car must slide off the lift:
/// the fitted front circle opens by at least kRequiredOpening (the lift's circle needs more than
/// mu g; the least circle the friction can hold at the same speed is wider by the ratio).
constexpr double kRequiredOpening = 0.01;

/// The grip the exact circle needs, in mu g; InputError unless it is past the limit by 20%.
double beyond_grip_need(const Params& p) {
  const CarSetup setup = setup_from(p);
  const car::Circle fe = car::front_circle(setup.car, start_from(p));
  const double need = setup.drive.speed_mps * setup.drive.speed_mps / fe.radius_m / (setup.mu * setup.gravity_mps2);
  if (!(need > 1.2))
    throw InputError(
        fmt::format("car.beyond-grip needs v^2/(r g) > 1.2 mu to be past the grip limit: it is {:.3g} mu", need));
  return need;
}

/// car.beyond-grip's judgement of the circle's full outcome (run_circle).
Outcome judge_beyond_grip(const Params& p, const Outcome& o) {
  const double need = beyond_grip_need(p);
  const car::Circle fe = car::front_circle(setup_from(p).car, start_from(p));
  const double opening = (o.values.at("front_radius").measured - fe.radius_m) / fe.radius_m;
  Outcome b;
  b.values["com_accel_excess"] = o.values.at("com_accel_excess");
  b.values["com_accel_excess"].informational = false;
  b.values["slide_shortfall"] = {0.0, std::max(0.0, 1.0 - opening / kRequiredOpening)};
  b.details = o.details;
  b.details["front_radius_opening"] = opening;
  b.details["lift_needs_mu_g"] = need;
  for (const char* k : {"slip_along_max", "slip_across_max", "slip_rms"})
    if (o.values.count(k)) b.values[k] = o.values.at(k), b.values[k].informational = true;  // sliding is the point here
  for (const char* k : {"load_at_rest", "load_over_drive", "momentum_balance"})             // sliding or not: Newton
    if (o.values.count(k)) b.values[k] = o.values.at(k);
  return b;
}

/// car.slip's judgement of the circle's full outcome: the no-slip comparison, which must fail.
Outcome judge_slip(const Params&, Outcome o) {
  for (const char* keep_out :
       {"center_x", "center_y", "final_heading_error", "heading_residual", "realized_lift_error", "com_accel_excess"})
    o.values.erase(keep_out);
  return o;
}

}  // namespace

std::vector<Scenario> circle_scenarios() {
  return {{.name = "car.circle",
           .vehicle = Vehicle::kCar,
           .summary = "Fixed steering: the front-axle centre draws a circle of radius l/sin(beta0), the rear-axle "
                      "centre one of radius l/tan(beta0), about the same centre.",
           .equations = "(4.1), (D.1), appendix D",
           // 10 m of arc (3 rad of the 3.38 m circle: what the radius fit needs, and what keeps the
           // start's transient from weighing on it) at 2 m/s after ramps of 2 m/s^2: 5 s of cruise,
           // 6.6 s with the ramps; the grip use v^2/(r g mu) is 0.12.
           .params = with(
               with_defaults(car_params("0.3"), {{"speed", "2.0"}, {"accel", "2.0"}}),
               {number("drive", "10", "m", "front-wheel path length (enough arc to fit a circle)", 1.0, false, 1e4)}),
           .metrics = {rel("front_radius", "m", 1e-9, 1e-4, "fitted radius of the front-axle centre's path"),
                       rel("rear_radius", "m", 1e-9, 1e-4, "fitted radius of the rear-axle centre's path"),
                       abs_("center_x", "m", 1e-9, 1e-3, "fitted circle centre, world x"),
                       abs_("center_y", "m", 1e-9, 1e-3, "fitted circle centre, world y"),
                       abs_("final_offset", "m", 1e-9, 1e-3, "front-axle centre at the end against the exact arc"),
                       abs_("final_heading_error", "rad", 1e-9, 1e-3, "heading at the end against the exact arc"),
                       abs_("heading_residual", "rad", 1e-9, 1e-5,
                            "largest difference between the heading and the one the exact circle gives at the sampled "
                            "position (tolerance at dt = 1 ms, x dt / 1 ms)"),
                       REALIZED_LIFT, COM_ACCEL, SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, LOAD_REST, LOAD_DRIVE, MOMENTUM,
                       TRACE_PATH, TRACE_SHAPE, STEER_LAG, DRIVE_LAG},
           .run_car = run_circle,
           .headline = {.metrics = {"front_radius", "rear_radius"}, .label = "radius"}}};
}

std::vector<Scenario> grip_scenarios() {
  return {
      {.name = "car.beyond-grip",
       .vehicle = Vehicle::kCar,
       .summary =
           "Past the grip limit (car.slip's drive: 3 m/s on the 3.4 m circle, mu = 0.1, the lift needs 2.7 mu g): the "
           "ground pushes the car by at most mu times its weight, so its centre of mass may not accelerate "
           "horizontally "
           "by more than mu g, and the car must slide off the lift (its front circle opens by at least 1%).",
       .equations = "Coulomb friction bounds (4.1)",
       .params = with_defaults(
           with(car_params("0.3"), {number("drive", "10", "m", "front-wheel path length", 0.0, true, 1e4)}),
           {{"mu", "0.1"}, {"speed", "3.0"}}),
       .metrics = {COM_ACCEL,
                   abs_("slide_shortfall", "1", 1e-9, 0.0,
                        "1 - (front circle's opening)/(1%), or 0 when it opened by 1% or more: the car kept grip the "
                        "friction cannot give"),
                   SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, LOAD_REST, LOAD_DRIVE, MOMENTUM},
       .run_car =
           [](const Params& p, CarEngine& engine) {
             beyond_grip_need(p);  // before the drive: a --set that leaves the grip is bad input
             return judge_beyond_grip(p, run_circle(p, engine));
           },
       // car.slip's drive: a suite with both makes it once.
       .shared_drive = SharedDrive{kPastGripDrive, run_circle, judge_beyond_grip},
       .needs_contact_dynamics = true,
       // Both halves of the engine's error: grip the friction cannot give (as a fraction of mu g, and
       // as the share of the 1% opening the circle failed to make).
       .headline = {.metrics = {"com_accel_excess", "slide_shortfall"}, .label = "excess grip"}},
      {.name = "car.slip",
       .vehicle = Vehicle::kCar,
       .summary = "Negative control: at 3 m/s on a 3.4 m circle with mu = 0.1 the lateral acceleration needs "
                  "v^2/(r g) = 0.27 > mu, so the car slides; the harness must detect it and the no-slip "
                  "comparison must fail.",
       .equations = "(4.1) fails without grip",
       .params = with_defaults(
           with(car_params("0.3"), {number("drive", "10", "m", "front-wheel path length", 0.0, true, 1e4)}),
           {{"mu", "0.1"}, {"speed", "3.0"}}),
       .metrics = {rel("front_radius", "m", 1e-9, 1e-4, "fitted radius of the front-axle centre's path"),
                   rel("rear_radius", "m", 1e-9, 1e-4, "fitted radius of the rear-axle centre's path"),
                   abs_("final_offset", "m", 1e-9, 1e-3, "front-axle centre at the end against the exact arc"),
                   SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, LOAD_REST, LOAD_DRIVE, MOMENTUM, TRACE_PATH, TRACE_SHAPE,
                   STEER_LAG, DRIVE_LAG},
       .run_car = [](const Params& p, CarEngine& engine) { return judge_slip(p, run_circle(p, engine)); },
       .shared_drive = SharedDrive{kPastGripDrive, run_circle, judge_slip},
       .needs_contact_dynamics = true,
       .negative_control = true,
       .headline = {.metrics = {"front_radius", "rear_radius"}, .label = "radius"}}};
}

}  // namespace liftcheck
