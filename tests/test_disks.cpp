// The two-disk model (Farber, Kurz, Pillin): every closed form against the integrated lift (21).
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "models/disks.hpp"

using namespace liftcheck::disks;

namespace {

Mechanism make(MechanismKind k, double lambda = 0, double omega = 0, double a = 1, double b = 0) {
  Mechanism m;
  m.kind = k;
  m.lambda = lambda;
  m.omega = omega;
  m.a = a;
  m.b = b;
  return m;
}

NPath figure8(const Vec2& c0) {
  NPath p;
  p.kind = NPath::Kind::kFigure8;
  p.c0 = c0;
  p.radius_m = 2.5;
  p.omega_radps = 0.7;
  return p;
}

NPath line(const Vec2& c0, const Vec2& v) { return {.kind = NPath::Kind::kLine, .c0 = c0, .v = v}; }

}  // namespace

TEST(Actuation, IsOneUpToTwoZeroFromThreeAndSmooth) {
  EXPECT_EQ(actuation(0.0), 1.0);
  EXPECT_EQ(actuation(2.0), 1.0);
  EXPECT_EQ(actuation(3.0), 0.0);
  EXPECT_EQ(actuation(7.0), 0.0);
  double prev = 1.0;
  for (double r = 2.0; r <= 3.0; r += 0.001) {
    EXPECT_LE(actuation(r), prev + 1e-15);
    prev = actuation(r);
  }
  EXPECT_NEAR(actuation(2.5), 0.5, 1e-15);  // symmetric bump
  // One-sided derivatives vanish at the ends (C-infinity joins).
  EXPECT_NEAR((actuation(2.0 + 1e-3) - 1.0) / 1e-3, 0.0, 1e-6);
  EXPECT_NEAR(actuation(3.0 - 1e-3) / 1e-3, 0.0, 1e-6);
}

TEST(Disks, Lemma51DistanceAndDirectionUnderRepelForAnyPathOfN) {
  for (double lambda : {-0.5, 0.3}) {
    const Vec2 cM0(0.0, 0.0), cN0(5.0, 1.0);
    const auto r = lift(make(MechanismKind::kRepel, lambda), figure8(cN0), cM0, 4.0);
    const Vec2 dir0 = (cM0 - cN0).normalized();
    for (const auto& s : r.trace) {
      const Vec2 c = s.cM - s.cN;
      EXPECT_NEAR(c.norm(), repel_distance((cM0 - cN0).norm(), lambda, s.t_s), 1e-9 * c.norm()) << s.t_s;
      EXPECT_NEAR(c.normalized().dot(dir0), 1.0, 1e-12);
    }
  }
}

TEST(Disks, Lemma51TouchTime) {
  const auto r = lift(make(MechanismKind::kRepel, -0.5), line({5.0, 0.0}, {0.3, -0.2}), {0.0, 0.0}, 4.0);
  ASSERT_TRUE(r.t_contact_s.has_value());
  EXPECT_NEAR(*r.t_contact_s, std::log(0.4) / -0.5, 1e-9);
  EXPECT_NEAR(*repel_touch_time(5.0, -0.5), 1.8325814637483102, 1e-15);
  EXPECT_FALSE(repel_touch_time(5.0, 0.2).has_value());
}

TEST(Disks, RotationKeepsDistanceAndTurnsAtOmega40) {
  const double omega = 0.8;
  const Vec2 cM0(0.0, 0.0), cN0(3.0, 0.5);
  const auto r = lift(make(MechanismKind::kRotation, 0, omega), figure8(cN0), cM0, 5.0);
  const Vec2 c0 = cM0 - cN0;
  for (const auto& s : r.trace) {
    const Vec2 c = s.cM - s.cN;
    EXPECT_NEAR(c.norm(), c0.norm(), 1e-9);
    const double turned = std::atan2(c0.x() * c.y() - c0.y() * c.x(), c0.dot(c));
    const double expected = std::remainder(omega * s.t_s, 2.0 * std::numbers::pi);
    EXPECT_NEAR(std::remainder(turned - expected, 2.0 * std::numbers::pi), 0.0, 1e-9) << s.t_s;
  }
}

