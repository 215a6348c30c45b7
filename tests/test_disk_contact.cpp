// The contact response (models/disk_contact.hpp) against independent computations: the closed
// form for a constant relative command, Lemma 5.1's rigid relative position, a projected Euler
// integration that converges to it, and the two odeint methods against each other.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "models/disk_contact.hpp"

using namespace liftcheck::disks;

namespace {

Mechanism linear(double a, double b) { return {.kind = MechanismKind::kLinear, .a = a, .b = b}; }

NPath line(const Vec2& c0, const Vec2& v) { return {.kind = NPath::Kind::kLine, .c0 = c0, .v = v}; }

LiftDef sampled(LiftMethod method, double dt = 0.01) {
  LiftDef d;
  d.method = method;
  d.sample_dt_s = dt;
  return d;
}

/// Projected forward Euler at step h: M moves with contact_velocity while |c_M - c_N| <= 2 and its
/// command presses into N, and is put back on the circle radially (the constraint). First order.
Vec2 projected_euler(const Rule& rule, const NPath& path, Vec2 cM, double T, double h) {
  const long n = std::lround(T / h);
  for (long k = 0; k < n; ++k) {
    const double t = k * h;
    const Vec2 cN = path.position(t), vN = path.velocity(t), v = rule(t, cM, cN, vN);
    const Vec2 rel = cM - cN;
    const bool touching = rel.norm() <= kContactDistance * (1.0 + 1e-12);
    cM += h * (touching ? contact_velocity(v, vN, rel.normalized()) : v);
    const Vec2 rel1 = cM - path.position(t + h);
    if (rel1.norm() < kContactDistance) cM = path.position(t + h) + kContactDistance * rel1.normalized();
  }
  return cM;
}

}  // namespace

TEST(DiskContact, VelocityRemovesOnlyThePushIntoN) {
  const Vec2 n(1.0, 0.0), vN(0.5, 0.2);
  EXPECT_EQ(contact_velocity(Vec2(-1.0, 3.0), vN, n), Vec2(0.5, 3.0));  // pressing: normal part relative to N gone
  EXPECT_EQ(contact_velocity(Vec2(2.0, 3.0), vN, n), Vec2(2.0, 3.0));   // pulling away: untouched
  const Vec2 v = contact_velocity(Vec2(-4.0, 1.0), Vec2(1.0, -1.0), Vec2(0.6, 0.8));
  EXPECT_NEAR(Vec2(0.6, 0.8).dot(v - Vec2(1.0, -1.0)), 0.0, 1e-15);
}

// Oblique: a = 2, b = 0, N on a line at vN = (1, 0): the relative command is u = vN, M's relative
// path (-4 + t, 1) meets the circle at t = 4 - sqrt(3), at 150 degrees; it slides over N and
// leaves at 90 degrees after (2/|u|) ln tan(75 deg), then goes straight on along the tangent.
TEST(DiskContact, ObliqueContactMatchesTheClosedForm) {
  const NPath path = line({4.0, 0.0}, {1.0, 0.0});
  const Vec2 cM0(0.0, 1.0), u(1.0, 0.0);
  const double tc = 4.0 - std::sqrt(3.0), theta0 = 5.0 * std::numbers::pi / 6.0;
  const ConstantRelativeContact closed{u, theta0};
  ASSERT_TRUE(closed.release_after_s().has_value());
  const double tr = tc + 2.0 * std::log(std::tan(75.0 * std::numbers::pi / 180.0));
  EXPECT_NEAR(tc + *closed.release_after_s(), tr, 1e-14);
  EXPECT_NEAR(closed.relative_at(*closed.release_after_s()).x(), 0.0, 1e-12);  // leaves at the top of N
  for (LiftMethod method : {LiftMethod::kDopri5, LiftMethod::kBulirschStoer}) {
    const ResponseResult r = lift_with_response(rule_of(linear(2.0, 0.0)), path, cM0, 0.0, 7.0, sampled(method));
    ASSERT_TRUE(r.t_contact_s && r.t_release_s);
    EXPECT_NEAR(*r.t_contact_s, tc, 1e-10);
    EXPECT_NEAR(*r.t_release_s, tr, 1e-8);
    ASSERT_TRUE(r.t_press_end_s);
    EXPECT_NEAR(*r.t_press_end_s, tr, 1e-8);
    EXPECT_NEAR(r.contact_s, tr - tc, 1e-8);
    int in_contact = 0;
    for (const Sample& s : r.trace) {
      const Vec2 rel = s.cM - s.cN;
      if (s.t_s < tc) {
        EXPECT_LT((rel - Vec2(-4.0 + s.t_s, 1.0)).norm(), 1e-10) << s.t_s;
      } else if (s.t_s <= tr) {
        ++in_contact;
        EXPECT_LT((rel - closed.relative_at(s.t_s - tc)).norm(), 1e-8) << s.t_s;
      } else {
        EXPECT_LT((rel - (Vec2(0.0, 2.0) + u * (s.t_s - tr))).norm(), 1e-8) << s.t_s;
      }
    }
    EXPECT_GT(in_contact, 200);
  }
}

