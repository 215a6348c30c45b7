// The parking cycles and their holonomies (Fecko, section 5), steering in place, the lift's
// reparametrisation invariance and its E(2) covariance.
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

// ---- car.covariance ------------------------------------------------------------------------

/// The pose `q` seen from the frame of `start`: g^{-1} q with g the element of (A.5) for `start`.
e2::Pose in_frame_of(const Config& start, const Config& q) {
  const double c = std::cos(start.phi_rad), s = std::sin(start.phi_rad);
  const double dx = q.x_m - start.x_m, dy = q.y_m - start.y_m;
  return {c * dx + s * dy, -s * dx + c * dy, q.phi_rad - start.phi_rad};
}

Outcome run_covariance(const Params& p, CarEngine& engine) {
  const CarSetup setup = setup_from(p);
  const Config q0 = start_from(p);
  const int n = p.integer("headings");
  const Eigen::Vector2d shift = p.vec("shift");
  const double d_alpha = p.num("drive") / setup.car.R_m;
  // The manoeuvre: a fixed-steering arc, then the simple parking cycle.
  std::vector<car::Segment> segs{{d_alpha, 0.0}};
  for (const auto& seg : car::to_segments(car::simple_cycle(0.3, 0.3))) segs.push_back(seg);
  const car::BasePath path(segs, 0.0, q0.beta_rad, setup.drive);
  const e2::Pose exact = in_frame_of(q0, car::lift_end(setup.car, path, q0));

  double worst = 0.0;
  nlohmann::json rows = nlohmann::json::array();
  std::vector<e2::Pose> seen;
  for (int k = 0; k < n; ++k) {
    const double theta = 2.0 * std::numbers::pi * k / n;
    const Config start = car::act(e2::element(theta, k % 2 ? shift.x() : 0.0, k % 2 ? shift.y() : 0.0), q0);
    const auto trace = drive_checked(engine, setup, start, path);
    const e2::Pose local = in_frame_of(trace.front().q, trace.back().q);
    seen.push_back(local);
    worst = std::max(worst, std::hypot(local.x_m - exact.x_m, local.y_m - exact.y_m));
    nlohmann::json tr = trace_json(trace), thin = nlohmann::json::array();
    for (std::size_t i = 0; i < tr.size(); i += 4) thin.push_back(tr[i]);
    if ((tr.size() - 1) % 4 != 0) thin.push_back(tr.back());
    rows.push_back({{"theta_rad", theta},
                    {"start", {start.x_m, start.y_m, start.phi_rad}},
                    {"end_in_start_frame", {local.x_m, local.y_m, local.phi_rad}},
                    {detail_key::kTrace, thin}});
  }
  const auto [spread_xy, spread_phi] = pose_spread(seen);
  Outcome o;
  o.values["spread_xy"] = {0.0, spread_xy};
  o.values["spread_phi"] = {0.0, spread_phi};
  // In the default regime the wheels slide a little, identically at every heading: the distance
  // from the no-slip lift is information here, the no-slip check is car.circle's.
  // "drawing": the report draws every start and its path in one picture.
  o.details = {{detail_key::kRuns, rows},
               {detail_key::kDrawing, detail_key::kDrawingStarts},
               {"exact_end_in_start_frame", {exact.x_m, exact.y_m, exact.phi_rad}},
               {"largest_distance_from_no_slip_lift_m", worst}};
  return o;
}

// ---- holonomy of parking cycles ------------------------------------------------------------

/// Size of a pose change: root mean square of the displacements of the rod's two ends (front- and
/// rear-axle centres). Every component of a holonomy is compared relative to this size; a heading
/// change counts through the length l it swings the rod.
double rod_shift(const car::CarDef& c, const Config& from, const Config& to) {
  const Eigen::Vector2d front(to.x_m - from.x_m, to.y_m - from.y_m);
  const Eigen::Vector2d rear = car::rear_axle_W(c, to) - car::rear_axle_W(c, from);
  return std::sqrt(0.5 * (front.squaredNorm() + rear.squaredNorm()));
}

