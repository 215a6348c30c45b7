#include "scenarios/disk_common.hpp"

#include <cmath>
#include <fmt/format.h>
#include <numbers>

#include <boost/math/tools/roots.hpp>

namespace liftcheck::disk_common {

/// Parameters every disk scenario shares; `path` is left out where the scenario fixes N's motion.
std::vector<ParamSpec> disk_params(const std::string& cM, const std::string& cN, const std::string& vN,
                                   const std::string& path, const std::string& T, bool with_path, double T_max) {
  std::vector<ParamSpec> v{
      vec2("cM", cM, "m", "initial centre of the ego disk M"),
      vec2("cN", cN, "m", "initial centre of the other disk N"),
      vec2("vN", vN, "m/s", "N's velocity (line path) or speed as |vN| (toward path)", 1e3),
  };
  if (with_path) v.push_back(choice("path", path, "N's path", {"line", "circle", "figure8"}));
  v.push_back(number("path_r", "3", "m", "radius of the circle and figure-eight paths", 0.0, true, 100.0));
  v.push_back(
      number("path_omega", "0.5", "rad/s", "angular rate of the circle and figure-eight paths", -10.0, false, 10.0));
  v.push_back(number("T", T, "s", "duration", 0.0, true, T_max));
  v.push_back(number("dt", "0.001", "s", "engine time step", 0.0, true, 0.1));
  v.push_back(number("sample_dt", "0.02", "s", "spacing of the recorded trace", 0.0, true, 10.0));
  return v;
}

disks::NPath path_from(const Params& p) {
  disks::NPath path;
  path.c0 = p.vec("cN");
  path.v = p.vec("vN");
  path.radius_m = p.num("path_r");
  path.omega_radps = p.num("path_omega");
  const std::string& k = p.str("path");
  path.kind = k == "circle"    ? disks::NPath::Kind::kCircle
              : k == "figure8" ? disks::NPath::Kind::kFigure8
                               : disks::NPath::Kind::kLine;
  return path;
}

/// The trace is sampled every whole number of engine steps closest to sample_dt (at least one).
DiskSetup setup_from(const Params& p) {
  const double dt = p.num("dt");
  if (!(dt < p.num("T")))
    throw InputError(fmt::format("parameter 'dt' must be < T = {:g} s (the duration), got '{:g}'", p.num("T"), dt));
  if (!(p.num("sample_dt") <= p.num("T")))
    throw InputError(fmt::format("parameter 'sample_dt' must be <= T = {:g} s (the duration), got '{:g}'", p.num("T"),
                                 p.num("sample_dt")));
  check_run_budget(p.num("T"), dt, p.num("sample_dt"));
  return {1.0, dt, dt * std::max(1L, std::lround(p.num("sample_dt") / dt))};
}

void check_start(const Vec2& cM, const Vec2& cN) {
  if ((cM - cN).norm() < disks::kContactDistance)
    throw InputError(fmt::format("the initial centres cM and cN overlap: |cM - cN| = {:.6g}, must be >= 2 (unit disks)",
                                 (cM - cN).norm()));
}

/// The plans (14), (17) must be continuous in t for M to follow them; where two paths around N
/// are equally short the planner switches sides and the plan jumps. Sampled finely, a jump
/// between neighbours of more than 0.1 m is such a switch (N moves at most 1000 m/s here, so a
/// continuous plan moves far less over T / 20000).
void check_continuous(const std::function<Vec2(double)>& q, double T) {
  constexpr int n = 20000;
  Vec2 prev = q(0.0);
  for (int k = 1; k <= n; ++k) {
    const double t = T * k / n;
    const Vec2 cur = q(t);
    if ((cur - prev).norm() > 0.1)
      throw InputError(fmt::format(
          "the plan switches sides around N at t = {:.4f} s (it jumps {:.3g} m): choose another T, target or path", t,
          (cur - prev).norm()));
    prev = cur;
  }
}

/// The planners keep `clearance` from N: start and goal must lie outside that circle.
void check_clearance(const Vec2& a, const Vec2& b, const Vec2& cN, double clearance) {
  for (const Vec2& q : {a, b})
    if ((q - cN).norm() < clearance)
      throw InputError(
          fmt::format("the planner keeps clearance {} m from c_N, but a start or target lies {:.6g} m from it",
                      clearance, (q - cN).norm()));
}

DiskRun run_checked(DiskEngine& engine, const DiskSetup& setup, const DiskProblem& pb) {
  check_start(pb.cM0, pb.path.position(0.0));
  return engine.run(setup, pb);
}

nlohmann::json trace_json(const std::vector<disks::Sample>& trace) {
  nlohmann::json rows = nlohmann::json::array();
  const std::size_t stride = std::max<std::size_t>(1, trace.size() / 400);  // every row up to 799 (score reads them)
  const auto row = [&](const disks::Sample& s) { rows.push_back({s.t_s, s.cM.x(), s.cM.y(), s.cN.x(), s.cN.y()}); };
  for (std::size_t i = 0; i < trace.size(); i += stride) row(trace[i]);
  if (!trace.empty() && (trace.size() - 1) % stride != 0) row(trace.back());  // and the last
  return rows;
}

/// The first time the relative position rel(t) has |rel| <= 2 on [0, T]: a fine scan, then TOMS 748.
std::optional<double> first_contact(const std::function<Vec2(double)>& rel, double T) {
  const auto f = [&](double t) { return rel(t).norm() - disks::kContactDistance; };
  if (f(0.0) <= 0.0) return 0.0;
  const int n = std::max(1000, static_cast<int>(T / 1e-3));
  double ta = 0.0, fa = f(0.0);
  for (int k = 1; k <= n; ++k) {
    const double tb = T * k / n, fb = f(tb);
    if (fb <= 0.0) {
      boost::uintmax_t it = 200;
      const auto [lo, hi] =
          boost::math::tools::toms748_solve(f, ta, tb, fa, fb, boost::math::tools::eps_tolerance<double>(52), it);
      return 0.5 * (lo + hi);
    }
    ta = tb;
    fa = fb;
  }
  return std::nullopt;
}

double final_distance(const DiskRun& r) { return (r.trace.back().cM - r.trace.back().cN).norm(); }

/// Engines integrate M's commanded velocity step by step: their trajectory errors are first order
/// in dt. Tolerances of trajectory metrics are data at dt = 1 ms, scaled by dt / 1 ms.
double first_order(const Params& p) { return p.num("dt") / 1e-3; }

/// The lift (21) of the problem, integrated with a different method (Bulirsch-Stoer) from the one
/// the analytic engine runs (dopri5), and sampled where the engines sample.
disks::LiftResult analytic(const DiskProblem& pb, const DiskSetup& setup) {
  disks::LiftDef def;
  def.method = disks::LiftMethod::kBulirschStoer;
  def.sample_dt_s = setup.sample_dt_s;
  try {
    return disks::lift(pb.rule, pb.path, pb.cM0, pb.T_s, def);
  } catch (const disks::LiftStalled& e) {  // the problem, not an engine: no exact reference exists
    throw InputError(std::string(e.what()) + " (the plan switches sides around N; choose another T or target)");
  }
}

/// Largest |c_M - c_M,ref(t)| over the trace samples up to t_limit.
double path_error(const DiskRun& run, const std::function<Vec2(double)>& cM_ref, double t_limit) {
  double e = 0.0;
  for (const auto& s : run.trace) {
    if (s.t_s > t_limit) break;
    e = std::max(e, (s.cM - cM_ref(s.t_s)).norm());
  }
  return e;
}

/// The reference lift's c_M at a sample time of the engine's trace (both sample at i * spacing).
std::function<Vec2(double)> at_samples(const disks::LiftResult& ref) {
  return [&ref](double t) {
    const auto it = std::lower_bound(ref.trace.begin(), ref.trace.end(), t - 1e-9,
                                     [](const disks::Sample& s, double x) { return s.t_s < x; });
    if (it == ref.trace.end() || std::abs(it->t_s - t) > 1e-9)
      throw std::logic_error(fmt::format("the reference has no sample at t = {} s", t));
    return it->cM;
  };
}

/// penetration_max's tolerance: contact is first seen up to one step of closing travel deep; a
/// Baumgarte-stabilised response (ERP 0.2) holds a sustained push at up to 1 / ERP = 5 such steps.
constexpr double kPenetrationSteps = 5.0;

/// The trace sample of `trace` at time t (the traces compared share the grid i * sample spacing).
const disks::Sample& sample_at(const std::vector<disks::Sample>& trace, double t) {
  const auto it = std::lower_bound(trace.begin(), trace.end(), t - 1e-9,
                                   [](const disks::Sample& s, double x) { return s.t_s < x; });
  if (it == trace.end() || std::abs(it->t_s - t) > 1e-9)
    throw std::logic_error(fmt::format("the reference has no sample at t = {} s", t));
  return *it;
}

/// The contact-time shift of the zero-order hold itself: M stepped by its command held over each
/// step (the forward Euler of the lift (21) at dt, which is what an engine that realises its
/// command does, to round-off) first overlaps N in some step; that step's midpoint against the
/// exact time. It depends on the problem and dt only, never on the engine judged.
double zoh_contact_shift_s(const DiskProblem& pb, double dt, double t_exact) {
  const long steps = static_cast<long>(std::ceil(pb.T_s / dt - 1e-9));
  Vec2 cM = pb.cM0;
  for (long k = 0; k <= steps; ++k) {
    const double t = std::min(k * dt, pb.T_s);
    const Vec2 cN = pb.path.position(t);
    if ((cM - cN).norm() <= disks::kContactDistance) return std::abs(std::max(0.0, t - 0.5 * dt) - t_exact);
    cM += std::min(dt, pb.T_s - t) * pb.rule(t, cM, cN, pb.path.velocity(t));
  }
  return std::abs(pb.T_s - t_exact);  // the held command misses N within T: it is late by at least this
}

/// After the first contact (class of faults: contacts that stick, stop M dead or bounce). The
/// frictionless, inelastic response is exact (models/disk_contact.hpp); it is integrated from the
/// state on which the engine first reported contact (its own positions, so the comparison starts
/// where the engine's contact did) to T: M's path against it at every trace sample after
/// contact, and the time the first contact lasts against the reference's. Tolerances in steps:
/// of M's travel relative to N at contact (path), of dt (duration).
void after_contact(Outcome& o, const DiskProblem& pb, const DiskRun& run, const DiskSetup& setup) {
  if (!run.contact_state) return;
  const disks::Sample& c = *run.contact_state;
  disks::LiftDef def;
  def.method = disks::LiftMethod::kBulirschStoer;
  def.sample_dt_s = setup.sample_dt_s;
  disks::ResponseResult ref;
  try {
    ref = disks::lift_with_response(pb.rule, pb.path, c.cM, c.t_s, pb.T_s, def);
  } catch (const disks::LiftStalled& e) {
    throw InputError(std::string(e.what()) +
                     " (the reference after contact has no exact solution here; choose another T)");
  }
  double err = 0.0;
  for (const auto& s : run.trace)
    if (s.t_s > c.t_s + 1e-12) err = std::max(err, (s.cM - sample_at(ref.trace, s.t_s).cM).norm());
  const bool stepping = run.contact_log.has_value();
  const Vec2 vN = pb.path.velocity(c.t_s);
  const double rel_speed = (pb.rule(c.t_s, c.cM, c.cN, vN) - vN).norm();
  // A step of relative travel, at least the round-off of a touching distance (a command equal to N's velocity).
  o.values["contact_path_error"] = {
      .expected = 0.0,
      .measured = err,
      .tolerance_factor = stepping ? std::max(rel_speed * setup.dt_s, kTouchRoundoff_m) : 1.0};
  // The contact must last while the command presses M into N and end when it points away; where
  // the command comes to rest against N (n.(v_cmd - v_N) = 0) it may end anywhere in between (at
  // rest, touching and a push-out's gap of a micrometre are both the inelastic answer).
  const double press_end = ref.t_press_end_s.value_or(pb.T_s), release = ref.t_release_s.value_or(pb.T_s);
  const double end_run = run.t_release_s.value_or(pb.T_s);
  const double closing = std::max(0.0, -(c.cM - c.cN).normalized().dot(pb.rule(c.t_s, c.cM, c.cN, vN) - vN));
  // An engine's release is seen up to a step late, and an engine holding the disks delta deep
  // (penetration_max allows kPenetrationSteps steps of closing travel) separates only once M has
  // gone on along the tangent far enough to clear it, 2 sqrt(delta) / |v_rel| later.
  const double bound_s =
      2.0 * setup.dt_s + 2.0 * std::sqrt(kPenetrationSteps * closing * setup.dt_s) / std::max(rel_speed, 1e-9);
  o.values["contact_duration"] = {.expected = std::clamp(end_run, press_end, release) - c.t_s,
                                  .measured = end_run - c.t_s,
                                  .tolerance_factor = stepping ? bound_s : 1.0};
  o.details["after_contact"] = {
      {"from_t_s", c.t_s},
      {"relative_speed_mps", rel_speed},
      {"reference_release_s", ref.t_release_s ? nlohmann::json(*ref.t_release_s) : nlohmann::json()},
      {"reference_press_end_s", ref.t_press_end_s ? nlohmann::json(*ref.t_press_end_s) : nlohmann::json()},
      {"duration_bound_s", stepping ? bound_s : 1.0},
      {"release_s", run.t_release_s ? nlohmann::json(*run.t_release_s) : nlohmann::json()},
      {"reference", trace_json(ref.trace)}};
}

/// What every disk scenario measures. Before contact the engine must follow the lift: its path
/// against `cM_ref`, and, where the disks never touch, the closest approach and the final
/// distance. Contact: collision and its time (in steps), and, from the engine's own contact log,
/// that it reported contact on the first state whose disks overlapped and not before, and that
/// its contact response kept the penetration small.
Outcome disk_outcome(const Params& p, const DiskProblem& pb, const DiskRun& run, const disks::LiftResult& ref,
                     const std::optional<double>& expected_t, const std::function<Vec2(double)>& cM_ref) {
  const double dt = p.num("dt"), f = first_order(p);
  Outcome o;
  o.details[detail_key::kTrace] = trace_json(run.trace);
  o.details[detail_key::kReference] = trace_json(ref.trace);
  o.values["collision"] = {.expected = expected_t ? 1.0 : 0.0, .measured = run.t_contact_s ? 1.0 : 0.0};
  o.details["t_contact_expected_s"] = expected_t ? nlohmann::json(*expected_t) : nlohmann::json();
  o.details[detail_key::kTContactMeasured] = run.t_contact_s ? nlohmann::json(*run.t_contact_s) : nlohmann::json();
  o.details[detail_key::kReferenceMinDistance] = ref.min_distance;
  const double t_limit = std::min(expected_t.value_or(INFINITY), run.t_contact_s.value_or(INFINITY));
  const double path_err = path_error(run, cM_ref, t_limit);
  o.values["path_error"] = {.expected = 0.0, .measured = path_err, .tolerance_factor = f};
  // The lift's closing speed -d|c_M - c_N|/dt at the expected contact.
  double closing = NAN;
  if (expected_t && ref.cM_contact.allFinite()) {
    const Vec2 cN = pb.path.position(*expected_t), vN = pb.path.velocity(*expected_t);
    closing = -(ref.cM_contact - cN).normalized().dot(pb.rule(*expected_t, ref.cM_contact, cN, vN) - vN);
    o.details["closing_speed_mps"] = closing;
  }
  if (expected_t && run.t_contact_s) {
    // A stepping engine's contact happened between its last state reported free of contact and its
    // first reported in contact: the midpoint of that step is compared. The tolerance is that step
    // plus the shift of the zero-order hold itself (an engine integrating its held command is
    // first-order early or late by that much and no more); it is computed from the problem and dt,
    // not from the engine judged.
    const double t = run.contact_log ? std::max(0.0, *run.t_contact_s - 0.5 * dt) : *run.t_contact_s;
    const double shift_s = run.contact_log ? zoh_contact_shift_s(pb, dt, *expected_t) : 0.0;
    o.values["t_contact"] = {.expected = *expected_t, .measured = t, .tolerance_factor = dt + shift_s};
    o.details["t_contact_shift_allowed_s"] = shift_s;
  }
  if (!expected_t && !run.t_contact_s) {
    o.values["min_distance"] = {.expected = ref.min_distance, .measured = run.min_distance, .tolerance_factor = f};
    o.values["final_distance"] = {
        .expected = ref.final_distance, .measured = final_distance(run), .tolerance_factor = f};
  }
  after_contact(o, pb, run, setup_from(p));
  if (const auto& log = run.contact_log) {
    o.values["n_path_error"] = {.expected = 0.0, .measured = log->n_path_error_max_m};
    // Before contact each step moves M by its command times the step (a trace from outside is not
    // known to hold its command over a step: it may integrate otherwise).
    if (log->reported_by_engine) {
      o.values["step_displacement"] = {.expected = 0.0, .measured = log->step_displacement_error_max_m};
      o.details["step_displacement_at_s"] = log->step_displacement_error_at_s;
    }
    // M's spin, held by every engine (a trace from outside has positions only).
    if (log->reported_by_engine) {
      o.values["spin_M_max"] = {.expected = 0.0, .measured = log->spin_M_max_radps};
      o.details["spin_M_max_at_s"] = log->spin_M_max_at_s;
    }
    if (log->reported_by_engine)
      o.values["contact_missed"] = {.expected = 0.0, .measured = std::max(0.0, log->overlap_unreported_m)};
    if (run.t_contact_s) {
      if (log->reported_by_engine) {
        o.values["contact_report_gap"] = {.expected = 0.0, .measured = std::max(0.0, log->gap_reported_max_m)};
        o.values["contact_depth_error"] = {.expected = 0.0, .measured = log->depth_error_max_m};
      }
      // A response acting on the first contact stops the approach within that step.
      if (closing > 0.0)
        o.values["overlap_growth"] = {
            .expected = 0.0, .measured = std::max(0.0, log->overlap_growth_first_m), .tolerance_factor = closing * dt};
      // The response must bound the overlap (tolerance in steps of closing travel).
      if (closing > 0.0)
        o.values["penetration_max"] = {
            .expected = 0.0, .measured = std::max(0.0, log->penetration_max_m), .tolerance_factor = closing * dt};
    }
    o.details[detail_key::kContactLog] = {
        {"distance_at_first_m",
         std::isfinite(log->distance_at_first_m) ? nlohmann::json(log->distance_at_first_m) : nlohmann::json()},
        {"overlap_unreported_m", log->overlap_unreported_m},
        {"gap_reported_max_m", log->gap_reported_max_m},
        {"depth_error_max_m", log->depth_error_max_m},
        {"overlap_growth_first_m", log->overlap_growth_first_m},
        {"n_path_error_max_m", log->n_path_error_max_m},
        {"penetration_max_m", log->penetration_max_m},
        {"depth_reported_max_m", log->depth_reported_max_m},
        {"steps_in_contact", log->steps_in_contact},
        {"apart_at_end", log->apart_at_end}};
  }
  return o;
}

Outcome disk_outcome(const Params& p, const DiskProblem& pb, const DiskRun& run, const disks::LiftResult& ref,
                     const std::optional<double>& expected_t) {
  return disk_outcome(p, pb, run, ref, expected_t, at_samples(ref));
}

/// Largest |d(t) - d(0)| and largest angle between c(t) = c_M - c_N and c(0) over the trace.
std::pair<double, double> spreads(const DiskRun& r, double t_limit) {
  const Vec2 c0 = r.trace.front().cM - r.trace.front().cN;
  double dd = 0.0, ang = 0.0;
  for (const auto& s : r.trace) {
    if (s.t_s > t_limit || (r.t_contact_s && s.t_s > *r.t_contact_s)) break;
    const Vec2 c = s.cM - s.cN;
    dd = std::max(dd, std::abs(c.norm() - c0.norm()));
    ang = std::max(ang, std::abs(std::atan2(c0.x() * c.y() - c0.y() * c.x(), c0.dot(c))));
  }
  return {dd, ang};
}

DiskProblem problem(const Params& p, const disks::Mechanism& m) {
  return {disks::rule_of(m), path_from(p), p.vec("cM"), p.num("T")};
}

const MetricDef kCollision{
    "collision", "1", TolKind::kAbsolute, {{TolRole::kDefault, 0.0}}, "1 if the disks touch within T, else 0"};
// The contact time is compared in engine steps: the tolerance is this many steps of dt.
const MetricDef kTContact{
    "t_contact",
    "s",
    TolKind::kAbsolute,
    {{TolRole::kReference, 1e-6}, {TolRole::kDefault, 1.0}},
    "first contact time (engines: the midpoint of the step in which contact came); tolerance in steps of dt"};

disks::Mechanism linear_from(const Params& p) {
  disks::Mechanism m;
  m.kind = disks::MechanismKind::kLinear;  // (41)
  m.a = p.num("a");
  m.b = p.num("b");
  return m;
}

namespace {
const MetricDef final_d = abs_("final_distance", "m", 1e-8, 1e-2, "|c_M - c_N| at T (runs without contact)");
const MetricDef min_d = abs_("min_distance", "m", 1e-8, 1e-2, "closest approach |c_M - c_N| (runs without contact)");
}  // namespace

namespace {

/// A metric of the engine's bookkeeping against itself, in metres: held to its own round-off (1e-9
/// m in float64, scaled with the precision it declares: MetricDef::bookkeeping).
MetricDef bookkeeping_m(const std::string& name, const std::string& help) {
  return {name, "m", TolKind::kAbsolute, {{TolRole::kDefault, 1e-9}}, help, {}, true};
}

}  // namespace

std::vector<MetricDef> disk_metrics(std::vector<MetricDef> extra, double analytic_path_tol) {
  std::vector<MetricDef> all{
      kCollision,
      kTContact,
      abs_("path_error", "m", 1e-8, 1e-2, "largest distance of c_M from the reference up to the first contact"),
      // The engine's own contact log against its own reported positions: exact for any engine.
      bookkeeping_m("n_path_error", "largest distance of N, as the engine moved it, from its path"),
      bookkeeping_m("contact_missed",
                    "largest overlap 2 - |c_M - c_N| on a state the engine's collision pass reported free of contact"),
      bookkeeping_m("contact_report_gap",
                    "largest gap |c_M - c_N| - 2 on a state the engine's collision pass reported in contact"),
      bookkeeping_m("contact_depth_error",
                    "largest difference between the depth the engine's contacts report and the overlap of its bodies"),
      abs_("overlap_growth", "m", 0.0, 0.1,
           "growth of the overlap over the step after the first contact; tolerance in steps of closing travel"),
      abs_("penetration_max", "m", 0.0, kPenetrationSteps,
           "largest overlap 2 - |c_M - c_N| after the first contact; tolerance in steps of closing travel at the "
           "lift's closing speed"),
      min_d,
      final_d,
      // Round-off: float64 positions of at most 100 m carry 1.4e-14 m of it per step (float32: a few
      // 1e-7 m at 10 m, so the floor scales with the declared precision); a motor one step late is
      // off by the change of its command times dt (2 mm on the first step from rest at 2 m/s).
      bookkeeping_m(
          "step_displacement",
          "largest |step displacement of M - v_cmd dt| over the free steps before the first contact (not the step in "
          "which the engine's contact stops M at touching)"),
      // Farber's disks are planar vehicles whose velocity is commanded: M does not turn. An engine
      // that leaves its spin free lets friction between the disks roll M on N instead of moving it
      // (disks.oblique with M-N friction: M's path within 3.4e-4 m of the frictionless response).
      // Held by a joint or a lock, it is zero to round-off; a spin of 1e-6 rad/s turns M's surface
      // by a micrometre a second. The scenarios' disks are frictionless, so their contact puts no
      // torque on M (a free M turns at 4e-15 rad/s on cannon-es): here the metric catches a torque
      // of the engine's own making; that every adapter holds the spin is the conformance test's
      // (DisksHoldMsSpinAndFeelFrictionBetweenThem, with friction between the disks).
      {"spin_M_max",
       "rad/s",
       TolKind::kAbsolute,
       {{TolRole::kDefault, 1e-6}},
       "largest angular speed |omega_M| of M after any step: every engine holds M's spin"},
      // Engines: the penetration penetration_max allows (kPenetrationSteps steps of closing travel, along n)
      // plus one step of travel along the tangent (contact is seen up to a step late, M went straight on).
      abs_("contact_path_error", "m", 1e-8, kPenetrationSteps + 1.0,
           "largest distance of M after the first contact from the exact frictionless, inelastic response started at "
           "that contact; "
           "tolerance in steps of M's travel relative to N"),
      // Engines: 1 x the bound of after_contact (two steps, and the time to clear an allowed penetration).
      abs_("contact_duration", "s", 1e-6, 1.0,
           "how long the first contact lasts (to a separation of 1 um, or T) against the exact response's; tolerance a "
           "multiple "
           "of two steps plus the time M takes to clear an allowed penetration after release")};
  for (auto& m : all)
    if (m.name == "path_error" || m.name == "min_distance" || m.name == "final_distance")
      m.tolerance[TolRole::kReference] = analytic_path_tol;
  all.insert(all.end(), extra.begin(), extra.end());
  return all;
}

}  // namespace liftcheck::disk_common