// Head-on (the relative command along -n): M stays where it touched relative to N, pushing.
TEST(DiskContact, HeadOnContactNeverReleases) {
  const ConstantRelativeContact closed{Vec2(1.0, 0.0), std::numbers::pi};
  EXPECT_FALSE(closed.release_after_s().has_value());
  const ResponseResult r = lift_with_response(rule_of(linear(2.0, 0.0)), line({3.0, 0.0}, {1.0, 0.0}), Vec2::Zero(),
                                              0.0, 4.0, sampled(LiftMethod::kDopri5));
  ASSERT_TRUE(r.t_contact_s);
  EXPECT_NEAR(*r.t_contact_s, 1.0, 1e-10);
  EXPECT_FALSE(r.t_release_s);
  EXPECT_NEAR(r.contact_s, 3.0, 1e-10);
  for (const Sample& s : r.trace) {
    if (s.t_s > 1.0) {
      EXPECT_LT((s.cM - s.cN - Vec2(-2.0, 0.0)).norm(), 1e-12) << s.t_s;
    }
  }
}

// Corollary 6.3's forced contact: N drives at the centre of D and stops there; M's command is then
// zero, so it presses no more and rests against N (no release: it never points away).
TEST(DiskContact, ACommandAtRestStopsPressingButDoesNotRelease) {
  const Mechanism m = linear(0.5, 0.5);
  const Vec2 cM0(0.0, 0.0), cN0(6.0, -2.0);
  NPath path;
  path.kind = NPath::Kind::kToward;
  path.c0 = cN0;
  path.v = Vec2(1.5, 0.0);
  path.goal = collision_centre(0.5, 0.5, cM0, cN0);
  const double t_goal = (path.goal - cN0).norm() / 1.5;
  const ResponseResult r = lift_with_response(rule_of(m), path, cM0, 0.0, 10.0, sampled(LiftMethod::kBulirschStoer));
  ASSERT_TRUE(r.t_contact_s && r.t_press_end_s);
  EXPECT_NEAR(*r.t_contact_s, forced_contact_time(0.5, 0.5, cM0, cN0, 1.5), 1e-9);
  EXPECT_NEAR(*r.t_press_end_s, t_goal, 1e-9);
  EXPECT_FALSE(r.t_release_s);
  EXPECT_NEAR((r.trace.back().cM - r.trace.back().cN).norm(), 2.0, 1e-12);
}

