// The car scenarios of the catalogue (Fecko). Each builds a base path, lets the engine drive it,
// and compares the realized motion with the exact lift of the commanded path.
#include <cmath>
#include <fmt/format.h>
#include <numbers>
#include <map>

#include "scenarios/car_scenarios.hpp"
#include "scenarios/declare.hpp"
#include "scenarios/fit.hpp"
#include "models/holonomy.hpp"
#include "models/lift.hpp"

namespace liftcheck {

namespace {

using namespace declare;
using car::Config;
using car::Vec5;
constexpr double kHalfPi = std::numbers::pi / 2.0;

/// Parameters every car scenario shares: geometry, start pose, driving, engine settings.
std::vector<ParamSpec> car_params(const std::string& beta_default) {
  return {
      number("R", "0.3", "m", "front wheel radius", 0.0, true),
      number("l", "1.0", "m", "tie-rod length (rear-axle centre to front-axle centre)", 0.0, true),
      number("beta", beta_default, "rad", "start steering angle, left positive", -1.4, false, 1.4),
      number("x", "0", "m", "start front-axle centre, world x", -1e3, false, 1e3),
      number("y", "0", "m", "start front-axle centre, world y", -1e3, false, 1e3),
      number("phi", "0", "rad", "start heading of the tie rod", -100.0, false, 100.0),
      number("speed", "0.5", "m/s", "cruise speed of the front wheel", 0.0, true, 50.0),
      number("steer_rate", "0.5", "rad/s", "cruise steering rate", 0.0, true, 50.0),
      number("accel", "1.0", "m/s^2", "peak acceleration of the front wheel", 0.0, true, 100.0),
      number("steer_accel", "4.0", "rad/s^2", "peak angular acceleration of the steering", 0.0, true, 1000.0),
      number("dt", "0.001", "s", "engine time step", 0.0, true, 0.1),
      number("sample_dt", "0.01", "s", "spacing of the recorded trace", 0.0, true, 10.0),
      number("mu", "1.0", "1", "Coulomb friction coefficient, wheel against ground", 0.0, true, 10.0),
      number("gravity", "9.81", "m/s^2", "gravity magnitude (down)", 0.0, true, 100.0),
      choice("wheels", "3", "3: the paper's tricycle; 4: two Ackermann-steered front wheels driven by an electronic differential (the reference is the same tricycle: average wheel angle, virtual steering angle)", {"3", "4"}),
      number("track", "0.8", "m", "distance between the rear wheels (and between the front wheels of a four-wheel car)", 0.0, true, 100.0),
      choice("steering", "ackermann", "four wheels: each front wheel at its Ackermann angle, or both at beta (parallel: they fight and scrub)", {"ackermann", "parallel"}),
      // The masses in a real car's proportions: a passenger car's wheel with its tyre weighs 15 to
      // 25 kg and its steering knuckle with hub and brake about as much, against 1200 to 1600 kg
      // of body. The tricycle keeps a 40 kg chassis and 2 kg wheels (chassis/wheel 20, gentler on
      // a solver than a real car's 60 to 80) and a knuckle as heavy as a wheel (ratio 1); the
      // 0.05 kg knuckle it had before (ratios 40 and 800 along chassis-knuckle-wheel) is the
      // extreme of the knuckle_mass sweep. The analytic lift does not depend on any mass.
      number("chassis_mass", "40", "kg", "chassis mass (a box from the rear to the front axle, no collision)", 0.0, true, 1e5),
      number("wheel_mass", "2", "kg", "mass of each wheel", 0.0, true, 1e4),
      number("knuckle_mass", "2", "kg", "mass of each steering knuckle (the body between the chassis and a steered wheel)", 0.0, true, 1e4),
  };
}

CarSetup setup_from(const Params& p) {
  CarSetup s;
  s.car = {p.num("R"), p.num("l")};
  s.drive = {p.num("R"), p.num("speed"), p.num("steer_rate"), p.num("accel"), p.num("steer_accel")};
  s.dt_s = p.num("dt");
  s.sample_dt_s = p.num("sample_dt");
  s.mu = p.num("mu");
  s.gravity_mps2 = p.num("gravity");
  s.wheels = p.str("wheels") == "4" ? 4 : 3;
  s.track_m = p.num("track");
  s.parallel_steering = p.str("steering") == "parallel";
  s.chassis_mass_kg = p.num("chassis_mass");
  s.wheel_mass_kg = p.num("wheel_mass");
  s.knuckle_mass_kg = p.num("knuckle_mass");
  if (s.parallel_steering && s.wheels != 4)
    throw InputError("steering=parallel needs wheels=4: the tricycle has one steered wheel");
  return s;
}

Config start_from(const Params& p) { return {0.0, p.num("beta"), p.num("x"), p.num("y"), p.num("phi")}; }

/// Drives `path` and checks the trace: non-empty and finite, or the engine failed.
std::vector<car::TimedConfig> drive_checked(CarEngine& engine, const CarSetup& setup, const Config& q0,
                                            const car::BasePath& path) {
  check_run_budget(path.duration_s(), setup.dt_s, setup.sample_dt_s);
  engine.reset(setup, q0);
  auto trace = engine.drive(path);
  if (trace.empty()) throw EngineError("engine returned an empty trace");
  for (const auto& s : trace)
    if (!s.q.vec().allFinite() || !std::isfinite(s.t_s))
      throw EngineError(fmt::format("engine state is not finite at t = {:.4f} s", s.t_s));
  return trace;
}

/// A simulator outside liftcheck shows only its trace: its whole path is compared with the exact
/// lift of the commanded path at every sample (front-axle position), and its realized shape with
/// the commanded one. An engine liftcheck runs is judged by the same comparisons of its own trace
/// (up to the path's end, as a trace written back covers it), so that its verdict does not depend
/// on the road its results took. A model that reports the commanded shape and its exact lift (the
/// analytic engine) compares them with themselves: informational.
void add_trace_check(Outcome& o, const CarEngine& engine, const CarSetup& setup, const car::BasePath& path, const Config& q0,
                     const std::vector<car::TimedConfig>& trace) {
  double pos = 0.0, shape = 0.0;
  car::LiftDef def;
  def.sample_dt_s = setup.sample_dt_s;
  const auto exact = car::lift(setup.car, path, q0, def);
  for (const auto& s : trace) {
    if (s.t_s > path.duration_s() + 1e-9) break;  // the hold after the path's end is no part of a trace
    // The exact lift at the same time: on the path's sample grid (which the trace was checked to
    // cover) it is a sample of the lift; a row in between is compared with the chord between the
    // neighbouring samples (off the arc by (v h)^2 / 8r, a micrometre at 1 m/s, h = 10 ms, r = 1 m).
    auto hi = std::lower_bound(exact.begin(), exact.end(), s.t_s - 1e-9,
                               [](const car::TimedConfig& a, double t) { return a.t_s < t; });
    if (hi == exact.end()) hi = std::prev(exact.end());
    double ex = hi->q.x_m, ey = hi->q.y_m, ephi = hi->q.phi_rad;
    if (hi != exact.begin() && std::abs(hi->t_s - s.t_s) > 1e-9) {
      const auto lo = std::prev(hi);
      const double w = std::clamp((s.t_s - lo->t_s) / (hi->t_s - lo->t_s), 0.0, 1.0);
      ex = lo->q.x_m + w * (hi->q.x_m - lo->q.x_m);
      ey = lo->q.y_m + w * (hi->q.y_m - lo->q.y_m);
      ephi = lo->q.phi_rad + w * (hi->q.phi_rad - lo->q.phi_rad);
    }
    pos = std::max(pos, std::hypot(s.q.x_m - ex, s.q.y_m - ey));
    // The heading too: a trace can keep the front axle on the lift and turn the car wrongly.
    shape = std::max(shape, std::abs(e2::wrap_angle(s.q.phi_rad - ephi)));
    const car::BaseSample cmd = path.at(std::min(s.t_s, path.duration_s()));
    shape = std::max({shape, std::abs(s.q.alpha_rad - cmd.alpha_rad), std::abs(s.q.beta_rad - cmd.beta_rad)});
  }
  o.values["trace_path_error"] = {.expected = 0.0, .measured = pos, .informational = engine.exact_by_construction()};
  o.values["trace_shape_error"] = {.expected = 0.0, .measured = shape, .informational = engine.exact_by_construction()};
}

/// At most ~400 rows [t, alpha, beta, x, y, phi] for plots and snapshots.
nlohmann::json trace_json(const std::vector<car::TimedConfig>& trace) {
  nlohmann::json rows = nlohmann::json::array();
  const std::size_t stride = std::max<std::size_t>(1, (trace.size() + 399) / 400);  // at most about 400 rows
  for (std::size_t i = 0; i < trace.size(); i += stride) {
    const auto& s = trace[i];
    rows.push_back({s.t_s, s.q.alpha_rad, s.q.beta_rad, s.q.x_m, s.q.y_m, s.q.phi_rad});
  }
  if ((trace.size() - 1) % stride != 0) {
    const auto& s = trace.back();
    rows.push_back({s.t_s, s.q.alpha_rad, s.q.beta_rad, s.q.x_m, s.q.y_m, s.q.phi_rad});
  }
  return rows;
}

/// The exact lift (4.1) of the commanded path from q0, sampled like the engines' traces: what the
/// reports draw as the analytic reference.
nlohmann::json reference_json(const CarSetup& setup, const car::BasePath& path, const Config& q0) {
  car::LiftDef def;
  def.sample_dt_s = setup.sample_dt_s;
  return trace_json(car::lift(setup.car, path, q0, def));
}

/// Actuation error against contact error: the lift of the (alpha, beta) path the engine realized
/// tells how far the commanded path was missed (actuation) and how far the car strayed from the
/// lift of what its wheels did (contact: slip, compliance, friction model).
nlohmann::json error_split(const car::CarDef& c, const std::vector<car::TimedConfig>& trace, const Config& commanded_end) {
  const Config realized = car::lift_of_samples(c, trace);
  const Config& eng = trace.back().q;
  return {{detail_key::kCommandedLiftEnd, {commanded_end.x_m, commanded_end.y_m, commanded_end.phi_rad}},
          {"realized_lift_end", {realized.x_m, realized.y_m, realized.phi_rad}},
          {"engine_end", {eng.x_m, eng.y_m, eng.phi_rad}},
          {detail_key::kActuationError, std::hypot(realized.x_m - commanded_end.x_m, realized.y_m - commanded_end.y_m)},
          {detail_key::kContactError, std::hypot(eng.x_m - realized.x_m, eng.y_m - realized.y_m)}};
}

/// Contact-point slip measured by the engine every step (engines with wheels): the worst wheel's
/// largest speed along and across its rolling direction and its RMS slip speed. The analytic lift
/// rolls without slipping by construction and reports none.
void add_slip(Outcome& o, const CarEngine& engine) {
  const std::vector<WheelSlip> slip = engine.slip();
  if (slip.empty()) return;
  double along = 0.0, across = 0.0, rms = 0.0;
  bool along_measured = true;
  nlohmann::json wheels = nlohmann::json::array();
  for (const WheelSlip& w : slip) {
    along_measured = along_measured && w.along_measured;
    along = std::max(along, w.along_max_mps);
    across = std::max(across, w.across_max_mps);
    rms = std::max(rms, w.rms_mps);
    wheels.push_back({{"wheel", w.wheel}, {"along_max_mps", w.along_max_mps}, {"across_max_mps", w.across_max_mps}, {"rms_mps", w.rms_mps}});
  }
  // A wheel without a spin state of its own turns as the chassis moves: its along-slip is zero by
  // construction, shown but not counted.
  o.values["slip_along_max"] = {.expected = 0.0, .measured = along, .informational = !along_measured};
  o.values["slip_across_max"] = {0.0, across};
  o.values["slip_rms"] = {0.0, rms};
  o.details["wheel_slip"] = wheels;
}

/// The connection (3.3) at every sample: the pose the engine reports at sample k against the lift
/// of the (alpha, beta) its own wheels realized over samples 0..k (lift_of_samples, each interval
/// composed of exact flows; exact where only one of alpha and beta changes between two samples:
/// on car.circle the front-axle centre's arc is R times the wheel angle turned). A pose read late,
/// before the step that turned the wheels, or interpolated between steps, is off by its lag's
/// travel at every moving sample. The comparison must start where pose and wheels are known to
/// agree (at rest, t = 0): a lag is invisible to any comparison over a window that starts at a
/// pose which lags too.
///
/// What the comparison may accumulate: (3.3) ties the front-axle centre's velocity to R dalpha/dt
/// along the wheel's heading, so an engine's pose leaves the lift (4.1) of its own realized shape
/// only at the speed its contacts slip, |dp/dt - R alphadot e(theta)| = |v_slip|, and after time t
/// it is at most  int_0^t |v_slip| dt <= u t  from it, u = sqrt(2) x 1e-4 m/s the contact-slip
/// speed the slip metrics let every engine have (1e-4 m/s along and across). The metric is the largest excess over that
/// bound, max_k (|p_k - lift_k| - u t_k)+, in m; its tolerance is a fifth of one engine step's
/// travel v dt at the command's fastest front-wheel speed v (1e-4 m at 0.5 m/s and 1 ms, scaled by
/// v dt / 0.5 mm), so a pose one step late (v dt at the fastest samples) fails it wherever
/// u t_k < 0.8 v dt (the first 2.8 s on car.circle, 0.8 s of car.cycle's 1.9 s). The bound covers
/// the slip's own displacement, not the heading it turns (rear lateral slip turns the car at up to
/// u / l rad/s, a position error growing as v u t^2 / (2 l)): an engine slipping within the slip
/// tolerance can still fail it, which errs towards flagging.
/// A model that reports the commanded shape as its realized one compares its lift with itself:
/// informational.
constexpr double kSlipBudget_mps = 1.41421356e-4;
void add_realized_lift(Outcome& o, const CarEngine& engine, const CarSetup& setup, const car::BasePath& path,
                       const std::vector<car::TimedConfig>& trace) {
  const car::CarDef& c = setup.car;
  Config q = trace.front().q;
  const double t0 = trace.front().t_s;
  double worst = 0.0;
  for (std::size_t i = 1; i < trace.size(); ++i) {
    const Config& b = trace[i].q;
    q = car::flow_beta(q, 0.5 * (b.beta_rad - q.beta_rad));
    q = car::flow_alpha(c, q, b.alpha_rad - q.alpha_rad);
    q = car::flow_beta(q, b.beta_rad - q.beta_rad);
    const double d = std::hypot(b.x_m - q.x_m, b.y_m - q.y_m);
    worst = std::max(worst, d - kSlipBudget_mps * (trace[i].t_s - t0));
  }
  // One step's travel at the commanded path's fastest front-wheel speed, R |dalpha/dt| (the
  // command's, never the engine's own: a tolerance is not widened by the error it judges).
  double v_peak_mps = 0.0;
  for (const auto& smp : trace)
    v_peak_mps = std::max(v_peak_mps, setup.car.R_m * std::abs(path.at(std::min(smp.t_s, path.duration_s())).alpha_rate_radps));
  const double step_travel_factor = v_peak_mps * setup.dt_s / (0.5 * 1e-3);
  o.values["realized_lift_error"] = {.expected = 0.0, .measured = worst, .tolerance_factor = step_travel_factor, .informational = engine.exact_by_construction()};
}

/// The car's centre of mass in the chassis frame (x forward from the front-axle centre, y left):
/// the chassis box l/2 behind the front axle, the front wheels with their knuckles, the rear wheels.
Eigen::Vector2d com_in_chassis(const CarSetup& s) {
  const double l = s.car.l_m, mc = s.chassis_mass_kg, mw = s.wheel_mass_kg, mk = s.knuckle_mass_kg;
  const int n_front = s.wheels == 4 ? 2 : 1;
  const double M = mc + (n_front + 2) * mw + n_front * mk;
  // The front wheels sit at y = 0 (one) or +-track/2 (two), the rear ones at +-track/2: no y offset.
  return {(mc * -0.5 * l + 2.0 * mw * -l) / M, 0.0};
}

/// Coulomb's law for the whole car on flat ground: the ground pushes it horizontally by at most mu
/// times its weight, so its centre of mass never accelerates horizontally by more than mu g. The
/// centre of mass from each sample's pose (the chassis frame's point com_in_chassis), its
/// acceleration by second differences of the samples (the mean over two sample intervals, which
/// also averages the normal load's fluctuations); the excess of the largest over mu g, as a
/// fraction of mu g (0 within the bound). A car that follows a lift needing more, as a kinematic
/// one or one that keeps its grip past the limit does, is not doing physics.
double com_accel_excess(const CarSetup& s, const std::vector<car::TimedConfig>& trace) {
  const Eigen::Vector2d cB = com_in_chassis(s);
  const auto com = [&](const Config& q) {
    const double c = std::cos(q.phi_rad), sn = std::sin(q.phi_rad);
    return Eigen::Vector2d(q.x_m + c * cB.x() - sn * cB.y(), q.y_m + sn * cB.x() + c * cB.y());
  };
  double worst = 0.0;
  for (std::size_t i = 1; i + 1 < trace.size(); ++i) {
    const double h0 = trace[i].t_s - trace[i - 1].t_s, h1 = trace[i + 1].t_s - trace[i].t_s;
    if (!(h0 > 0.0 && h1 > 0.0)) continue;
    const Eigen::Vector2d a = 2.0 * ((com(trace[i + 1].q) - com(trace[i].q)) / h1 - (com(trace[i].q) - com(trace[i - 1].q)) / h0) / (h0 + h1);
    worst = std::max(worst, a.norm());
  }
  return std::max(0.0, worst / (s.mu * s.gravity_mps2) - 1.0);
}

// ---- car.circle ----------------------------------------------------------------------------

Outcome run_circle(const Params& p, CarEngine& engine) {
  const CarSetup setup = setup_from(p);
  const Config q0 = start_from(p);
  if (std::abs(q0.beta_rad) < 1e-3)
    throw InputError("car.circle needs |beta| >= 0.001 rad: beta = 0 drives a straight line");
  const double d_alpha = p.num("drive") / setup.car.R_m;
  const car::BasePath path({{d_alpha, 0.0}}, 0.0, q0.beta_rad, setup.drive);
  if (path.duration_s() / setup.sample_dt_s < 8.0)
    throw InputError(fmt::format("car.circle needs at least 8 samples of the drive to fit its circle: sample_dt = {:g} s is too coarse for {:.3g} s",
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
  o.values["final_heading_error"] = {.expected = 0.0, .measured = std::abs(e2::wrap_angle(end.phi_rad - end_exact.phi_rad)),
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
  o.values["com_accel_excess"] = {.expected = 0.0, .measured = com_accel_excess(setup, trace), .informational = engine.exact_by_construction()};
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
    throw InputError(fmt::format("car.beyond-grip needs v^2/(r g) > 1.2 mu to be past the grip limit: it is {:.3g} mu", need));
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
  return b;
}

/// car.slip's judgement of the circle's full outcome: the no-slip comparison, which must fail.
Outcome judge_slip(const Params&, Outcome o) {
  for (const char* keep_out : {"center_x", "center_y", "final_heading_error", "heading_residual", "realized_lift_error", "com_accel_excess"}) o.values.erase(keep_out);
  return o;
}

/// Largest pairwise distance and heading difference among poses.
std::pair<double, double> pose_spread(const std::vector<e2::Pose>& poses) {
  double xy = 0.0, phi = 0.0;
  for (const auto& a : poses)
    for (const auto& b : poses) {
      xy = std::max(xy, std::hypot(a.x_m - b.x_m, a.y_m - b.y_m));
      phi = std::max(phi, std::abs(e2::wrap_angle(a.phi_rad - b.phi_rad)));
    }
  return {xy, phi};
}

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
    thin.push_back(tr.back());
    rows.push_back({{"theta_rad", theta}, {"start", {start.x_m, start.y_m, start.phi_rad}},
                    {"end_in_start_frame", {local.x_m, local.y_m, local.phi_rad}}, {detail_key::kTrace, thin}});
  }
  const auto [spread_xy, spread_phi] = pose_spread(seen);
  Outcome o;
  o.values["spread_xy"] = {0.0, spread_xy};
  o.values["spread_phi"] = {0.0, spread_phi};
  // In the default regime the wheels slide a little, identically at every heading: the distance
  // from the no-slip lift is information here, the no-slip check is car.circle's.
  // "drawing": the report draws every start and its path in one picture.
  o.details = {{detail_key::kRuns, rows}, {detail_key::kDrawing, detail_key::kDrawingStarts}, {"exact_end_in_start_frame", {exact.x_m, exact.y_m, exact.phi_rad}},
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
Outcome run_cycle(const Params& p, CarEngine& engine, const std::vector<car::Step>& steps,
                  const Vec5& predicted, double lo_factor) {
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
  o.values["base_closure"] = {.expected = 0.0, .measured = std::hypot(d[car::kAlpha], d[car::kBeta]), .informational = engine.exact_by_construction()};
  o.values["lo_dx"] = {.expected = predicted[car::kX], .measured = d[car::kX], .scale = lo_size, .tolerance_factor = lo_factor};
  o.values["lo_dy"] = {.expected = predicted[car::kY], .measured = d[car::kY], .scale = lo_size, .tolerance_factor = lo_factor};
  o.values["lo_dphi"] = {.expected = predicted[car::kPhi], .measured = d[car::kPhi], .scale = lo_size / l, .tolerance_factor = lo_factor};
  add_realized_lift(o, engine, setup, path, trace);
  o.details = {{detail_key::kTrace, trace_json(trace)}, {detail_key::kReference, reference_json(setup, path, q0)},
               {detail_key::kSteps, steps.size()}, {detail_key::kHolonomySize, size},
               {detail_key::kMeasuredSize, rod_shift(setup.car, trace.front().q, trace.back().q)},
               {detail_key::kHolonomyError, rod_shift(setup.car, end_exact, Config::from(trace.back().q.vec() - trace.front().q.vec() + q0.vec()))},
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
  o.values["beta_reached"] = {.expected = q0.beta_rad + d_beta, .measured = end.beta_rad, .informational = engine.exact_by_construction()};
  o.details = {{detail_key::kTrace, trace_json(trace)}, {detail_key::kReference, reference_json(setup, path, q0)},
               {detail_key::kErrors, error_split(setup.car, trace, car::flow_beta(q0, d_beta))}};
  add_slip(o, engine);
  return o;
}

// ---- car.reparam ---------------------------------------------------------------------------

/// A path with segments that steer while driving (forwards and backwards): no closed form,
/// so the reference is the lift (4.1) integrated at tolerance 1e-13.
std::vector<car::Segment> reparam_segments() {
  return {{2.0, 0.3}, {3.0, -0.5}, {-2.0, 0.2}, {1.5, 0.0}};
}

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
    traces.push_back({{"speed_mps", s.drive.speed_mps}, {"duration_s", path.duration_s()}, {detail_key::kTrace, trace_json(trace)}});
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
  o.values["end_error"] = {.expected = 0.0, .measured = std::hypot(ends[0].x_m - ref.x_m, ends[0].y_m - ref.y_m),
                           .tolerance_factor = engine.exact_by_construction() ? std::max(1.0, travel_m / 2.55) : 1.0};
  o.details = {{detail_key::kRuns, traces}, {"reference_end", {ref.x_m, ref.y_m, ref.phi_rad}},
               {detail_key::kTrace, traces[0][detail_key::kTrace]}, {detail_key::kReference, reference_json(base, ref_path, q0)}};
  return o;
}

// ---- car.slope -----------------------------------------------------------------------------

/// Gravity tilted by `slope` about the horizontal axis at angle `slope_dir` in the ground plane
/// (the ground stays z = 0): Rodrigues' rotation of (0, 0, -1) about a = (cos d, sin d, 0),
/// g_dir = (-sin d sin s, cos d sin s, -cos s). Its horizontal part points downhill.
Eigen::Vector3d tilted_gravity_dir(double slope_rad, double slope_dir_rad) {
  return {-std::sin(slope_dir_rad) * std::sin(slope_rad), std::cos(slope_dir_rad) * std::sin(slope_rad), -std::cos(slope_rad)};
}

/// The trace's sample nearest to time t.
const car::TimedConfig& sample_at(const std::vector<car::TimedConfig>& trace, double t_s) {
  auto it = std::lower_bound(trace.begin(), trace.end(), t_s - 1e-9, [](const car::TimedConfig& a, double t) { return a.t_s < t; });
  if (it == trace.end()) return trace.back();
  if (it != trace.begin() && std::abs(std::prev(it)->t_s - t_s) < std::abs(it->t_s - t_s)) return *std::prev(it);
  return *it;
}

Outcome run_slope(const Params& p, CarEngine& engine) {
  CarSetup setup = setup_from(p);
  const Config q0 = start_from(p);
  const double slope = p.num("slope"), slope_dir = p.num("slope_dir"), park = p.num("park"), laps = p.num("laps");
  if (!(std::tan(slope) < setup.mu))
    throw InputError(fmt::format("car.slope needs tan(slope) < mu for the car to hold: tan({:g}) = {:.3g} >= mu = {:g}", slope, std::tan(slope), setup.mu));
  if (std::abs(q0.beta_rad) < 1e-3) throw InputError("car.slope needs |beta| >= 0.001 rad: beta = 0 drives a straight line");
  setup.gravity_dir_W = tilted_gravity_dir(slope, slope_dir);
  const Eigen::Vector2d downhill(-std::sin(slope_dir), std::cos(slope_dir));
  // Phase 1: parked for `park` seconds, wheels held by their servos (alpha and beta fixed); phase
  // 2: whole laps of the fixed-steering circle (appendix D, radius l/sin(beta0)). The no-slip
  // connection (3.3) does not involve gravity: the exact lift stands still, then closes each lap.
  const car::Circle fe = car::front_circle(setup.car, q0), re = car::rear_circle(setup.car, q0);
  const double d_alpha = laps * 2.0 * std::numbers::pi * fe.radius_m / setup.car.R_m;
  const car::BasePath path({{0.0, 0.0, park}, {d_alpha, 0.0}}, 0.0, q0.beta_rad, setup.drive);
  const auto trace = drive_checked(engine, setup, q0, path);
  Outcome traced;
  add_trace_check(traced, engine, setup, path, q0, trace);

  // Creep over the last two thirds of the park (the first third lets the settle's transient die
  // away), from the engine's own body state: the farthest either axle centre got from where it
  // stood at the start of the window, at any sample, over the window's length. A car that creeps
  // and comes back, or pivots about one axle, is caught as well as a steady slide.
  const car::TimedConfig &c0 = sample_at(trace, park / 3.0), &c1 = sample_at(trace, park);
  double creep_m = 0.0;
  const Eigen::Vector2d front0(c0.q.x_m, c0.q.y_m), rear0 = car::rear_axle_W(setup.car, c0.q);
  for (const auto& smp : trace)
    if (smp.t_s >= c0.t_s && smp.t_s <= c1.t_s)
      creep_m = std::max({creep_m, (Eigen::Vector2d(smp.q.x_m, smp.q.y_m) - front0).norm(), (car::rear_axle_W(setup.car, smp.q) - rear0).norm()});
  const double creep_mps = c1.t_s > c0.t_s ? creep_m / (c1.t_s - c0.t_s) : 0.0;
  // Circle: fitted to the drive after the park, against the exact radii; drift: the downhill
  // part of the front-axle centre's displacement from the start of the laps to their end, less
  // the exact lift's (zero over whole laps), per lap.
  std::vector<Eigen::Vector2d> front, rear;
  for (const auto& s : trace)
    if (s.t_s >= park - 1e-9) {
      front.emplace_back(s.q.x_m, s.q.y_m);
      rear.push_back(car::rear_axle_W(setup.car, s.q));
    }
  if (front.size() < 8)
    throw InputError(fmt::format("car.slope needs at least 8 samples of the laps to fit their circle: sample_dt = {:g} s is too coarse", setup.sample_dt_s));
  const CircleFit ff = fit_circle(front), rf = fit_circle(rear);
  const Config& end = trace.back().q;
  const Config end_exact = car::flow_alpha(setup.car, q0, d_alpha);
  const Eigen::Vector2d lap_shift(end.x_m - c1.q.x_m, end.y_m - c1.q.y_m), exact_shift(end_exact.x_m - q0.x_m, end_exact.y_m - q0.y_m);

  Outcome o = traced;
  o.values["creep_speed"] = {0.0, creep_mps};
  o.values["front_radius"] = {fe.radius_m, ff.radius_m};
  o.values["rear_radius"] = {re.radius_m, rf.radius_m};
  o.values["drift_per_lap"] = {0.0, (lap_shift - exact_shift).dot(downhill) / laps};
  o.values["final_offset"] = {0.0, std::hypot(end.x_m - end_exact.x_m, end.y_m - end_exact.y_m)};
  const Eigen::Vector3d g = setup.gravity_W();
  o.details = {{detail_key::kTrace, trace_json(trace)},
               {detail_key::kReference, reference_json(setup, path, q0)},
               {"gravity_W_mps2", {g.x(), g.y(), g.z()}},
               {"downhill_W", {downhill.x(), downhill.y()}},
               {"creep_window_s", {c0.t_s, c1.t_s}},
               {"creep_um_per_s", creep_mps * 1e6},
               {"lap_shift_m", {lap_shift.x(), lap_shift.y()}},
               {"front_fit_rms_m", ff.rms_residual_m},
               {detail_key::kGripUse, (setup.drive.speed_mps * setup.drive.speed_mps / fe.radius_m + setup.gravity_mps2 * std::sin(slope)) /
                                (setup.gravity_mps2 * std::cos(slope)) / setup.mu},
               {detail_key::kErrors, error_split(setup.car, trace, end_exact)}};
  add_slip(o, engine);
  return o;
}

// ---- car.coulomb ---------------------------------------------------------------------------

/// Least-squares s(t) = s0 + v0 t + a t^2 / 2 over the samples: the fitted a, m/s^2.
double fit_accel(const std::vector<double>& t, const std::vector<double>& s) {
  Eigen::MatrixXd A(t.size(), 3);
  Eigen::VectorXd b(t.size());
  for (std::size_t i = 0; i < t.size(); ++i) {
    A.row(i) << 1.0, t[i], 0.5 * t[i] * t[i];
    b[i] = s[i];
  }
  return A.colPivHouseholderQr().solve(b)[2];
}

/// Coulomb's law on a slope steeper than the friction angle (tan(slope) > mu): the car, its front
/// wheel held by its servos (zero commanded rates; the rear wheels roll freely about their axles)
/// and its axles along the fall line, slides downhill like a block (the fall line lies along
/// every wheel's axle, where its friction acts whether it rolls or not), s(t) = s0 + v0 t + g (sin(slope) - mu cos(slope)) t^2 / 2 (the friction of
/// every sliding contact is mu times its normal load, which sum to the weight's normal part). The
/// acceleration measures the engine's clock (a step of the wrong length scales it by the square of
/// the ratio), its gravity (tilted) and its effective friction coefficient at once. It slides
/// from the start of the settle (the exact acceleration is constant from the first contact), so
/// the fit takes s0 and v0 free, over the samples from `fit_from` on.
Outcome run_coulomb(const Params& p, CarEngine& engine) {
  CarSetup setup = setup_from(p);
  const Config q0 = start_from(p);
  const double slope = p.num("slope"), slope_dir = p.num("slope_dir"), T = p.num("slide"), fit_from = p.num("fit_from");
  if (!(std::tan(slope) > setup.mu * 1.05))
    throw InputError(fmt::format("car.coulomb needs tan(slope) > 1.05 mu for the car to slide: tan({:g}) = {:.3g}, mu = {:g}", slope, std::tan(slope), setup.mu));
  if (!(fit_from + 0.2 < T)) throw InputError(fmt::format("car.coulomb needs fit_from + 0.2 s < slide: {:g} and {:g} s", fit_from, T));
  setup.gravity_dir_W = tilted_gravity_dir(slope, slope_dir);
  const Eigen::Vector2d downhill(-std::sin(slope_dir), std::cos(slope_dir));
  const car::BasePath path({{0.0, 0.0, T}}, 0.0, q0.beta_rad, setup.drive);
  const auto trace = drive_checked(engine, setup, q0, path);
  const Eigen::Vector2d cB = com_in_chassis(setup);
  std::vector<double> ts, s_down, s_across;
  for (const auto& smp : trace) {
    if (smp.t_s < fit_from - 1e-9 || smp.t_s > T + 1e-9) continue;
    const double c = std::cos(smp.q.phi_rad), sn = std::sin(smp.q.phi_rad);
    const Eigen::Vector2d com(smp.q.x_m + c * cB.x() - sn * cB.y(), smp.q.y_m + sn * cB.x() + c * cB.y());
    ts.push_back(smp.t_s);
    s_down.push_back(com.dot(downhill));
    s_across.push_back(com.x() * downhill.y() - com.y() * downhill.x());
  }
  if (ts.size() < 8)
    throw InputError(fmt::format("car.coulomb needs at least 8 samples to fit the slide: sample_dt = {:g} s is too coarse", setup.sample_dt_s));
  const double g = setup.gravity_mps2, a_exact = g * (std::sin(slope) - setup.mu * std::cos(slope));
  const double a = fit_accel(ts, s_down), a_across = fit_accel(ts, s_across);
  Outcome o;
  o.values["slide_accel"] = {a_exact, a};
  // Straight down: sliding friction opposes the slide, so nothing pushes the car across it.
  o.values["slide_accel_across"] = {.expected = 0.0, .measured = a_across, .scale = a_exact};
  o.values["heading_change"] = {0.0, std::abs(e2::wrap_angle(trace.back().q.phi_rad - trace.front().q.phi_rad))};
  o.details = {{detail_key::kTrace, trace_json(trace)},
               {detail_key::kReference, reference_json(setup, path, q0)},
               {"gravity_W_mps2", {setup.gravity_W().x(), setup.gravity_W().y(), setup.gravity_W().z()}},
               {"effective_mu", (g * std::sin(slope) - a) / (g * std::cos(slope))},
               {"clock_ratio_if_mu_exact", std::sqrt(a / a_exact)}};
  add_slip(o, engine);
  for (const char* k : {"slip_along_max", "slip_across_max", "slip_rms"})
    if (o.values.count(k)) o.values[k].informational = true;  // the car slides: that is the point here
  return o;
}

MetricDef reference_only(MetricDef m) {
  m.reference_only = true;
  return m;
}


// Contact-point slip, measured by the engine every step (not produced by the analytic lift). A
// gripping wheel's contact point is at rest: 0.1 mm/s is 2e-4 of the default speed.
const MetricDef SLIP_ALONG = abs_("slip_along_max", "m/s", 0.0, 1e-4, "largest contact-point speed along a wheel's rolling direction (worst wheel)");
const MetricDef SLIP_ACROSS = abs_("slip_across_max", "m/s", 0.0, 1e-4, "largest contact-point speed along a wheel's axle (worst wheel)");
const MetricDef SLIP_RMS = abs_("slip_rms", "m/s", 0.0, 1e-4, "RMS contact-point speed over the drive (worst wheel)");
// Every sample of the trace (an engine's, or an outside simulator's from liftcheck score) against
// the exact lift and the command.
const MetricDef TRACE_PATH = abs_("trace_path_error", "m", 0.0, 1e-3, "the trace up to the path's end: largest distance of the front-axle centre from the exact lift at any sample");
const MetricDef TRACE_SHAPE = abs_("trace_shape_error", "rad", 0.0, 1e-3, "the trace up to the path's end: largest difference of its (alpha, beta) from the commanded path, or of its heading from the exact lift's, at any sample");

// The connection (3.3) at every sample: the pose against the lift of the engine's own realized
// (alpha, beta), less what the slip tolerance lets accumulate (add_realized_lift). 0.1 mm is a
// fifth of one engine step's travel at the default 0.5 m/s and 1 ms; the tolerance scales with
// v dt (a pose one step late is off by one step's travel).
const MetricDef REALIZED_LIFT = abs_("realized_lift_error", "m", 1e-9, 1e-4, "largest excess, at any sample t, of the front-axle centre's distance from the lift of the wheel and steering angles the engine realized up to t over what the contact-slip tolerance lets accumulate (sqrt(2) x 1e-4 m/s x t): a pose reported late or early; tolerance at 0.5 m/s and dt = 1 ms, x v dt / 0.5 mm with v the command's fastest front-wheel speed");
// Coulomb: the ground pushes the car by at most mu times its weight. 5% for the normal load's
// fluctuation over two sample intervals and the second differences.
const MetricDef COM_ACCEL = abs_("com_accel_excess", "1", 1e-9, 0.05, "largest horizontal acceleration of the car's centre of mass beyond mu g, as a fraction of mu g (0: within Coulomb's bound)");

std::vector<MetricDef> cycle_metrics() {
  const std::string size = ", relative to the size of the holonomy (rms shift of the rod's ends)";
  // The analytic engine integrates (4.1) at 1e-13 per step while the exact holonomy composes
  // closed-form flows: over a cycle's profile kinks the integration leaves up to ~1e-11 m (measured
  // at accel = 100 m/s^2 and at speed = 1 mm/s), which is all of a 1e-9 m holonomy's relative
  // budget at eps = 0.05. Hence an absolute floor for the analytic engine.
  const auto floored = [](MetricDef m) {
    m.floor = {{TolRole::kReference, 5e-11}};
    return m;
  };
  return {SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, TRACE_PATH, TRACE_SHAPE, REALIZED_LIFT,
      floored(rel("dx", "m", 1e-9, 0.02, "net x change against the exact holonomy" + size)),
      floored(rel("dy", "m", 1e-9, 0.02, "net y change against the exact holonomy" + size)),
      floored(rel("dphi", "rad", 1e-9, 0.02, "net heading change against the exact holonomy" + size + " / l")),
      abs_("base_closure", "rad", 1e-12, 1e-3, "the realized (alpha, beta) path closes"),
      // Leading-order predictions are off by O(eps) relative: tolerance 1.0 x eps for every engine.
      reference_only(rel("lo_dx", "m", 1.0, 1.0, "net x change against the bracket prediction (tolerance x eps): the leading order's check, counted for the reference only")),
      reference_only(rel("lo_dy", "m", 1.0, 1.0, "net y change against the bracket prediction (tolerance x eps): the leading order's check, counted for the reference only")),
      reference_only(rel("lo_dphi", "rad", 1.0, 1.0, "net heading change against the bracket prediction (tolerance x eps): the leading order's check, counted for the reference only")),
  };
}

/// A car scenario of the catalogue (its headline and flags are set after).
Scenario car_scenario(std::string name, std::string summary, std::string equations, std::vector<ParamSpec> params,
                      std::vector<MetricDef> metrics, std::function<Outcome(const Params&, CarEngine&)> run) {
  return {.name = std::move(name), .vehicle = Vehicle::kCar, .summary = std::move(summary), .equations = std::move(equations),
          .params = std::move(params), .metrics = std::move(metrics), .run_car = std::move(run)};
}

}  // namespace

std::vector<Scenario> car_scenarios() {
  std::vector<Scenario> v;
  v.push_back(car_scenario("car.circle",
               "Fixed steering: the front-axle centre draws a circle of radius l/sin(beta0), the rear-axle "
               "centre one of radius l/tan(beta0), about the same centre.",
               "(4.1), (D.1), appendix D",
               // 10 m of arc (3 rad of the 3.38 m circle: what the radius fit needs, and what keeps the
               // start's transient from weighing on it) at 2 m/s after ramps of 2 m/s^2: 5 s of cruise,
               // 6.6 s with the ramps; the grip use v^2/(r g mu) is 0.12.
               with(with_defaults(car_params("0.3"), {{"speed", "2.0"}, {"accel", "2.0"}}),
                    {number("drive", "10", "m", "front-wheel path length (enough arc to fit a circle)", 1.0, false, 1e4)}),
               {rel("front_radius", "m", 1e-9, 1e-4, "fitted radius of the front-axle centre's path"),
                rel("rear_radius", "m", 1e-9, 1e-4, "fitted radius of the rear-axle centre's path"),
                abs_("center_x", "m", 1e-9, 1e-3, "fitted circle centre, world x"),
                abs_("center_y", "m", 1e-9, 1e-3, "fitted circle centre, world y"),
                abs_("final_offset", "m", 1e-9, 1e-3, "front-axle centre at the end against the exact arc"),
                abs_("final_heading_error", "rad", 1e-9, 1e-3, "heading at the end against the exact arc"),
                abs_("heading_residual", "rad", 1e-9, 1e-5, "largest difference between the heading and the one the exact circle gives at the sampled position (tolerance at dt = 1 ms, x dt / 1 ms)"),
                REALIZED_LIFT, COM_ACCEL, SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, TRACE_PATH, TRACE_SHAPE},
               run_circle));
  v.back().headline = {.metrics = {"front_radius", "rear_radius"}, .label = "radius"};
  v.push_back(car_scenario("car.cycle",
               "Simple parking cycle (section 5, steps i-iv): the net pose change is the holonomy of the loop, "
               "to leading order eps_alpha eps_beta [H_alpha, H_beta].",
               "(5.3), (5.5), (E.1)",
               with(car_params("0.2"), {number("eps_alpha", "0.1", "rad", "drive step in alpha", 0.0, true, 100.0),
                                        number("eps_beta", "0.1", "rad", "steering step in beta", 0.0, true, 1.0)}),
               cycle_metrics(), run_simple_cycle));
  v.back().headline = {.metrics = {"dx", "dy", "dphi"}, .label = "holonomy"};
  v.push_back(car_scenario("car.iterated",
               "Iterated cycle (5.8), ten steps: a sideways shift of the tie rod, -eps^4 [H_alpha, [H_alpha, H_beta]] "
               "= eps^4 R^2/l (sin phi, -cos phi) to leading order, heading unchanged.",
               "(5.6), (5.8), (5.9), (E.3)",
               with(car_params("0.2"), {number("eps", "0.3", "rad", "step size eps (alpha and beta)", 0.0, true, 1.0)}),
               cycle_metrics(), run_iterated_alpha));
  v.back().headline = {.metrics = {"dx", "dy", "dphi"}, .label = "holonomy"};
  v.push_back(car_scenario("car.iterated-beta",
               "Iterated cycle (5.10), ten steps: the car slides as if alpha changed without the wheel turning, "
               "-eps^4 [H_beta, [H_alpha, H_beta]] = -eps^4 (H_alpha - d_alpha) to leading order.",
               "(5.7), (5.10), (E.3)",
               with(car_params("0.2"), {number("eps", "0.3", "rad", "step size eps (alpha and beta)", 0.0, true, 1.0)}),
               cycle_metrics(), run_iterated_beta));
  v.back().headline = {.metrics = {"dx", "dy", "dphi"}, .label = "holonomy"};
  v.push_back(car_scenario("car.steer-in-place",
               "Turning the steering wheel alone moves no tie rod: H_beta = d/dbeta.",
               "(4.4), (C.10)",
               with(car_params("0.0"), {number("d_beta", "0.35", "rad", "steering change", -2.8, false, 2.8)}),
               {abs_("front_shift", "m", 1e-12, 1e-4, "largest displacement of the front-axle centre"),
                abs_("dphi", "rad", 1e-12, 1e-3, "heading change"),
                abs_("beta_reached", "rad", 1e-12, 1e-3, "realized steering angle at the end"),
                SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, TRACE_PATH, TRACE_SHAPE},
               run_steer_in_place));
  v.back().headline = {.metrics = {"front_shift"}, .label = "front-axle shift", .unit = "mm", .scale = 1e3};
  v.push_back(car_scenario("car.reparam",
               "The same path in (alpha, beta), steering while driving, at its pace and at f times it (every rate "
               "multiplied by f, every acceleration by f^2): the lift (4.1) is reparametrisation invariant, so both "
               "runs end in the same pose, that of the lift.",
               "(4.1), section 4",
               // The path's four short segments (2.55 m of wheel travel, mostly ramps) at 0.25 m/s^2 and
               // 1 rad/s^2 take 15.9 s; at f = 3 (1.5 m/s, 2.25 m/s^2, 0.75 rad/s, 9 rad/s^2) 5.3 s: three
               // times the pace, nine times the accelerations (the fast run's 104 N of drive within the
               // 235 N the front wheel grips with at mu = 1). Three speeds with the accelerations fixed
               // (0.125, 0.5 and 2 m/s) took 21.2, 8.2 and 7.9 s: a time ratio of 2.7.
               with(with_defaults(car_params("0.1"), {{"speed", "0.5"}, {"steer_rate", "0.25"}, {"accel", "0.25"}, {"steer_accel", "1.0"}}),
                    {number("factor", "3", "1", "pace factor f", 1.0, true, 100.0)}),
               {abs_("end_spread", "m", 1e-9, 1e-3, "largest distance between the end positions of the runs"),
                abs_("heading_spread", "rad", 1e-9, 1e-3, "largest difference between the end headings"),
                abs_("end_error", "m", 1e-7, 1e-3, "end position of the run at the path's own pace against the reference lift (Bulirsch-Stoer; the analytic engine runs dopri5, both at 1e-13 per step; they differ by up to 1.2e-8 m across the steering kinks)")},
               run_reparam));
  v.back().headline = {.metrics = {"end_spread"}, .label = "end spread", .unit = "mm", .scale = 1e3};
  {
    // Three headings, 0, 120 and 240 degrees (0, 30 and 60 modulo a right angle): a friction box fixed
    // to the world axes grips differently at each, while headings a right angle apart would all
    // see the same box. Each start drives 3.5 s (with the car's settle and hold 4.2 s).
    auto params = with(with_defaults(car_params("0.3"), {{"mu", "0.1"}, {"speed", "2.0"}}),
                       {number("drive", "2", "m", "arc length before the cycle", 0.0, true, 1e3),
                        integer("headings", "3", "1", "start headings over the full turn", 2.0, 64.0),
                        vec2("shift", "3,-2", "m", "translation of every other start", 1e4)});
    v.push_back(car_scenario("car.covariance",
                 "E(2) covariance (A.6): the same manoeuvre (an arc, then a parking cycle) started from 3 headings "
                 "over the full turn, every other one translated, must end in the same pose relative to its start. "
                 "On mu = 0.1 the 2 m arc (cruise speed 2 m/s, ramps of 1 m/s^2: it peaks at 1.13 m/s, grip use "
                 "v^2/(r g mu) = 0.38) loads the friction in a direction that turns with the start: isotropic friction "
                 "acts the same at every heading, a friction pyramid fixed to the world axes does not.",
                 "(A.6), equivariance of the lift",
                 params,
                 {abs_("spread_xy", "m", 1e-9, 1e-3, "largest distance between end positions in the start frames"),
                  abs_("spread_phi", "rad", 1e-9, 1e-3, "largest difference between end headings in the start frames")},
                 run_covariance));
    v.back().headline = {.metrics = {"spread_xy"}, .label = "end spread", .unit = "mm", .scale = 1e3};
  }
  {
    // Default geometry: the slope falls towards +y (slope_dir 0), the car heads along +x (phi 0),
    // across the slope. One lap at car.circle's 2 m/s on the 2.09 m circle of beta0 = 0.5 is 6.6 s
    // (the lateral 1.9 m/s^2 and gravity's downhill 2.9 m/s^2 well inside mu g cos(slope) = 9.4
    // m/s^2): with the 3 s park and the ramps the run steps 11.8 s.
    auto params = with(car_params("0.5"), {number("slope", "0.3", "rad", "tilt of gravity against the ground's normal (tan(slope) < mu)", 0.0, false, 1.4),
                                           number("slope_dir", "0", "rad", "direction of the tilt axis in the ground plane (downhill is this turned by +90 degrees)"),
                                           number("park", "3", "s", "parked with the wheels held before driving (creep measured over its last two thirds)", 0.5, false, 1e3),
                                           number("laps", "1", "1", "laps of the circle after the park", 0.5, false, 100.0)});
    params = with_defaults(std::move(params), {{"speed", "2.0"}, {"accel", "2.0"}});
    v.push_back(car_scenario("car.slope",
                 "On ground inclined by `slope` (gravity tilted; tan(slope) < mu) the no-slip constraint (3.3) does not see "
                 "gravity: the car parked across the slope with its wheels held must not move (creep), then its fixed-steering "
                 "circle must keep the radius l/sin(beta0) and close every lap without drifting downhill.",
                 "(3.3), (4.1), appendix D",
                 params,
                 {abs_("creep_speed", "m/s", 1e-12, 1e-6, "parked across the slope, wheels held: the farthest either axle centre gets from where it stood, over the last two thirds of the park, per second (regularised friction creeps)"),
                  rel("front_radius", "m", 1e-9, 1e-4, "fitted radius of the front-axle centre's path on the slope"),
                  rel("rear_radius", "m", 1e-9, 1e-4, "fitted radius of the rear-axle centre's path on the slope"),
                  abs_("drift_per_lap", "m", 1e-9, 1e-3, "downhill displacement of the front-axle centre from the start of the laps to their end, less the exact lift's (none over whole laps), per lap"),
                  abs_("final_offset", "m", 1e-9, 1e-3, "front-axle centre at the end against the exact lift (no creep, whole laps)"),
                  SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, TRACE_PATH, TRACE_SHAPE},
                 run_slope));
    v.back().headline = {.metrics = {"creep_speed"}, .label = "creep", .unit = "µm/s", .scale = 1e6};
  }
  {
    // Default: a 0.5 rad slope (tan 0.546) with mu = 0.3 (friction angle 0.29 rad): a = 2.12 m/s^2;
    // the car heads along +x, across the slope falling towards +y, so it slides along its axles.
    auto params = with(car_params("0.0"), {number("slope", "0.5", "rad", "tilt of gravity against the ground's normal (tan(slope) > mu)", 0.0, false, 1.4),
                                           number("slope_dir", "0", "rad", "direction of the tilt axis in the ground plane (downhill is this turned by +90 degrees)"),
                                           number("slide", "2", "s", "time held with the wheels locked after the settle", 0.5, false, 100.0),
                                           number("fit_from", "0.2", "s", "first sample of the fit (the settle's landing transient before it)", 0.0, false, 100.0)});
    params = with_defaults(std::move(params), {{"mu", "0.3"}});
    Scenario coulomb = car_scenario("car.coulomb",
                     "Coulomb's law: on a slope steeper than the friction angle the car, wheels locked, slides down like a block "
                     "with s(t) = g (sin(slope) - mu cos(slope)) t^2 / 2, which measures the engine's clock, its tilted gravity and its "
                     "effective friction coefficient at once (the no-slip lift does not apply: the analytic engine is skipped).",
                     "Coulomb friction; (3.3) does not hold",
                     params,
                     {rel("slide_accel", "m/s^2", 1e-9, 2e-3, "downhill acceleration of the centre of mass, fitted over the slide, against g (sin(slope) - mu cos(slope))"),
                      rel("slide_accel_across", "m/s^2", 1e-9, 5e-3, "acceleration across the slope, relative to the exact downhill one (0: the slide goes straight down)"),
                      abs_("heading_change", "rad", 1e-9, 1e-2, "heading change over the slide (a block slides without turning)"),
                      SLIP_ALONG, SLIP_ACROSS, SLIP_RMS},
                     run_coulomb);
    coulomb.needs_contact_dynamics = true;
    coulomb.headline = {.metrics = {"slide_accel"}, .label = "slide acceleration"};
    v.push_back(coulomb);
  }
  {
    auto params = with(car_params("0.3"), {number("drive", "10", "m", "front-wheel path length", 0.0, true, 1e4)});
    params = with_defaults(std::move(params), {{"mu", "0.1"}, {"speed", "3.0"}});
    Scenario beyond = car_scenario("car.beyond-grip",
                    "Past the grip limit (car.slip's drive: 3 m/s on the 3.4 m circle, mu = 0.1, the lift needs 2.7 mu g): the "
                    "ground pushes the car by at most mu times its weight, so its centre of mass may not accelerate horizontally "
                    "by more than mu g, and the car must slide off the lift (its front circle opens by at least 1%).",
                    "Coulomb friction bounds (4.1)",
                    params,
                    {COM_ACCEL,
                     abs_("slide_shortfall", "1", 1e-9, 0.0, "1 - (front circle's opening)/(1%), or 0 when it opened by 1% or more: the car kept grip the friction cannot give"),
                     SLIP_ALONG, SLIP_ACROSS, SLIP_RMS},
                    [](const Params& p, CarEngine& engine) {
                      beyond_grip_need(p);  // before the drive: a --set that leaves the grip is bad input
                      return judge_beyond_grip(p, run_circle(p, engine));
                    });
    // car.slip's drive: a suite with both makes it once.
    beyond.shared_drive = SharedDrive{kPastGripDrive, run_circle, judge_beyond_grip};
    beyond.needs_contact_dynamics = true;
    // Both halves of the engine's error: grip the friction cannot give (as a fraction of mu g, and
    // as the share of the 1% opening the circle failed to make).
    beyond.headline = {.metrics = {"com_accel_excess", "slide_shortfall"}, .label = "excess grip"};
    v.push_back(beyond);
  }
  {
    auto params = with(car_params("0.3"), {number("drive", "10", "m", "front-wheel path length", 0.0, true, 1e4)});
    params = with_defaults(std::move(params), {{"mu", "0.1"}, {"speed", "3.0"}});
    Scenario slip = car_scenario("car.slip",
                  "Negative control: at 3 m/s on a 3.4 m circle with mu = 0.1 the lateral acceleration needs "
                  "v^2/(r g) = 0.27 > mu, so the car slides; the harness must detect it and the no-slip "
                  "comparison must fail.",
                  "(4.1) fails without grip",
                  params,
                  {rel("front_radius", "m", 1e-9, 1e-4, "fitted radius of the front-axle centre's path"),
                   rel("rear_radius", "m", 1e-9, 1e-4, "fitted radius of the rear-axle centre's path"),
                   abs_("final_offset", "m", 1e-9, 1e-3, "front-axle centre at the end against the exact arc"),
                   SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, TRACE_PATH, TRACE_SHAPE},
                  [](const Params& p, CarEngine& engine) { return judge_slip(p, run_circle(p, engine)); });
    slip.shared_drive = SharedDrive{kPastGripDrive, run_circle, judge_slip};
    slip.needs_contact_dynamics = true;
    slip.negative_control = true;
    slip.headline = {.metrics = {"front_radius", "rear_radius"}, .label = "radius"};
    v.push_back(slip);
  }
  return v;
}

}  // namespace liftcheck