/// Drives `steps`, compares the net pose change with the exact holonomy and with the bracket
/// prediction (a tangent vector: its rod shift is taken to first order).
Outcome run_cycle(const Params& p, CarEngine& engine, const std::vector<car::Step>& steps, const Vec5& predicted,
                  double lo_factor) {
  const CarSetup setup = setup_from(p);
  const Config q0 = start_from(p);
  const car::BasePath path(car::to_segments(steps), 0.0, q0.beta_rad, setup.drive);
  const auto trace = drive_checked(engine, setup, q0, path);
  Outcome traced;
  add_trace_check(traced, engine, setup, path, q0, trace);
  // Net change from the engine's own start (a rigid car settles on its wheels before t = 0).
  const Vec5 d = trace.back().q.vec() - trace.front().q.vec();
  const Config end_exact = car::apply_exact(setup.car, q0, steps);
  const Vec5 exact = end_exact.vec() - q0.vec();

  const double l = setup.car.l_m;
  const double size = rod_shift(setup.car, q0, end_exact);
  const Config lo_end = Config::from(q0.vec() + predicted);
  const double lo_size = rod_shift(setup.car, q0, lo_end);
  // The bracket expansion is in eps R / l (the heading a wheel turn of eps swings the rod by), so
  // its relative error is of that order when R > l.
  lo_factor *= std::max(1.0, setup.car.R_m / setup.car.l_m);
  Outcome o = traced;
  o.values["dx"] = {.expected = exact[car::kX], .measured = d[car::kX], .scale = size};
  o.values["dy"] = {.expected = exact[car::kY], .measured = d[car::kY], .scale = size};
  o.values["dphi"] = {.expected = exact[car::kPhi], .measured = d[car::kPhi], .scale = size / l};
  o.values["base_closure"] = {.expected = 0.0,
                              .measured = std::hypot(d[car::kAlpha], d[car::kBeta]),
                              .informational = engine.exact_by_construction()};
  o.values["lo_dx"] = {
      .expected = predicted[car::kX], .measured = d[car::kX], .scale = lo_size, .tolerance_factor = lo_factor};
  o.values["lo_dy"] = {
      .expected = predicted[car::kY], .measured = d[car::kY], .scale = lo_size, .tolerance_factor = lo_factor};
  o.values["lo_dphi"] = {
      .expected = predicted[car::kPhi], .measured = d[car::kPhi], .scale = lo_size / l, .tolerance_factor = lo_factor};
  add_realized_lift(o, engine, setup, path, trace);
  o.details = {{detail_key::kTrace, trace_json(trace)},
               {detail_key::kReference, reference_json(setup, path, q0)},
               {detail_key::kSteps, steps.size()},
               {detail_key::kHolonomySize, size},
               {detail_key::kMeasuredSize, rod_shift(setup.car, trace.front().q, trace.back().q)},
               {detail_key::kHolonomyError,
                rod_shift(setup.car, end_exact, Config::from(trace.back().q.vec() - trace.front().q.vec() + q0.vec()))},
               {detail_key::kErrors, error_split(setup.car, trace, end_exact)}};
  add_slip(o, engine);
  return o;
}

Outcome run_simple_cycle(const Params& p, CarEngine& engine) {
  const double ea = p.num("eps_alpha"), eb = p.num("eps_beta");
  const car::CarDef c{p.num("R"), p.num("l")};
  return run_cycle(p, engine, car::simple_cycle(ea, eb), car::predicted_simple(c, start_from(p), ea, eb),
                   std::max(std::abs(ea), std::abs(eb)));
}

Outcome run_iterated_alpha(const Params& p, CarEngine& engine) {
  const double e = p.num("eps");
  const car::CarDef c{p.num("R"), p.num("l")};
  // The (5.8) cycle changes phi by exactly zero: each steering level drives a net zero alpha.
  return run_cycle(p, engine, car::iterated_cycle_alpha(e), car::predicted_iterated_alpha(c, start_from(p), e),
                   std::abs(e));
}

Outcome run_iterated_beta(const Params& p, CarEngine& engine) {
  const double e = p.num("eps");
  const car::CarDef c{p.num("R"), p.num("l")};
  return run_cycle(p, engine, car::iterated_cycle_beta(e), car::predicted_iterated_beta(c, start_from(p), e),
                   std::abs(e));
}