// Lemma 5.1 after contact: under (38) with lambda < 0 the relative command lambda c is radial, so
// M is carried along with N at the contact's relative position, whatever N does.
TEST(DiskContact, AttractGluesMToNForAnyPathOfN) {
  Mechanism m;
  m.kind = MechanismKind::kRepel;
  m.lambda = -0.5;
  NPath path;
  path.kind = NPath::Kind::kFigure8;
  path.c0 = Vec2(5.0, 1.0);
  const ResponseResult r =
      lift_with_response(rule_of(m), path, Vec2::Zero(), 0.0, 6.0, sampled(LiftMethod::kBulirschStoer));
  ASSERT_TRUE(r.t_contact_s);
  EXPECT_FALSE(r.t_release_s);
  const Vec2 rel = r.cM_contact - path.position(*r.t_contact_s);
  EXPECT_NEAR(rel.norm(), 2.0, 1e-12);
  EXPECT_NEAR(rel.normalized().dot((Vec2::Zero() - path.c0).normalized()), 1.0, 1e-9);  // Lemma 5.1: constant direction
  for (const Sample& s : r.trace) {
    if (s.t_s > *r.t_contact_s) {
      EXPECT_LT((s.cM - s.cN - rel).norm(), 1e-8) << s.t_s;
    }
  }
}

// A nonlinear case with no closed form (N on a figure eight, M under (41) with a rotation part):
// the two methods agree, and a projected Euler integration converges to them at first order.
TEST(DiskContact, MethodsAgreeAndProjectedEulerConverges) {
  NPath path;
  path.kind = NPath::Kind::kFigure8;
  path.c0 = Vec2(4.0, 1.0);
  path.radius_m = 2.5;
  path.omega_radps = 0.7;
  const Rule rule = rule_of(linear(2.0, 0.5));  // meets N at t = 1.9 s
  const double T = 6.0;
  const ResponseResult a = lift_with_response(rule, path, Vec2::Zero(), 0.0, T, sampled(LiftMethod::kDopri5, 0.05));
  const ResponseResult b =
      lift_with_response(rule, path, Vec2::Zero(), 0.0, T, sampled(LiftMethod::kBulirschStoer, 0.05));
  ASSERT_TRUE(a.t_contact_s && b.t_contact_s);
  EXPECT_GT(a.contact_s, 0.1);
  ASSERT_EQ(a.trace.size(), b.trace.size());
  for (std::size_t i = 0; i < a.trace.size(); ++i)
    EXPECT_LT((a.trace[i].cM - b.trace[i].cM).norm(), 1e-8) << a.trace[i].t_s;
  const double e1 = (projected_euler(rule, path, Vec2::Zero(), T, 1e-4) - a.trace.back().cM).norm();
  const double e2 = (projected_euler(rule, path, Vec2::Zero(), T, 5e-5) - a.trace.back().cM).norm();
  EXPECT_LT(e1, 1e-2);
  EXPECT_NEAR(e1 / e2, 2.0, 0.3);  // first order
}

// Started from an engine's state one step deep in N (contact reported on it), the reference starts
// on the circle at that angle and samples on the absolute grid after t0.
TEST(DiskContact, StartsOnTheCircleFromAStateInsideIt) {
  const NPath path = line({4.0, 0.0}, {1.0, 0.0});
  const double t0 = 2.3;
  const Vec2 inside = path.position(t0) + 1.999 * Vec2(std::cos(2.6), std::sin(2.6));
  const ResponseResult r =
      lift_with_response(rule_of(linear(2.0, 0.0)), path, inside, t0, 5.0, sampled(LiftMethod::kDopri5));
  ASSERT_TRUE(r.t_contact_s && r.t_release_s);
  EXPECT_EQ(*r.t_contact_s, t0);
  const ConstantRelativeContact closed{Vec2(1.0, 0.0), 2.6};
  EXPECT_NEAR(*r.t_release_s, t0 + *closed.release_after_s(), 1e-8);
  EXPECT_NEAR(r.trace[1].t_s, 2.31, 1e-12);
  EXPECT_LT((r.trace[1].cM - r.trace[1].cN - closed.relative_at(0.01)).norm(), 1e-8);
}