TEST(Disks, LinearMechanismClosedForm43To46) {
  for (const auto& [a, b] : std::vector<std::pair<double, double>>{{2.0, 0.0}, {0.5, 0.5}, {-1.0, 2.0}, {1.0, -0.7}}) {
    const Vec2 cM0(0.0, 0.0), cN0(4.0, 1.0);
    const NPath path = figure8(cN0);
    const auto r = lift(make(MechanismKind::kLinear, 0, 0, a, b), path, cM0, 6.0);
    const Vec2 chat = collision_centre(a, b, cM0, cN0);
    const Mat2 B = matrix_B(a, b);
    for (const auto& s : r.trace) {
      EXPECT_LT((s.cM - linear_cM(a, b, cM0, cN0, s.cN)).norm(), 1e-9) << a << "," << b << " t " << s.t_s;  // (43)
      EXPECT_LT(((s.cM - s.cN) - B * (s.cN - chat)).norm(), 1e-9);                                          // (45)
    }
    // (46) against its definition c0 = B c^0 with c0 = A c_N(0) - c_M(0).
    EXPECT_LT((B * chat - (matrix_A(a, b) * cN0 - cM0)).norm(), 1e-12);
  }
}

TEST(Disks, CollisionDomainLemma61AndRemark62AreExact) {
  // B is a similarity, so D = D' and "in collision iff c_N in D" holds with the printed radius.
  const Vec2 cM0(0.0, 0.0), cN0(4.0, 1.0);
  for (const auto& [a, b] : std::vector<std::pair<double, double>>{{2.0, 0.0}, {0.5, 0.5}, {-1.0, 2.0}, {3.0, 1.0}}) {
    const Mat2 B = matrix_B(a, b);
    EXPECT_NEAR(B.operatorNorm(), std::hypot(a - 1, b), 1e-12);
    EXPECT_NEAR(B.inverse().operatorNorm(), 1.0 / B.operatorNorm(), 1e-12);  // |B^-1| = |B|^-1: D = D'
    const Vec2 chat = collision_centre(a, b, cM0, cN0);
    const double rD = collision_radius(a, b);
    for (double ang = 0.0; ang < 6.28; ang += 0.1)
      for (double k : {0.5, 0.99, 1.01, 2.0}) {
        const Vec2 cN = chat + k * rD * Vec2(std::cos(ang), std::sin(ang));
        const double d = (linear_cM(a, b, cM0, cN0, cN) - cN).norm();
        EXPECT_EQ(in_collision_domain(a, b, cM0, cN0, cN), d < 2.0);
        EXPECT_NEAR(d, 2.0 * k, 1e-12);
      }
  }
}

TEST(Disks, ForcedCollisionCorollary63) {
  const Vec2 cM0(0.0, 0.0), cN0(6.0, -2.0);
  for (const auto& [a, b] : std::vector<std::pair<double, double>>{{0.5, 0.5}, {2.0, 0.0}, {-0.5, -1.0}}) {
    NPath p;
    p.kind = NPath::Kind::kToward;
    p.c0 = cN0;
    p.v = Vec2(1.5, 0.0);
    p.goal = collision_centre(a, b, cM0, cN0);
    const auto r = lift(make(MechanismKind::kLinear, 0, 0, a, b), p, cM0, 40.0);
    ASSERT_TRUE(r.t_contact_s.has_value()) << a << "," << b;
    EXPECT_NEAR(*r.t_contact_s, forced_contact_time(a, b, cM0, cN0, 1.5), 1e-8);
  }
}