// ---- car.steer-in-place --------------------------------------------------------------------

Outcome run_steer_in_place(const Params& p, CarEngine& engine) {
  const CarSetup setup = setup_from(p);
  const Config q0 = start_from(p);
  const double d_beta = p.num("d_beta");
  if (std::abs(q0.beta_rad + d_beta) > 1.4) throw InputError("beta + d_beta must stay within [-1.4, 1.4] rad");
  const car::BasePath path({{0.0, d_beta}}, 0.0, q0.beta_rad, setup.drive);
  const auto trace = drive_checked(engine, setup, q0, path);
  Outcome traced;
  add_trace_check(traced, engine, setup, path, q0, trace);
  double max_shift = 0.0;
  for (const auto& s : trace) max_shift = std::max(max_shift, std::hypot(s.q.x_m - q0.x_m, s.q.y_m - q0.y_m));
  const Config& end = trace.back().q;
  Outcome o = traced;
  o.values["front_shift"] = {0.0, max_shift};
  o.values["dphi"] = {0.0, std::abs(e2::wrap_angle(end.phi_rad - q0.phi_rad))};
  o.values["beta_reached"] = {
      .expected = q0.beta_rad + d_beta, .measured = end.beta_rad, .informational = engine.exact_by_construction()};
  o.details = {{detail_key::kTrace, trace_json(trace)},
               {detail_key::kReference, reference_json(setup, path, q0)},
               {detail_key::kErrors, error_split(setup.car, trace, car::flow_beta(q0, d_beta))}};
  add_slip(o, engine);
  return o;
}

// ---- car.reparam ---------------------------------------------------------------------------

/// A path with segments that steer while driving (forwards and backwards): no closed form,
/// so the reference is the lift (4.1) integrated at tolerance 1e-13.
std::vector<car::Segment> reparam_segments() { return {{2.0, 0.3}, {3.0, -0.5}, {-2.0, 0.2}, {1.5, 0.0}}; }

Outcome run_reparam(const Params& p, CarEngine& engine) {
  const CarSetup base = setup_from(p);
  const Config q0 = start_from(p);
  const double f = p.num("factor");
  std::vector<Config> ends;
  nlohmann::json traces = nlohmann::json::array();
  for (double k : {1.0, f}) {
    // Every rate k times, every acceleration k^2 times: the run at pace k is the path of the run at
    // pace 1 played k times as fast (its duration over k), an exact reparametrisation of the same path.
    CarSetup s = base;
    s.drive.speed_mps *= k;
    s.drive.steer_rate_radps *= k;
    s.drive.accel_mps2 *= k * k;
    s.drive.steer_accel_radps2 *= k * k;
    const car::BasePath path(reparam_segments(), 0.0, q0.beta_rad, s.drive);
    const auto trace = drive_checked(engine, s, q0, path);
    ends.push_back(trace.back().q);
    traces.push_back(
        {{"speed_mps", s.drive.speed_mps}, {"duration_s", path.duration_s()}, {detail_key::kTrace, trace_json(trace)}});
  }
  const car::BasePath ref_path(reparam_segments(), 0.0, q0.beta_rad, base.drive);
  car::LiftDef independent;  // not the analytic engine's integrator
  independent.method = car::LiftMethod::kBulirschStoer;
  const Config ref = car::lift_end(base.car, ref_path, q0, independent);
  std::vector<e2::Pose> end_poses;
  for (const auto& c : ends) end_poses.push_back(c.pose());
  const auto [spread, heading_spread] = pose_spread(end_poses);
  Outcome o;
  o.values["end_spread"] = {0.0, spread};
  o.values["heading_spread"] = {0.0, heading_spread};
  // The two integrators differ by up to 1.2e-8 m over the default 2.55 m of wheel travel, and by
  // more over a longer path (1.1e-7 m over 28 m at R = 3.3 m): the reference's tolerance is per
  // default path length. Every engine's is the distance's.
  double travel_m = 0.0;
  for (const car::Segment& seg : reparam_segments()) travel_m += std::abs(seg.d_alpha_rad) * base.car.R_m;
  o.values["end_error"] = {.expected = 0.0,
                           .measured = std::hypot(ends[0].x_m - ref.x_m, ends[0].y_m - ref.y_m),
                           .tolerance_factor = engine.exact_by_construction() ? std::max(1.0, travel_m / 2.55) : 1.0};
  o.details = {{detail_key::kRuns, traces},
               {"reference_end", {ref.x_m, ref.y_m, ref.phi_rad}},
               {detail_key::kTrace, traces[0][detail_key::kTrace]},
               {detail_key::kReference, reference_json(base, ref_path, q0)}};
  return o;
}

