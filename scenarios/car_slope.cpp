// The car on a slope: parked and circling where grip holds (3.3), sliding where it cannot (Coulomb).
#include <cmath>
#include <fmt/format.h>
#include <map>

#include "engines/rigid_car.hpp"
#include "models/holonomy.hpp"
#include "models/lift.hpp"
#include "models/slide.hpp"
#include "scenarios/car_common.hpp"
#include "scenarios/fit.hpp"

namespace liftcheck {

using namespace car_common;

namespace {

// ---- car.slope -----------------------------------------------------------------------------

/// Gravity tilted by `slope` about the horizontal axis at angle `slope_dir` in the ground plane
/// (the ground stays z = 0): Rodrigues' rotation of (0, 0, -1) about a = (cos d, sin d, 0),
/// g_dir = (-sin d sin s, cos d sin s, -cos s). Its horizontal part points downhill.
Eigen::Vector3d tilted_gravity_dir(double slope_rad, double slope_dir_rad) {
  return {-std::sin(slope_dir_rad) * std::sin(slope_rad), std::cos(slope_dir_rad) * std::sin(slope_rad),
          -std::cos(slope_rad)};
}

/// The trace's sample nearest to time t.
const car::TimedConfig& sample_at(const std::vector<car::TimedConfig>& trace, double t_s) {
  auto it = std::lower_bound(trace.begin(), trace.end(), t_s - 1e-9,
                             [](const car::TimedConfig& a, double t) { return a.t_s < t; });
  if (it == trace.end()) return trace.back();
  if (it != trace.begin() && std::abs(std::prev(it)->t_s - t_s) < std::abs(it->t_s - t_s)) return *std::prev(it);
  return *it;
}

Outcome run_slope(const Params& p, CarEngine& engine) {
  CarSetup setup = setup_from(p);
  const Config q0 = start_from(p);
  const double slope = p.num("slope"), slope_dir = p.num("slope_dir"), park = p.num("park"), laps = p.num("laps");
  if (!(std::tan(slope) < setup.mu))
    throw InputError(fmt::format("car.slope needs tan(slope) < mu for the car to hold: tan({:g}) = {:.3g} >= mu = {:g}",
                                 slope, std::tan(slope), setup.mu));
  if (std::abs(q0.beta_rad) < 1e-3)
    throw InputError("car.slope needs |beta| >= 0.001 rad: beta = 0 drives a straight line");
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
      creep_m = std::max({creep_m, (Eigen::Vector2d(smp.q.x_m, smp.q.y_m) - front0).norm(),
                          (car::rear_axle_W(setup.car, smp.q) - rear0).norm()});
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
    throw InputError(fmt::format(
        "car.slope needs at least 8 samples of the laps to fit their circle: sample_dt = {:g} s is too coarse",
        setup.sample_dt_s));
  const CircleFit ff = fit_circle(front), rf = fit_circle(rear);
  const Config& end = trace.back().q;
  const Config end_exact = car::flow_alpha(setup.car, q0, d_alpha);
  const Eigen::Vector2d lap_shift(end.x_m - c1.q.x_m, end.y_m - c1.q.y_m),
      exact_shift(end_exact.x_m - q0.x_m, end_exact.y_m - q0.y_m);

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
               {detail_key::kGripUse,
                (setup.drive.speed_mps * setup.drive.speed_mps / fe.radius_m + setup.gravity_mps2 * std::sin(slope)) /
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

/// The exact slide as a trace at the engine's sample times, what the pictures draw car.coulomb
/// against (the lift (4.1) does not apply to a sliding car): the car released at rest in the
/// scenario's start pose q0 when its settle begins (`settle_s` before t = 0), its centre of mass
/// at a (t + settle_s)^2 / 2 down the fall line with a exact (constant from the first contact),
/// not moving across it (Coulomb friction pushes nothing across), heading and steering held.
std::vector<car::TimedConfig> exact_slide(const std::vector<car::TimedConfig>& trace, const car::Config& q0,
                                          double settle_s, double a_exact, const Eigen::Vector2d& downhill,
                                          const Eigen::Vector2d& cB) {
  const Eigen::Vector2d com_to_ref = -(Eigen::Rotation2Dd(q0.phi_rad) * cB);
  const Eigen::Vector2d com0 = Eigen::Vector2d(q0.x_m, q0.y_m) - com_to_ref;
  std::vector<car::TimedConfig> out;
  for (const auto& smp : trace) {
    const double t = smp.t_s + settle_s;
    const Eigen::Vector2d p = com0 + 0.5 * a_exact * t * t * downhill + com_to_ref;
    out.push_back({smp.t_s, {q0.alpha_rad, q0.beta_rad, p.x(), p.y(), q0.phi_rad}});
  }
  return out;
}

/// The slide: the car released at rest on ground tilted by `slope` towards `slope_dir`, every
/// commanded rate zero (the front wheels' servos hold alpha and beta; a braked run's rear wheels
/// held by the engine's own motors), its centre of mass fitted s(t) = s0 + v0 t + a t^2 / 2 along
/// the fall line and across it over the samples from `fit_from` on (it slides from the start of
/// the settle, so s0 and v0 are free). Coulomb's law (isotropic): a = g (sin(slope) - mu
/// cos(slope)) straight down, the friction of every sliding contact mu times its normal load, which
/// sum to the weight's normal part. The acceleration measures the engine's clock (a step of the
/// wrong length scales it by the square of the ratio), its tilted gravity and its effective friction
/// coefficient at once.
Outcome run_slide(const Params& p, CarEngine& engine, const char* name, double slope_dir, bool brake) {
  CarSetup setup = setup_from(p);
  const Config q0 = start_from(p);
  const double slope = p.num("slope"), T = p.num("slide"), fit_from = p.num("fit_from");
  if (!(std::tan(slope) > setup.mu * 1.05))
    throw InputError(fmt::format("{} needs tan(slope) > 1.05 mu for the car to slide: tan({:g}) = {:.3g}, mu = {:g}",
                                 name, slope, std::tan(slope), setup.mu));
  if (!(fit_from + 0.2 < T))
    throw InputError(fmt::format("{} needs fit_from + 0.2 s < slide: {:g} and {:g} s", name, fit_from, T));
  setup.gravity_dir_W = tilted_gravity_dir(slope, slope_dir);
  setup.rear_brake = brake;
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
    throw InputError(fmt::format("{} needs at least 8 samples to fit the slide: sample_dt = {:g} s is too coarse", name,
                                 setup.sample_dt_s));
  const double g = setup.gravity_mps2, a_exact = g * (std::sin(slope) - setup.mu * std::cos(slope));
  const double a = fit_accel(ts, s_down), a_across = fit_accel(ts, s_across);
  Outcome o;
  o.values["slide_accel"] = {a_exact, a};
  // Straight down: sliding friction opposes the slide, so nothing pushes the car across it.
  o.values["slide_accel_across"] = {.expected = 0.0, .measured = a_across, .scale = a_exact};
  o.values["heading_change"] = {0.0, std::abs(e2::wrap_angle(trace.back().q.phi_rad - trace.front().q.phi_rad))};
  o.details = {{detail_key::kTrace, trace_json(trace)},
               {detail_key::kReference, trace_json(exact_slide(trace, q0, ServoDef{}.settle_s, a_exact, downhill, cB))},
               {detail_key::kReferenceLabel, "the exact Coulomb slide"},
               {"gravity_W_mps2", {setup.gravity_W().x(), setup.gravity_W().y(), setup.gravity_W().z()}},
               {"effective_mu", (g * std::sin(slope) - a) / (g * std::cos(slope))},
               {"clock_ratio_if_mu_exact", std::sqrt(a / a_exact)}};
  add_slip(o, engine);
  for (const char* k : {"slip_along_max", "slip_across_max", "slip_rms"})
    if (o.values.count(k)) o.values[k].informational = true;  // the car slides: that is the point here
  // The car slides from the start of the settle and is still sliding when the drive ends: it is
  // never at rest, and the mean normal force over the drive also holds the change of its vertical
  // momentum, which this run does not measure. No load checks here; Newton's second law along the
  // ground (momentum_balance) holds sliding or not: the friction force makes the slide.
  for (const char* k : {"load_at_rest", "load_over_drive", "hold_at_rest"}) o.values.erase(k);
  return o;
}

/// car.coulomb: the car across the slope, its axles along the fall line, its front wheel held by
/// its servos and its rear wheels free (a wheel's friction along its axle acts whether it rolls or
/// not), slides down like a block.
Outcome run_coulomb(const Params& p, CarEngine& engine) {
  return run_slide(p, engine, "car.coulomb", p.num("slope_dir"), false);
}

/// car.yawed-slide: the braked car, the fall line at `yaw` to its axles (towards its heading), so
/// that every contact slides along neither of its friction directions. Coulomb's law is isotropic:
/// the slide goes straight down at car.coulomb's rate. A per-axis friction pyramid (each of a
/// contact's two friction rows bounded by mu N apart, models/slide.hpp) grips harder and pushes
/// the car sideways; the run records that law's figures beside the measured ones.
Outcome run_yawed_slide(const Params& p, CarEngine& engine) {
  const double yaw = p.num("yaw"), slope = p.num("slope");
  Outcome o = run_slide(p, engine, "car.yawed-slide", p.num("phi") - yaw, true);
  const slide::SlideDef def{.g_mps2 = p.num("gravity"), .slope_rad = slope, .mu = p.num("mu"), .yaw_rad = yaw};
  const slide::SlideAccel box = slide::slide_accel(def, slide::Law::kAxisPyramid);
  // In the run's own terms: the car's axle (left) and heading in the world, the fall line
  // downhill, "across" as slide_accel_across measures it.
  const double phi = p.num("phi"), sd = phi - yaw;
  const Eigen::Vector2d axle(-std::sin(phi), std::cos(phi)), heading(std::cos(phi), std::sin(phi));
  const Eigen::Vector2d a_W = box.a_car_mps2.x() * axle + box.a_car_mps2.y() * heading;
  const Eigen::Vector2d downhill(-std::sin(sd), std::cos(sd));
  o.details["axis_pyramid_accel_mps2"] = {{"along", a_W.dot(downhill)},
                                          {"across", a_W.x() * downhill.y() - a_W.y() * downhill.x()}};
  // Every wheel held: their rolling speed against the exact slide's mean speed over the drive,
  // a (settle + slide / 2). A wheel without a spin state of its own (a raycast vehicle's) shows
  // it, not counted; a trace without wheel states (a replay) leaves it unmeasured, as the slip.
  const std::vector<WheelSlip> wheels = engine.slip();
  if (wheels.empty()) return o;
  double roll_mps = 0.0;
  bool spins = true;
  for (const WheelSlip& w : wheels) roll_mps = std::max(roll_mps, w.roll_mean_mps), spins = spins && w.along_measured;
  const double mean_speed_mps = o.values.at("slide_accel").expected * (ServoDef{}.settle_s + 0.5 * p.num("slide"));
  o.values["brake_hold"] = {.expected = 0.0, .measured = roll_mps, .scale = mean_speed_mps, .informational = !spins};
  return o;
}

/// The slides' parameters: the slope, the fall line's direction (`direction`), the slide's length
/// with its wheels held as `held` says, and the fit's start; mu 0.3.
std::vector<ParamSpec> slide_params(ParamSpec direction, const char* held) {
  return with_defaults(
      with(car_params("0.0"),
           {number("slope", "0.5", "rad", "tilt of gravity against the ground's normal (tan(slope) > mu)", 0.0, false,
                   1.4),
            std::move(direction),
            number("slide", "2", "s", fmt::format("time held with {} after the settle", held), 0.5, false, 100.0),
            number("fit_from", "0.2", "s", "first sample of the fit (the settle's landing transient before it)", 0.0,
                   false, 100.0)}),
      {{"mu", "0.3"}});
}

}  // namespace

namespace {

Scenario slope_scenario() {
  // Default geometry: the slope falls towards +y (slope_dir 0), the car heads along +x (phi 0),
  // across the slope. One lap at car.circle's 2 m/s on the 2.09 m circle of beta0 = 0.5 is 6.6 s
  // (the lateral 1.9 m/s^2 and gravity's downhill 2.9 m/s^2 well inside mu g cos(slope) = 9.4
  // m/s^2): with the 3 s park and the ramps the run steps 11.8 s.
  return {
      .name = "car.slope",
      .vehicle = Vehicle::kCar,
      .summary =
          "On ground inclined by `slope` (gravity tilted; tan(slope) < mu) the no-slip constraint (3.3) does not see "
          "gravity: the car parked across the slope with its wheels held must not move (creep), then its "
          "fixed-steering "
          "circle must keep the radius l/sin(beta0) and close every lap without drifting downhill.",
      .equations = "(3.3), (4.1), appendix D",
      .params = with_defaults(
          with(car_params("0.5"),
               {number("slope", "0.3", "rad", "tilt of gravity against the ground's normal (tan(slope) < mu)", 0.0,
                       false, 1.4),
                number("slope_dir", "0", "rad",
                       "direction of the tilt axis in the ground plane (downhill is this turned by +90 degrees)"),
                number("park", "3", "s",
                       "parked with the wheels held before driving (creep measured over its last two thirds)", 0.5,
                       false, 1e3),
                number("laps", "1", "1", "laps of the circle after the park", 0.5, false, 100.0)}),
          {{"speed", "2.0"}, {"accel", "2.0"}}),
      .metrics = {abs_("creep_speed", "m/s", 1e-12, 1e-6,
                       "parked across the slope, wheels held: the farthest either axle centre gets from where it "
                       "stood, over the last two thirds of the park, per second (regularised friction creeps)"),
                  rel("front_radius", "m", 1e-9, 1e-4, "fitted radius of the front-axle centre's path on the slope"),
                  rel("rear_radius", "m", 1e-9, 1e-4, "fitted radius of the rear-axle centre's path on the slope"),
                  abs_("drift_per_lap", "m", 1e-9, 1e-3,
                       "downhill displacement of the front-axle centre from the start of the laps to their end, less "
                       "the exact lift's (none over whole laps), per lap"),
                  abs_("final_offset", "m", 1e-9, 1e-3,
                       "front-axle centre at the end against the exact lift (no creep, whole laps)"),
                  SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, LOAD_REST, LOAD_DRIVE, HOLD_REST, MOMENTUM, TRACE_PATH,
                  TRACE_SHAPE, STEER_LAG, DRIVE_LAG},
      .run_car = run_slope,
      .headline = {.metrics = {"creep_speed"}, .label = "creep", .unit = "µm/s", .scale = 1e6}};
}

Scenario coulomb_scenario() {
  // Default: a 0.5 rad slope (tan 0.546) with mu = 0.3 (friction angle 0.29 rad): a = 2.12 m/s^2;
  // the car heads along +x, across the slope falling towards +y, so it slides along its axles.
  return {
      .name = "car.coulomb",
      .vehicle = Vehicle::kCar,
      .summary =
          "Coulomb's law: on a slope steeper than the friction angle the car, wheels locked, slides down like a block "
          "with s(t) = g (sin(slope) - mu cos(slope)) t^2 / 2, which measures the engine's clock, its tilted gravity "
          "and its "
          "effective friction coefficient at once (the no-slip lift does not apply: the analytic engine is skipped).",
      .equations = "Coulomb friction; (3.3) does not hold",
      .params = slide_params(number("slope_dir", "0", "rad",
                                    "direction of the tilt axis in the ground plane (downhill is this turned by +90 "
                                    "degrees)"),
                             "the wheels locked"),
      .metrics =
          {rel("slide_accel", "m/s^2", 1e-9, 2e-3,
               "downhill acceleration of the centre of mass, fitted over the slide, against g (sin(slope) - mu "
               "cos(slope))"),
           rel("slide_accel_across", "m/s^2", 1e-9, 5e-3,
               "acceleration across the slope, relative to the exact downhill one (0: the slide goes straight down)"),
           abs_("heading_change", "rad", 1e-9, 1e-2, "heading change over the slide (a block slides without turning)"),
           SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, MOMENTUM},
      .run_car = run_coulomb,
      .needs_contact_dynamics = true,
      .headline = {.metrics = {"slide_accel"}, .label = "slide acceleration"}};
}

Scenario yawed_slide_scenario() {
  // Default: car.coulomb's slope and friction (a = 2.12 m/s^2), the car braked and turned so that
  // the fall line makes 40 degrees with its axles: a per-axis friction pyramid slides at 1.06
  // m/s^2 down and 0.32 m/s^2 across (models/slide.hpp).
  return {
      .name = "car.yawed-slide",
      .vehicle = Vehicle::kCar,
      .summary =
          "Coulomb's law is isotropic: the car, every wheel held (the front by its servos, the rear by the engine's "
          "own brake), on a slope steeper than the friction angle with the fall line at `yaw` to its axles, slides "
          "straight down at g (sin(slope) - mu cos(slope)) like a block, as it does along its axles. A per-axis "
          "friction pyramid grips harder off its axes and pushes the car sideways (its figures are in the run's "
          "record).",
      .equations = "Coulomb friction (isotropic); (3.3) does not hold",
      .params = slide_params(
          number("yaw", "0.6981317007977318", "rad",
                 "angle from the car's axles to the fall line, towards its heading (40 degrees)", -3.2, false, 3.2),
          "every wheel braked"),
      .metrics =
          {rel("slide_accel", "m/s^2", 1e-9, 2e-3,
               "acceleration of the centre of mass down the fall line, fitted over the slide, against g (sin(slope) "
               "- mu cos(slope)) (a per-axis pyramid: about half)"),
           rel("slide_accel_across", "m/s^2", 1e-9, 5e-3,
               "acceleration across the fall line, relative to the exact downhill one (0: Coulomb's law pushes "
               "nothing across the slide)"),
           abs_("heading_change", "rad", 1e-9, 1e-2, "heading change over the slide (a block slides without turning)"),
           rel("brake_hold", "m/s", 1e-9, 1e-2,
               "the fastest wheel's mean rolling speed over the drive (|omega . axle| x hub height), relative to the "
               "exact slide's mean speed: 0 where the brakes and servos hold every wheel"),
           SLIP_ALONG, SLIP_ACROSS, SLIP_RMS, MOMENTUM},
      .run_car = run_yawed_slide,
      .needs_contact_dynamics = true,
      .needs_brakes = true,
      .headline = {.metrics = {"slide_accel"}, .label = "yawed slide acceleration"}};
}

}  // namespace

std::vector<Scenario> slope_scenarios() { return {slope_scenario(), coulomb_scenario(), yawed_slide_scenario()}; }

}  // namespace liftcheck