TEST(Disks, Example64BothReachTheCentreTogether) {
  for (double a : {2.0, 0.5}) {
    const Vec2 cM0(0.0, 0.0), cN0(3.0, 0.0);
    const Vec2 chat = collision_centre(a, 0.0, cM0, cN0);
    EXPECT_LT((chat - (a * cN0 - cM0) / (a - 1.0)).norm(), 1e-12);          // (49)
    EXPECT_NEAR((chat - cM0).norm(), a * (chat - cN0).norm(), 1e-12);       // (50)
    EXPECT_NEAR(collision_radius(a, 0.0), 2.0 / std::abs(a - 1.0), 1e-15);  // |B^-1| = |a - 1|^-1
    NPath p;
    p.kind = NPath::Kind::kLine;
    p.c0 = cN0;
    p.v = (chat - cN0).normalized();
    const double t_arrive = (chat - cN0).norm();
    const auto r = lift(make(MechanismKind::kLinear, 0, 0, a, 0.0), p, cM0, t_arrive);
    EXPECT_LT((r.cM_end - chat).norm(), 1e-9) << a;
    EXPECT_LT((r.trace.back().cN - chat).norm(), 1e-12);
  }
}

TEST(Disks, Lemma47LinearMechanismsKeepATouchingPairTouching) {
  const Vec2 cN0(2.0, 0.0), cM0(0.0, 0.0);  // touching
  for (const auto kind : {MechanismKind::kCopy, MechanismKind::kActuated}) {
    const auto r = lift(make(kind), figure8(cN0), cM0, 5.0);
    for (const auto& s : r.trace) EXPECT_NEAR((s.cM - s.cN).norm(), 2.0, 1e-9);
    EXPECT_EQ(r.t_contact_s.value_or(-1.0), 0.0);  // touching from the start, and it stays so
  }
}

TEST(Disks, ClassifiesEhresmannConnections) {
  EXPECT_TRUE(satisfies_linearity(make(MechanismKind::kCopy)));
  EXPECT_TRUE(satisfies_linearity(make(MechanismKind::kActuated)));
  EXPECT_TRUE(satisfies_linearity(make(MechanismKind::kLinear, 0, 0, 0.5, -2.0)));
  EXPECT_FALSE(satisfies_linearity(make(MechanismKind::kRepel, 0.5)));
  EXPECT_FALSE(satisfies_linearity(make(MechanismKind::kRotation, 0, 1.0)));
  EXPECT_TRUE(satisfies_linearity(make(MechanismKind::kRepel, 0.0)));  // lambda = 0 is (36)
  Mechanism away = make(MechanismKind::kCopy);
  away.moving_away = true;
  EXPECT_FALSE(satisfies_linearity(away));  // positively homogeneous only (31)
}

TEST(Disks, Corollary48OnlyTheNonlinearFormPushesAwayAtTheBoundary) {
  const Vec2 cN(2.0, 0.0), cM(0.0, 0.0);
  const Vec2 n = (cM - cN).normalized();
  Mechanism away = make(MechanismKind::kLinear, 0, 0, 2.0, 0.0);
  away.moving_away = true;
  for (double ang = 0.0; ang < 6.28; ang += 0.05) {
    const Vec2 X(std::cos(ang), std::sin(ang));
    for (const auto kind : {MechanismKind::kCopy, MechanismKind::kActuated})
      EXPECT_NEAR((make(kind).velocity(cM, cN, X) - X).dot(n), 0.0, 1e-15);  // tangent to the boundary
    EXPECT_GT((away.velocity(cM, cN, X) - X).dot(n), 0.0);                   // strictly inwards
  }
}

TEST(Disks, MovingAwayAvoidsTheCollisionItsBaseMechanismMakes) {
  Mechanism base = make(MechanismKind::kLinear, 0, 0, 2.0, 0.0);
  const NPath p = line({3.0, 0.0}, {1.0, 0.0});
  const auto hit = lift(base, p, {0.0, 0.0}, 5.0);
  ASSERT_TRUE(hit.t_contact_s.has_value());
  EXPECT_NEAR(*hit.t_contact_s, 1.0, 1e-9);  // d = 3 - t
  base.moving_away = true;
  const auto safe = lift(base, p, {0.0, 0.0}, 5.0);
  EXPECT_FALSE(safe.t_contact_s.has_value());
  EXPECT_GT(safe.min_distance, 2.0);
}