/// The parking cycles and their holonomies.
std::vector<Scenario> parking_cycle_scenarios() {
  return {
      {.name = "car.cycle",
       .vehicle = Vehicle::kCar,
       .summary = "Simple parking cycle (section 5, steps i-iv): the net pose change is the holonomy of the loop, "
                  "to leading order eps_alpha eps_beta [H_alpha, H_beta].",
       .equations = "(5.3), (5.5), (E.1)",
       .params = with(car_params("0.2"), {number("eps_alpha", "0.1", "rad", "drive step in alpha", 0.0, true, 100.0),
                                          number("eps_beta", "0.1", "rad", "steering step in beta", 0.0, true, 1.0)}),
       .metrics = cycle_metrics(),
       .run_car = run_simple_cycle,
       .headline = {.metrics = {"dx", "dy", "dphi"}, .label = "holonomy"}},
      {.name = "car.iterated",
       .vehicle = Vehicle::kCar,
       .summary =
           "Iterated cycle (5.8), ten steps: a sideways shift of the tie rod, -eps^4 [H_alpha, [H_alpha, H_beta]] "
           "= eps^4 R^2/l (sin phi, -cos phi) to leading order, heading unchanged.",
       .equations = "(5.6), (5.8), (5.9), (E.3)",
       .params =
           with(car_params("0.2"), {number("eps", "0.3", "rad", "step size eps (alpha and beta)", 0.0, true, 1.0)}),
       .metrics = cycle_metrics(),
       .run_car = run_iterated_alpha,
       .headline = {.metrics = {"dx", "dy", "dphi"}, .label = "holonomy"}},
      {.name = "car.iterated-beta",
       .vehicle = Vehicle::kCar,
       .summary = "Iterated cycle (5.10), ten steps: the car slides as if alpha changed without the wheel turning, "
                  "-eps^4 [H_beta, [H_alpha, H_beta]] = -eps^4 (H_alpha - d_alpha) to leading order.",
       .equations = "(5.7), (5.10), (E.3)",
       .params =
           with(car_params("0.2"), {number("eps", "0.3", "rad", "step size eps (alpha and beta)", 0.0, true, 1.0)}),
       .metrics = cycle_metrics(),
       .run_car = run_iterated_beta,
       .headline = {.metrics = {"dx", "dy", "dphi"}, .label = "holonomy"}}};
}

