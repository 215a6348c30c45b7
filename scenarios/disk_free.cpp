// The disk scenarios without contact (Farber, Kurz, Pillin, sections 3 and 5): copying, the actuated
// no-reaction, the orbit, and the planners of (14) and (17).
#include <cmath>
#include <fmt/format.h>
#include <numbers>

#include "scenarios/disk_common.hpp"
#include "scenarios/disk_scenarios.hpp"

namespace liftcheck {

using namespace disk_common;

namespace {

Outcome run_copy(const Params& p, DiskEngine& e) {
  disks::Mechanism m;  // (36)
  const DiskProblem pb = problem(p, m);
  const DiskRun r = run_checked(e, setup_from(p), pb);
  const double d0 = (p.vec("cM") - p.vec("cN")).norm();
  const disks::LiftResult ref = analytic(pb, setup_from(p));
  // c_M - c_N is constant: no contact from a disjoint start, and c_M(t) = c_M(0) + c_N(t) - c_N(0).
  Outcome o = disk_outcome(p, pb, r, ref, std::nullopt,
                           [&](double t) { return Vec2(pb.cM0 + pb.path.position(t) - pb.path.position(0.0)); });
  o.values["min_distance"] = {.expected = d0, .measured = r.min_distance, .tolerance_factor = first_order(p)};
  o.values["final_distance"] = {.expected = d0, .measured = final_distance(r), .tolerance_factor = first_order(p)};
  o.values["distance_spread"] = {.expected = 0.0, .measured = spreads(r).first, .tolerance_factor = first_order(p)};
  o.values["direction_change"] = {.expected = 0.0, .measured = spreads(r).second, .tolerance_factor = first_order(p)};
  return o;
}

Outcome run_actuated(const Params& p, DiskEngine& e) {
  disks::Mechanism m;
  m.kind = disks::MechanismKind::kActuated;  // (37)
  const DiskProblem pb = problem(p, m);
  const DiskRun r = run_checked(e, setup_from(p), pb);
  const disks::LiftResult ref = analytic(pb, setup_from(p));
  return disk_outcome(p, pb, r, ref, ref.t_contact_s);
}

Outcome run_orbit(const Params& p, DiskEngine& e) {
  disks::Mechanism m;
  m.kind = disks::MechanismKind::kRotation;  // (40)
  m.omega = p.num("omega");
  if (std::abs(m.omega) * setup_from(p).sample_dt_s > 1.0)
    throw InputError(
        "disks.orbit needs |omega| sample_dt <= 1 rad: the turned angle is followed from sample to sample");
  const DiskProblem pb = problem(p, m);
  const DiskRun r = run_checked(e, setup_from(p), pb);
  const double T = p.num("T");
  // Turned angle of c_M - c_N, unwrapped along the trace.
  double turned = 0.0;
  for (std::size_t i = 1; i < r.trace.size(); ++i) {
    const Vec2 a = r.trace[i - 1].cM - r.trace[i - 1].cN, b = r.trace[i].cM - r.trace[i].cN;
    turned += std::atan2(a.x() * b.y() - a.y() * b.x(), a.dot(b));
  }
  Outcome o = disk_outcome(p, pb, r, analytic(pb, setup_from(p)), std::nullopt);  // the distance is constant
  o.values["distance_spread"] = {.expected = 0.0, .measured = spreads(r).first, .tolerance_factor = first_order(p)};
  o.values["turned_angle"] = {.expected = m.omega * T, .measured = turned, .tolerance_factor = first_order(p)};
  return o;
}

disks::Lifting copy_lifting(const disks::NPath& path) {
  return [path](const Vec2& c, double t) { return Vec2(c + path.position(t) - path.position(0.0)); };
}

Outcome run_extended(const Params& p, DiskEngine& e) {
  const disks::NPath path = path_from(p);
  const Vec2 cM0 = p.vec("cM"), cM1 = p.vec("target");
  const double T = p.num("T"), clearance = p.num("clearance");
  check_start(cM1, path.position(0.0));
  check_clearance(cM0, cM1, path.position(0.0), clearance);
  const disks::Lifting L = copy_lifting(path);
  const auto q = [=](double t) { return disks::extended(L, cM0, cM1, path, T, std::clamp(t, 0.0, T), clearance); };
  check_continuous(q, T);
  const DiskProblem pb{disks::rule_following(q, T), path, cM0, T};
  const disks::LiftResult ref = analytic(pb, setup_from(p));  // first: a plan without a lift is bad input
  const DiskRun r = run_checked(e, setup_from(p), pb);
  Outcome o = disk_outcome(p, pb, r, ref, std::nullopt);  // the plan keeps the clearance in N's frame
  o.values["end_error"] = {
      .expected = 0.0,
      .measured = (r.trace.back().cM - L(cM1, T)).norm(),
      .tolerance_factor = first_order(p)};  // (11): ends at L(e', gamma)(1)  // (11): ends at L(e', gamma)(1)
  return o;
}

Outcome run_target(const Params& p, DiskEngine& e) {
  const disks::NPath path = path_from(p);
  const Vec2 cM0 = p.vec("cM"), v0 = p.vec("target");
  const double T = p.num("T"), clearance = p.num("clearance"), w = p.num("target_omega");
  check_start(v0, path.position(0.0));
  check_clearance(cM0, v0, path.position(0.0), clearance);
  // The target keeps its own reaction mechanism: it circles N as under (40).
  const Vec2 rel0 = v0 - path.position(0.0);
  const auto target = [=](double t) {
    const double c = std::cos(w * t), s = std::sin(w * t);
    return Vec2(path.position(t) + Vec2(c * rel0.x() - s * rel0.y(), s * rel0.x() + c * rel0.y()));
  };
  const disks::Lifting L = copy_lifting(path);
  const auto q = [=](double t) { return disks::navigate(L, cM0, target, path, T, std::clamp(t, 0.0, T), clearance); };
  check_continuous(q, T);
  const DiskProblem pb{disks::rule_following(q, T), path, cM0, T};
  const disks::LiftResult ref = analytic(pb, setup_from(p));  // first: a plan without a lift is bad input
  const DiskRun r = run_checked(e, setup_from(p), pb);
  Outcome o = disk_outcome(p, pb, r, ref, std::nullopt);
  o.values["end_error"] = {
      .expected = 0.0, .measured = (r.trace.back().cM - target(T)).norm(), .tolerance_factor = first_order(p)};
  return o;
}

}  // namespace

std::vector<Scenario> contact_free_disk_scenarios() {
  return {
      {.name = "disks.copy",
       .vehicle = Vehicle::kDisks,
       .summary = "M copies N's velocity: c_M - c_N stays constant, the disks never touch.",
       .equations = "(36), section 5.3",
       .params = disk_params("0,0", "3,0", "1,0", "figure8", "6"),
       .metrics = disk_metrics({kDistanceSpread, kDirectionChange}),
       .run_disks = run_copy,
       .headline = {.metrics = {"step_displacement"}, .label = "step against command", .unit = "µm", .scale = 1e6}},
      {.name = "disks.actuated",
       .vehicle = Vehicle::kDisks,
       .summary = "Actuated no-reaction: M stays put until N comes within 3, then follows it more and more.",
       .equations = "(37), Figure 6",
       .params = disk_params("0,0", "6,0.5", "-1,0", "line", "8"),
       .metrics = disk_metrics({}),
       .run_disks = run_actuated,
       .headline = {.metrics = {"step_displacement"}, .label = "step against command", .unit = "µm", .scale = 1e6}},
      {.name = "disks.orbit",
       .vehicle = Vehicle::kDisks,
       .summary = "Rotation: M circles N at constant distance with angular velocity omega (the paper's mu).",
       .equations = "(40), section 5.6",
       .params = with(disk_params("0,0", "3,0", "1,0", "circle", "6"),
                      {number("omega", "0.8", "rad/s", "angular velocity of (40)", -100.0, false, 100.0)}),
       .metrics = disk_metrics({kDistanceSpread, abs_("turned_angle", "rad", 1e-8, 5e-3, "angle turned by c_M - c_N")}),
       .run_disks = run_orbit,
       .headline = {.metrics = {"step_displacement"}, .label = "step against command", .unit = "µm", .scale = 1e6}},
      {.name = "disks.extended",
       .vehicle = Vehicle::kDisks,
       .summary = "Extended algorithm for a known motion of N: a plan in the fibre around N, lifted by the copy "
                  "mechanism, ends at the lift of the target.",
       .equations = "(11), (14)",
       .params = with(disk_params("-4,0.1", "0,0", "0.6,0.2", "line", "8", true, kPlannerTmax),
                      {vec2("target", "4,-0.3", "m", "target position of M over N's start"),
                       number("clearance", "2.2", "m", "planner's distance kept from c_N", 2.0, true, 100.0)}),
       .metrics = disk_metrics({abs_("end_error", "m", 1e-6, 1e-2, "c_M(T) against L(e', gamma)(T)")}, kPlanTol),
       .run_disks = run_extended,
       .headline = {.metrics = {"step_displacement"}, .label = "step against command", .unit = "µm", .scale = 1e6}},
      {.name = "disks.target",
       .vehicle = Vehicle::kDisks,
       .summary = "Navigation to a moving target that circles N with its own mechanism: M ends on the target.",
       .equations = "(16), (17)",
       .params = with(disk_params("-4,0", "1,0", "1,0", "figure8", "8", true, kPlannerTmax),
                      {vec2("target", "5,0", "m", "initial target position"),
                       number("target_omega", "0.4", "rad/s", "the target's rotation about N (40)", -10.0, false, 10.0),
                       number("clearance", "2.2", "m", "planner's distance kept from c_N", 2.0, true, 100.0)}),
       .metrics = disk_metrics({abs_("end_error", "m", 1e-6, 1e-2, "c_M(T) against the target v(T)")}, kPlanTol),
       .run_disks = run_target,
       .headline = {.metrics = {"step_displacement"}, .label = "step against command", .unit = "µm", .scale = 1e6}}};
}

}  // namespace liftcheck