TEST(Planner, AvoidsTheDiskAndJoinsTheEnds) {
  const Vec2 cN(0.0, 0.0), a(-5.0, 0.3), b(5.0, -0.2);
  EXPECT_LT((plan(a, b, cN, 2.2, 0.0) - a).norm(), 1e-12);
  EXPECT_LT((plan(a, b, cN, 2.2, 1.0) - b).norm(), 1e-12);
  double length = 0.0;
  Vec2 prev = a;
  for (double tau = 0.0; tau <= 1.0 + 1e-12; tau += 0.001) {
    const Vec2 q = plan(a, b, cN, 2.2, tau);
    EXPECT_GE((q - cN).norm(), 2.2 - 1e-9);
    length += (q - prev).norm();
    prev = q;
  }
  EXPECT_GT(length, (b - a).norm());
  EXPECT_LT(length, (b - a).norm() + 2.2 * std::numbers::pi);
  // Clear of the disk: the straight segment.
  EXPECT_LT((plan({-5, 3}, {5, 3}, cN, 2.2, 0.5) - Vec2(0, 3)).norm(), 1e-12);
}

TEST(Algorithms, Extended14EndsAtTheLiftOfTheTarget) {
  const NPath p = line({0.0, 0.0}, {0.6, 0.2});
  const Vec2 cM0(-4.0, 0.1), cM1(4.0, -0.3);
  const double T = 5.0;
  // The lifting function of the rotation mechanism (40), by integration of (21).
  const Mechanism rot = make(MechanismKind::kRotation, 0, 0.2);
  const Lifting L = [&](const Vec2& c, double t) { return t == 0.0 ? c : lift(rot, p, c, t).cM_end; };
  EXPECT_LT((extended(L, cM0, cM1, p, T, 0.0, 2.2) - cM0).norm(), 1e-12);
  EXPECT_LT((extended(L, cM0, cM1, p, T, T, 2.2) - L(cM1, T)).norm(), 1e-12);
  // With the copy lifting the relative motion is the plan itself: clear of N throughout.
  const Lifting copy = [&](const Vec2& c, double t) { return Vec2(c + p.position(t) - p.position(0.0)); };
  for (double t = 0.0; t <= T; t += 0.01)
    EXPECT_GE((extended(copy, cM0, cM1, p, T, t, 2.2) - p.position(t)).norm(), 2.2 - 1e-9);
}

TEST(Algorithms, Navigation17ReachesTheMovingTarget) {
  const NPath p = figure8({1.0, 0.0});
  const double T = 6.0;
  const Lifting copy = [&](const Vec2& c, double t) { return Vec2(c + p.position(t) - p.position(0.0)); };
  // The target circles N at radius 3 (its own mechanism, (40)).
  const auto target = [&](double t) { return Vec2(p.position(t) + 3.0 * Vec2(std::cos(0.4 * t), std::sin(0.4 * t))); };
  const Vec2 cM0(-4.0, 0.0);
  EXPECT_LT((navigate(copy, cM0, target, p, T, 0.0, 2.2) - cM0).norm(), 1e-12);
  EXPECT_LT((navigate(copy, cM0, target, p, T, T, 2.2) - target(T)).norm(), 1e-12);
}

TEST(Disks, ActuatedMechanismNeverLetsNThrough) {
  // While N is farther than 3, M is at rest and its velocity vanishes: the integrator must not step
  // over N's approach. With N passing at offset 0.5, d tends to 2 from above and never reaches it.
  Mechanism m = make(MechanismKind::kActuated);
  const auto r = lift(m, line({6.0, 0.5}, {-1.0, 0.0}), {0.0, 0.0}, 8.0);
  EXPECT_FALSE(r.t_contact_s.has_value());
  EXPECT_GT(r.min_distance, 2.0);
  EXPECT_LT(r.min_distance, 2.3);
  EXPECT_GT((r.cM_end - Vec2(0.0, 0.0)).norm(), 3.0);  // M was pushed along
}

TEST(Disks, FollowingRuleTracksAPrescribedMotion) {
  const auto q = [](double t) { return Vec2(std::sin(t), t * t); };
  const auto r = lift(rule_following(q, 2.0), line({10.0, 0.0}, {0.0, 0.0}), q(0.0), 2.0);
  EXPECT_LT((r.cM_end - q(2.0)).norm(), 1e-9);
}