/// Steering in place, the lift's reparametrisation invariance and its E(2) covariance.
std::vector<Scenario> lift_property_scenarios() {
  return {
      {.name = "car.steer-in-place",
       .vehicle = Vehicle::kCar,
       .summary = "Turning the steering wheel alone moves no tie rod: H_beta = d/dbeta.",
       .equations = "(4.4), (C.10)",
       .params = with(car_params("0.0"), {number("d_beta", "0.35", "rad", "steering change", -2.8, false, 2.8)}),
       .metrics = {abs_("front_shift", "m", 1e-12, 1e-4, "largest displacement of the front-axle centre"),
                   abs_("dphi", "rad", 1e-12, 1e-3, "heading change"),
                   abs_("beta_reached", "rad", 1e-12, 1e-3, "realized steering angle at the end"), SLIP_ALONG,
                   SLIP_ACROSS, SLIP_RMS, LOAD_REST, LOAD_DRIVE, MOMENTUM, TRACE_PATH, TRACE_SHAPE, STEER_LAG,
                   DRIVE_LAG},
       .run_car = run_steer_in_place,
       .headline = {.metrics = {"front_shift"}, .label = "front-axle shift", .unit = "mm", .scale = 1e3}},
      {.name = "car.reparam",
       .vehicle = Vehicle::kCar,
       .summary = "The same path in (alpha, beta), steering while driving, at its pace and at f times it (every rate "
                  "multiplied by f, every acceleration by f^2): the lift (4.1) is reparametrisation invariant, so both "
                  "runs end in the same pose, that of the lift.",
       .equations = "(4.1), section 4",
       // The path's four short segments (2.55 m of wheel travel, mostly ramps) at 0.25 m/s^2 and
       // 1 rad/s^2 take 15.9 s; at f = 3 (1.5 m/s, 2.25 m/s^2, 0.75 rad/s, 9 rad/s^2) 5.3 s: three
       // times the pace, nine times the accelerations (the fast run's 104 N of drive within the
       // 235 N the front wheel grips with at mu = 1). Three speeds with the accelerations fixed
       // (0.125, 0.5 and 2 m/s) took 21.2, 8.2 and 7.9 s: a time ratio of 2.7.
       .params =
           with(with_defaults(car_params("0.1"),
                              {{"speed", "0.5"}, {"steer_rate", "0.25"}, {"accel", "0.25"}, {"steer_accel", "1.0"}}),
                {number("factor", "3", "1", "pace factor f", 1.0, true, 100.0)}),
       .metrics = {abs_("end_spread", "m", 1e-9, 1e-3, "largest distance between the end positions of the runs"),
                   abs_("heading_spread", "rad", 1e-9, 1e-3, "largest difference between the end headings"),
                   abs_("end_error", "m", 1e-7, 1e-3,
                        "end position of the run at the path's own pace against the reference lift (Bulirsch-Stoer; "
                        "the analytic engine runs dopri5, both at 1e-13 per step; they differ by up to 1.2e-8 m across "
                        "the steering kinks)")},
       .run_car = run_reparam,
       .headline = {.metrics = {"end_spread"}, .label = "end spread", .unit = "mm", .scale = 1e3}},
      // Three headings, 0, 120 and 240 degrees (0, 30 and 60 modulo a right angle): a friction box fixed
      // to the world axes grips differently at each, while headings a right angle apart would all
      // see the same box. Each start drives 3.5 s (with the car's settle and hold 4.2 s).
      {.name = "car.covariance",
       .vehicle = Vehicle::kCar,
       .summary =
           "E(2) covariance (A.6): the same manoeuvre (an arc, then a parking cycle) started from 3 headings "
           "over the full turn, every other one translated, must end in the same pose relative to its start. "
           "On mu = 0.1 the 2 m arc (cruise speed 2 m/s, ramps of 1 m/s^2: it peaks at 1.13 m/s, grip use "
           "v^2/(r g mu) = 0.38) loads the friction in a direction that turns with the start: isotropic friction "
           "acts the same at every heading, a friction pyramid fixed to the world axes does not.",
       .equations = "(A.6), equivariance of the lift",
       .params = with(with_defaults(car_params("0.3"), {{"mu", "0.1"}, {"speed", "2.0"}}),
                      {number("drive", "2", "m", "arc length before the cycle", 0.0, true, 1e3),
                       integer("headings", "3", "1", "start headings over the full turn", 2.0, 64.0),
                       vec2("shift", "3,-2", "m", "translation of every other start", 1e4)}),
       .metrics = {abs_("spread_xy", "m", 1e-9, 1e-3, "largest distance between end positions in the start frames"),
                   abs_("spread_phi", "rad", 1e-9, 1e-3,
                        "largest difference between end headings in the start frames")},
       .run_car = run_covariance,
       .headline = {.metrics = {"spread_xy"}, .label = "end spread", .unit = "mm", .scale = 1e3}}};
}

}  // namespace

std::vector<Scenario> cycle_scenarios() {
  std::vector<Scenario> v = parking_cycle_scenarios();
  for (Scenario& s : lift_property_scenarios()) v.push_back(std::move(s));
  return v;
}

}  // namespace liftcheck
