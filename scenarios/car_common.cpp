#include <cmath>
#include <fmt/format.h>
#include <map>

#include "models/holonomy.hpp"
#include "models/lift.hpp"
#include "scenarios/car_common.hpp"
#include "scenarios/fit.hpp"

namespace liftcheck::car_common {

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
      choice("wheels", "3",
             "3: the paper's tricycle; 4: two Ackermann-steered front wheels driven by an electronic differential (the "
             "reference is the same tricycle: average wheel angle, virtual steering angle)",
             {"3", "4"}),
      number("track", "0.8", "m", "distance between the rear wheels (and between the front wheels of a four-wheel car)",
             0.0, true, 100.0),
      choice("steering", "ackermann",
             "four wheels: each front wheel at its Ackermann angle, or both at beta (parallel: they fight and scrub)",
             {"ackermann", "parallel"}),
      // The masses in a real car's proportions: a passenger car's wheel with its tyre weighs 15 to
      // 25 kg and its steering knuckle with hub and brake about as much, against 1200 to 1600 kg
      // of body. The tricycle keeps a 40 kg chassis and 2 kg wheels (chassis/wheel 20, gentler on
      // a solver than a real car's 60 to 80) and a knuckle as heavy as a wheel (ratio 1); the
      // 0.05 kg knuckle it had before (ratios 40 and 800 along chassis-knuckle-wheel) is the
      // extreme of the knuckle_mass sweep. The analytic lift does not depend on any mass.
      number("chassis_mass", "40", "kg", "chassis mass (a box from the rear to the front axle, no collision)", 0.0,
             true, 1e5),
      number("wheel_mass", "2", "kg", "mass of each wheel", 0.0, true, 1e4),
      number("knuckle_mass", "2", "kg",
             "mass of each steering knuckle (the body between the chassis and a steered wheel)", 0.0, true, 1e4),
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

namespace {

/// The lag tau of a realized angle behind its command, from samples of e = command - realized and
/// the command's rate r: realized(t) = command(t - tau) = command(t) - tau r(t) to first order, so
/// tau = sum(e r) / sum(r^2), the least-squares fit.
struct LagFit {
  double er = 0.0, rr = 0.0;
  void add(double error_rad, double rate_radps) { er += error_rad * rate_radps, rr += rate_radps * rate_radps; }
  /// Whether the command moves at all (a path that does not steer has no steering lag).
  bool moves() const { return rr > 0.0; }
  double steps(double dt_s) const { return moves() ? er / rr / dt_s : 0.0; }
};

}  // namespace

/// A simulator outside liftcheck shows only its trace: its whole path is compared with the exact
/// lift of the commanded path at every sample (front-axle position), and its realized shape with
/// the commanded one. An engine liftcheck runs is judged by the same comparisons of its own trace
/// (up to the path's end, as a trace written back covers it), so that its verdict does not depend
/// on the road its results took. A model that reports the commanded shape and its exact lift (the
/// analytic engine) compares them with themselves: informational.
void add_trace_check(Outcome& o, const CarEngine& engine, const CarSetup& setup, const car::BasePath& path,
                     const Config& q0, const std::vector<car::TimedConfig>& trace) {
  double pos = 0.0, shape = 0.0;
  LagFit alpha_lag, beta_lag;
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
    alpha_lag.add(cmd.alpha_rad - s.q.alpha_rad, cmd.alpha_rate_radps);
    beta_lag.add(cmd.beta_rad - s.q.beta_rad, cmd.beta_rate_radps);
  }
  const bool by_construction = engine.exact_by_construction();
  o.values["trace_path_error"] = {.expected = 0.0, .measured = pos, .informational = by_construction};
  o.values["trace_shape_error"] = {.expected = 0.0, .measured = shape, .informational = by_construction};
  o.values["drive_lag"] = {
      .expected = 0.0, .measured = alpha_lag.steps(setup.dt_s), .informational = by_construction || !alpha_lag.moves()};
  o.values["steer_lag"] = {
      .expected = 0.0, .measured = beta_lag.steps(setup.dt_s), .informational = by_construction || !beta_lag.moves()};
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
nlohmann::json error_split(const car::CarDef& c, const std::vector<car::TimedConfig>& trace,
                           const Config& commanded_end) {
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
/// The ground's load checks (LOAD_REST, LOAD_DRIVE, MOMENTUM, and HOLD_REST on a slope) from the
/// engine's own contact forces, or the reason they are not measured (details "ground_load").
void add_load(Outcome& o, const CarEngine& engine) {
  const GroundLoad g = engine.ground_load();
  if (!g.absent_why.empty()) {
    o.details[detail_key::kGroundLoad] = {{detail_key::kNotMeasured, g.absent_why}};
    return;
  }
  o.values["load_at_rest"] = {.expected = g.weight_normal_N, .measured = g.rest_normal_N};
  o.values["load_over_drive"] = {.expected = g.weight_normal_N, .measured = g.drive_normal_N};
  if (g.momentum_absent_why.empty())
    o.values["momentum_balance"] = {.expected = 0.0, .measured = g.momentum_gap_Ns, .scale = g.momentum_scale_Ns};
  if (g.plane_weight_N > 1e-6 * g.weight_normal_N)  // on a slope: the grip holds gravity's pull
    o.values["hold_at_rest"] = {.expected = 0.0, .measured = g.rest_hold_gap_N, .scale = g.plane_weight_N};
  o.details["ground_load"] = {{"weight_normal_N", g.weight_normal_N},       {"rest_normal_N", g.rest_normal_N},
                              {"drive_normal_N", g.drive_normal_N},         {"plane_weight_N", g.plane_weight_N},
                              {"rest_hold_gap_N", g.rest_hold_gap_N},       {"momentum_gap_Ns", g.momentum_gap_Ns},
                              {"momentum_change_Ns", g.momentum_change_Ns}, {"momentum_scale_Ns", g.momentum_scale_Ns}};
  if (!g.momentum_absent_why.empty()) o.details["ground_load"]["momentum_not_measured"] = g.momentum_absent_why;
}

void add_slip(Outcome& o, const CarEngine& engine) {
  add_load(o, engine);
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
    wheels.push_back({{"wheel", w.wheel},
                      {"along_max_mps", w.along_max_mps},
                      {"across_max_mps", w.across_max_mps},
                      {"rms_mps", w.rms_mps},
                      {"roll_mean_mps", w.roll_mean_mps}});
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
    v_peak_mps =
        std::max(v_peak_mps, setup.car.R_m * std::abs(path.at(std::min(smp.t_s, path.duration_s())).alpha_rate_radps));
  const double step_travel_factor = v_peak_mps * setup.dt_s / (0.5 * 1e-3);
  o.values["realized_lift_error"] = {.expected = 0.0,
                                     .measured = worst,
                                     .tolerance_factor = step_travel_factor,
                                     .informational = engine.exact_by_construction()};
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
    const Eigen::Vector2d a =
        2.0 * ((com(trace[i + 1].q) - com(trace[i].q)) / h1 - (com(trace[i].q) - com(trace[i - 1].q)) / h0) / (h0 + h1);
    worst = std::max(worst, a.norm());
  }
  return std::max(0.0, worst / (s.mu * s.gravity_mps2) - 1.0);
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

MetricDef reference_only(MetricDef m) {
  m.reference_only = true;
  return m;
}

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
  return {
      SLIP_ALONG,
      SLIP_ACROSS,
      SLIP_RMS,
      LOAD_REST,
      LOAD_DRIVE,
      MOMENTUM,
      TRACE_PATH,
      TRACE_SHAPE,
      STEER_LAG,
      DRIVE_LAG,
      REALIZED_LIFT,
      floored(rel("dx", "m", 1e-9, 0.02, "net x change against the exact holonomy" + size)),
      floored(rel("dy", "m", 1e-9, 0.02, "net y change against the exact holonomy" + size)),
      floored(rel("dphi", "rad", 1e-9, 0.02, "net heading change against the exact holonomy" + size + " / l")),
      abs_("base_closure", "rad", 1e-12, 1e-3, "the realized (alpha, beta) path closes"),
      // Leading-order predictions are off by O(eps) relative: tolerance 1.0 x eps for every engine.
      reference_only(rel("lo_dx", "m", 1.0, 1.0,
                         "net x change against the bracket prediction (tolerance x eps): the leading order's check, "
                         "counted for the reference only")),
      reference_only(rel("lo_dy", "m", 1.0, 1.0,
                         "net y change against the bracket prediction (tolerance x eps): the leading order's check, "
                         "counted for the reference only")),
      reference_only(rel("lo_dphi", "rad", 1.0, 1.0,
                         "net heading change against the bracket prediction (tolerance x eps): the leading order's "
                         "check, counted for the reference only")),
  };
}

}  // namespace liftcheck::car_common
