// The disk scenarios that meet (Farber, Kurz, Pillin, sections 5 and 6): repel, the linear mechanism
// head-on and oblique, the forced collision, and the moving-away reaction that prevents one.
#include <cmath>
#include <fmt/format.h>
#include <numbers>

#include "scenarios/disk_common.hpp"
#include "scenarios/disk_scenarios.hpp"

namespace liftcheck {

using namespace disk_common;

namespace {

Outcome run_repel(const Params& p, DiskEngine& e) {
  disks::Mechanism m;
  m.kind = disks::MechanismKind::kRepel;  // (38)
  m.lambda = p.num("lambda");
  if (std::abs(m.lambda) * p.num("T") > 50.0)
    throw InputError(fmt::format("disks.repel needs |lambda| T <= 50: the distance would change by a factor e^{:.0f}",
                                 std::abs(m.lambda) * p.num("T")));
  const DiskProblem pb = problem(p, m);
  const DiskRun r = run_checked(e, setup_from(p), pb);
  const double d0 = (p.vec("cM") - p.vec("cN")).norm(), T = p.num("T");
  const std::optional<double> touch = disks::repel_touch_time(d0, m.lambda);  // Lemma 5.1
  const std::optional<double> t = touch && *touch <= T ? touch : std::nullopt;
  Outcome o = disk_outcome(p, pb, r, analytic(pb, setup_from(p)), t);
  if (!t && !r.t_contact_s)
    o.values["final_distance"] = {.expected = disks::repel_distance(d0, m.lambda, T),
                                  .measured = final_distance(r),
                                  .tolerance_factor = first_order(p)};
  o.values["direction_change"] = {
      .expected = 0.0, .measured = spreads(r, t.value_or(T)).second, .tolerance_factor = first_order(p)};
  return o;
}

Outcome run_linear(const Params& p, DiskEngine& e) {
  const disks::Mechanism m = linear_from(p);
  const DiskProblem pb = problem(p, m);
  const DiskRun r = run_checked(e, setup_from(p), pb);
  const Vec2 cM0 = p.vec("cM"), cN0 = p.vec("cN");
  // (43): c_M(t) = A c_N(t) - c0, for any path of N; the contact is a root of its distance.
  const auto closed = [&](double t) { return disks::linear_cM(m.a, m.b, cM0, cN0, pb.path.position(t)); };
  const auto t = first_contact([&](double s) { return Vec2(closed(s) - pb.path.position(s)); }, pb.T_s);
  // The engine's path is compared with the closed form (43) itself.
  Outcome o = disk_outcome(p, pb, r, analytic(pb, setup_from(p)), t, closed);
  if (!t && !r.t_contact_s) {
    o.values["cM_end_error"] = {.expected = 0.0,
                                .measured = (r.trace.back().cM - closed(r.trace.back().t_s)).norm(),
                                .tolerance_factor = first_order(p)};
    o.values["final_distance"] = {.expected = (closed(pb.T_s) - pb.path.position(pb.T_s)).norm(),
                                  .measured = final_distance(r),
                                  .tolerance_factor = first_order(p)};
  }
  if (m.a != 1.0 || m.b != 0.0) {
    const Vec2 chat = disks::collision_centre(m.a, m.b, cM0, cN0);
    o.details[detail_key::kCollisionCentre] = {chat.x(), chat.y()};
    o.details[detail_key::kCollisionRadius] = disks::collision_radius(m.a, m.b);
  }
  o.details["linear"] = disks::satisfies_linearity(m);
  return o;
}

Outcome run_forced(const Params& p, DiskEngine& e) {
  const disks::Mechanism m = linear_from(p);
  if (m.a == 1.0 && m.b == 0.0)
    throw InputError("disks.forced needs (a, b) != (1, 0): copying N cannot be forced into contact");
  const Vec2 cM0 = p.vec("cM"), cN0 = p.vec("cN");
  const double speed = p.vec("vN").norm();
  if (!(speed > 0.0)) throw InputError("disks.forced needs a non-zero speed |vN|");
  disks::NPath path;  // Corollary 6.3: N drives straight into the ball D
  path.kind = disks::NPath::Kind::kToward;
  path.c0 = cN0;
  path.v = p.vec("vN");
  path.goal = disks::collision_centre(m.a, m.b, cM0, cN0);
  const DiskProblem pb{disks::rule_of(m), path, cM0, p.num("T")};
  const DiskRun r = run_checked(e, setup_from(p), pb);
  double t = disks::forced_contact_time(m.a, m.b, cM0, cN0, speed);
  Outcome o =
      disk_outcome(p, pb, r, analytic(pb, setup_from(p)), t <= p.num("T") ? std::optional<double>(t) : std::nullopt);
  if (r.t_contact_s) {  // Lemma 6.1: at contact N is on the boundary of D
    const Vec2 cN = path.position(*r.t_contact_s);
    o.values["contact_on_D"] = {.expected = disks::collision_radius(m.a, m.b),
                                .measured = (cN - path.goal).norm(),
                                .tolerance_factor = p.num("dt") * speed};
  }
  o.details[detail_key::kCollisionCentre] = {path.goal.x(), path.goal.y()};
  o.details[detail_key::kCollisionRadius] = disks::collision_radius(m.a, m.b);
  return o;
}

Outcome run_moving_away(const Params& p, DiskEngine& e) {
  disks::Mechanism m = linear_from(p);
  m.moving_away = true;  // Corollary 4.5: (41) + the reaction form (31)
  m.k_away = p.num("k_away");
  const DiskProblem pb = problem(p, m);
  const DiskRun r = run_checked(e, setup_from(p), pb);
  const disks::LiftResult ref = analytic(pb, setup_from(p));
  disks::Mechanism base = linear_from(p);
  const disks::LiftResult without = disks::lift(base, pb.path, pb.cM0, pb.T_s);
  Outcome o = disk_outcome(p, pb, r, ref, ref.t_contact_s);
  o.details["base_mechanism_t_contact_s"] =
      without.t_contact_s ? nlohmann::json(*without.t_contact_s) : nlohmann::json();
  return o;
}

/// The copy lifting function (36): L(e, gamma)(t) = c_M + c_N(t) - c_N(0).

}  // namespace

double linear_outcome_horizon_s(const Params& p, double clearance_m, double after_s, double min_s) {
  const disks::Mechanism m = linear_from(p);
  const disks::NPath path = path_from(p);
  const Vec2 cM0 = p.vec("cM"), cN0 = p.vec("cN");
  const double T = p.num("T"), h = 0.01;  // 1 cm of N's travel at 1 m/s between samples
  double clear_from = 0.0;
  bool contact = false;
  for (int k = 0; k * h <= T && !contact; ++k) {
    const Vec2 cN = path.position(k * h);
    const double d = (disks::linear_cM(m.a, m.b, cM0, cN0, cN) - cN).norm();
    contact = d <= disks::kContactDistance;
    if (d < disks::kContactDistance + clearance_m) clear_from = (k + 1) * h;
  }
  if (contact) {
    // After the contact (43) no longer holds: the exact motion goes on with the frictionless,
    // inelastic response (models/disk_contact.hpp; Bulirsch-Stoer here, the reference engine runs
    // dopri5) until M's command leaves N, then free again. A contact held to T keeps T.
    disks::LiftDef def;
    def.method = disks::LiftMethod::kBulirschStoer;
    def.sample_dt_s = h;
    const disks::ResponseResult exact = disks::lift_with_response(disks::rule_of(m), path, cM0, 0.0, T, def);
    if (!exact.t_release_s) return T;
    for (const disks::Sample& smp : exact.trace)
      if ((smp.cM - smp.cN).norm() < disks::kContactDistance + clearance_m) clear_from = smp.t_s + h;
  }
  return std::min(T, std::max(min_s, std::round((clear_from + after_s) / h) * h));
}

std::vector<Scenario> contact_disk_scenarios() {
  return {
      {.name = "disks.repel",
       .vehicle = Vehicle::kDisks,
       .summary = "Repel/attract: d(t) = exp(λ t) d(0) with constant direction for any motion of N; "
                  "for λ < 0 the disks touch at ln(2/d(0))/λ.",
       .equations = "(38), (39), Lemma 5.1",
       .params = with(disk_params("0,0", "5,0", "1,0", "line", "4"),
                      {number("lambda", "-0.5", "1/s", "rate lambda of (38)", -100.0, false, 100.0)}),
       .metrics = disk_metrics({kDirectionChange}),
       .run_disks = run_repel,
       .headline = {.metrics = {"contact_path_error"}, .label = "after-contact path", .unit = "mm", .scale = 1e3}},
      {.name = "disks.linear",
       .vehicle = Vehicle::kDisks,
       .summary = "Linear mechanism with constant coefficients: c_M(t) = A c_N(t) - c0 for any motion of N; "
                  "contact when N enters the ball D.",
       .equations = "(41)-(46), Lemma 6.1",
       .params = with(disk_params("0,0", "3,0", "1,0", "line", "4"),
                      {number("a", "2", "1", "coefficient a (the paper's alpha)", -100.0, false, 100.0),
                       number("b", "0", "1", "coefficient b (the paper's beta)", -100.0, false, 100.0)}),
       .metrics = disk_metrics({abs_("cM_end_error", "m", 1e-8, 1e-2, "c_M at T against (43) (runs without contact)")}),
       .run_disks = run_linear,
       .headline = {.metrics = {"penetration_max"}, .label = "penetration", .unit = "mm", .scale = 1e3}},
      // Oblique: the relative command u = B v_N = (1, 0) carries M past N at an offset of 1, so it meets
      // N at 150 degrees (t = 4 - sqrt 3), slides over it frictionlessly and leaves it on the tangent at
      // 90 degrees, (2/|u|) ln tan 75 deg = 2.63 s later (models/disk_contact.hpp).
      {.name = "disks.oblique",
       .vehicle = Vehicle::kDisks,
       .summary = "Oblique contact under the linear mechanism: M meets N off its line of approach, slides over it "
                  "(frictionless, inelastic) and leaves it along the tangent when its command points away.",
       .equations = "(41)-(43), (34)",
       .params = with(disk_params("0,1", "4,0", "1,0", "line", "7"),
                      {number("a", "2", "1", "coefficient a (the paper's alpha)", -100.0, false, 100.0),
                       number("b", "0", "1", "coefficient b (the paper's beta)", -100.0, false, 100.0)}),
       .metrics = disk_metrics({abs_("cM_end_error", "m", 1e-8, 1e-2, "c_M at T against (43) (runs without contact)")}),
       .run_disks = run_linear,
       .headline = {.metrics = {"contact_path_error"}, .label = "after-contact path", .unit = "mm", .scale = 1e3}},
      {.name = "disks.forced",
       .vehicle = Vehicle::kDisks,
       .summary = "Forced collision: N drives straight at the centre of D and contact follows when it enters D, "
                  "whatever linear mechanism (a, b) != (1, 0) M uses.",
       .equations = "Corollary 6.3, Lemma 6.1, (46)",
       // 8 s: contact at t = 4.08 s, M pushed along N's side until N stops at 5.96 s, then 2 s at
       // rest in contact. The 14 s it ran before held them 8 s at rest, where the contact's depth
       // bookkeeping may drift (Rapier's at 16 iterations with M free to turn: 3.0e-6 m after 5.9 s
       // of contact, 2.5e-5 m after 9.9 s, against 1e-5); with M's spin held, as every engine holds
       // it (a conformance test checks it), it did not, and every verdict and error but the
       // contact's duration (to T) is the same at 8 s. A slow drift at rest gets a quarter of the
       // time to show.
       .params = with(disk_params("0,0", "6,-2", "1.5,0", "line", "8", false),
                      {number("a", "0.5", "1", "coefficient a", -100.0, false, 100.0),
                       number("b", "0.5", "1", "coefficient b", -100.0, false, 100.0)}),
       .metrics = disk_metrics({{"contact_on_D",
                                 "m",
                                 TolKind::kAbsolute,
                                 {{TolRole::kReference, 1e-6}, {TolRole::kDefault, 1.0}},
                                 "|c_N - c^0| at contact against the radius of D (tolerance in steps of N's travel)"}}),
       .run_disks = run_forced,
       .headline = {.metrics = {"contact_path_error"}, .label = "after-contact path", .unit = "mm", .scale = 1e3}},
      {.name = "disks.moving-away",
       .vehicle = Vehicle::kDisks,
       .summary = "The linear mechanism a = 2 meets N at t = 1 s; adding the moving-away reaction form (31) "
                  "keeps the disks apart.",
       .equations = "(31), Corollary 4.5, Corollary 4.8",
       .params = with(disk_params("0,0", "3,0", "1,0", "line", "6"),
                      {number("a", "2", "1", "base mechanism (41): a", -100.0, false, 100.0),
                       number("b", "0", "1", "base mechanism (41): b", -100.0, false, 100.0),
                       number("k_away", "2", "1", "gain of the moving-away form", 0.0, false, 100.0)}),
       .metrics = disk_metrics({}),
       .run_disks = run_moving_away,
       .headline = {.metrics = {"step_displacement"}, .label = "step against command", .unit = "µm", .scale = 1e6}}};
}

}  // namespace liftcheck
