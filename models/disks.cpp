#include "models/disks.hpp"

#include <boost/math/tools/minima.hpp>
#include <boost/math/tools/roots.hpp>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <algorithm>
#include <numbers>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace liftcheck::disks {

namespace {
constexpr double kPi = std::numbers::pi;
double bump(double s) { return s > 0.0 ? std::exp(-1.0 / s) : 0.0; }
}  // namespace

double actuation(double r) {
  if (r <= 2.0) return 1.0;
  if (r >= 3.0) return 0.0;
  const double f = bump(3.0 - r), g = bump(r - 2.0);
  return f / (f + g);
}

Vec2 Mechanism::velocity(const Vec2& cM, const Vec2& cN, const Vec2& vN) const {
  const Vec2 c = cM - cN;
  Vec2 v;
  switch (kind) {
    case MechanismKind::kCopy:
      v = vN;
      break;  // (36)
    case MechanismKind::kActuated:
      v = actuation(c.norm()) * vN;
      break;  // (37)
    case MechanismKind::kRepel:
      v = vN + lambda * c;
      break;  // (38)
    case MechanismKind::kRotation:
      v = vN + omega * perp(c);
      break;  // (40)
    case MechanismKind::kLinear:
      v = a * vN + b * perp(vN);
      break;  // (41)
  }
  if (moving_away) {  // (31) with N(e) the unit vector from c_N to c_M, pointing into E
    const double d = c.norm();
    if (d > 0.0) v += actuation(d) * k_away * vN.norm() * c / d;
  }
  return v;
}

Vec2 NPath::position(double t) const {
  switch (kind) {
    case Kind::kLine:
      return c0 + v * t;
    case Kind::kCircle:
      return c0 + radius_m * Vec2(std::cos(omega_radps * t) - 1.0, std::sin(omega_radps * t));
    case Kind::kFigure8:
      return c0 + radius_m * Vec2(std::sin(omega_radps * t), 0.5 * std::sin(2.0 * omega_radps * t));
    case Kind::kToward: {
      const Vec2 d = goal - c0;
      const double L = d.norm();
      if (L == 0.0) return c0;
      return c0 + d / L * std::min(v.norm() * t, L);
    }
  }
  return c0;
}

Vec2 NPath::velocity(double t) const {
  switch (kind) {
    case Kind::kLine:
      return v;
    case Kind::kCircle:
      return radius_m * omega_radps * Vec2(-std::sin(omega_radps * t), std::cos(omega_radps * t));
    case Kind::kFigure8:
      return radius_m * omega_radps * Vec2(std::cos(omega_radps * t), std::cos(2.0 * omega_radps * t));
    case Kind::kToward: {
      const Vec2 d = goal - c0;
      const double L = d.norm();
      if (L == 0.0 || v.norm() * t >= L) return Vec2::Zero();
      return d / L * v.norm();
    }
  }
  return Vec2::Zero();
}

Rule rule_of(const Mechanism& m) {
  return [m](double, const Vec2& cM, const Vec2& cN, const Vec2& vN) { return m.velocity(cM, cN, vN); };
}

Rule rule_following(std::function<Vec2(double)> q, double T, double gain_per_s) {
  return [q = std::move(q), T, gain_per_s](double t, const Vec2& cM, const Vec2&, const Vec2&) {
    constexpr double h = 1e-6;
    const double lo = std::clamp(t - h, 0.0, T - 2.0 * h), hi = lo + 2.0 * h;
    return Vec2((q(hi) - q(lo)) / (2.0 * h) + gain_per_s * (q(std::clamp(t, 0.0, T)) - cM));
  };
}

namespace {

/// The lift (21) on any Odeint dense-output stepper `stepper` (already holding the tolerances).
template <class Stepper>
LiftResult lift_with(Stepper stepper, const Rule& rule, const NPath& path, const Vec2& cM0, double T_s,
                     const LiftDef& def) {
  namespace odeint = boost::numeric::odeint;
  using State = std::array<double, 2>;
  const auto rhs = [&](const State& x, State& dx, double t) {
    const Vec2 v = rule(t, Vec2(x[0], x[1]), path.position(t), path.velocity(t));
    dx[0] = v.x();
    dx[1] = v.y();
  };
  stepper.initialize(State{cM0.x(), cM0.y()}, 0.0, std::min(1e-3, T_s / 16.0));

  LiftResult r;
  const auto dist_at = [&](double t) {
    State x;
    stepper.calc_state(t, x);
    return (Vec2(x[0], x[1]) - path.position(t)).norm();
  };
  const auto sample = [&](double t) {
    State x;
    stepper.calc_state(t, x);
    r.trace.push_back({t, Vec2(x[0], x[1]), path.position(t)});
  };
  r.min_distance = (cM0 - path.position(0.0)).norm();
  if (r.min_distance <= kContactDistance)
    r.t_contact_s = 0.0, r.cM_contact = cM0;  // touching (or overlapping) from the start
  r.trace.push_back({0.0, cM0, path.position(0.0)});
  long next_sample = 1, steps = 0;
  while (stepper.current_time() < T_s) {
    if (++steps > def.max_steps)
      throw LiftStalled("the lift (21) stalled at t = " + std::to_string(stepper.current_time()) +
                        " s: M's rule is discontinuous in time there");
    const auto [t0, t1] = stepper.do_step(rhs);
    const double hi = std::min(t1, T_s);
    // Probe the step: bracket the first crossing of d = 2 and the lowest point of d.
    constexpr int kProbe = 8;
    double probes[kProbe + 1];
    for (int k = 0; k <= kProbe; ++k) probes[k] = dist_at(t0 + (hi - t0) * k / kProbe);
    for (int k = 1; k <= kProbe; ++k) {
      const double ta = t0 + (hi - t0) * (k - 1) / kProbe, tb = t0 + (hi - t0) * k / kProbe;
      const double da = probes[k - 1], db = probes[k];
      if (!r.t_contact_s && da > kContactDistance && db <= kContactDistance) {
        boost::uintmax_t iters = 100;
        const auto f = [&](double t) { return dist_at(t) - kContactDistance; };
        const auto [lo, up] = boost::math::tools::toms748_solve(f, ta, tb, da - kContactDistance, db - kContactDistance,
                                                                boost::math::tools::eps_tolerance<double>(52), iters);
        r.t_contact_s = 0.5 * (lo + up);
        State x;
        stepper.calc_state(*r.t_contact_s, x);
        r.cM_contact = Vec2(x[0], x[1]);
      }
    }
    // The step's minimum: Brent's method on the dense output around the lowest probe.
    const int kmin = static_cast<int>(std::min_element(probes, probes + kProbe + 1) - probes);
    const double a = t0 + (hi - t0) * std::max(kmin - 1, 0) / kProbe,
                 b = t0 + (hi - t0) * std::min(kmin + 1, kProbe) / kProbe;
    boost::uintmax_t iters = 200;
    const auto m = boost::math::tools::brent_find_minima(dist_at, a, b, 52, iters);
    r.min_distance = std::min({r.min_distance, probes[kmin], m.second});
    for (; next_sample * def.sample_dt_s <= hi + 1e-12; ++next_sample)
      sample(std::min(next_sample * def.sample_dt_s, T_s));
  }
  if (r.trace.back().t_s < T_s) sample(T_s);
  r.cM_end = r.trace.back().cM;
  r.final_distance = (r.cM_end - r.trace.back().cN).norm();
  return r;
}

}  // namespace

LiftResult lift(const Rule& rule, const NPath& path, const Vec2& cM0, double T_s, const LiftDef& def) {
  namespace odeint = boost::numeric::odeint;
  using State = std::array<double, 2>;
  if (def.method == LiftMethod::kBulirschStoer)
    return lift_with(odeint::bulirsch_stoer_dense_out<State>(def.abs_tol, def.rel_tol, 1.0, 1.0, def.max_step_s), rule,
                     path, cM0, T_s, def);
  return lift_with(
      odeint::make_dense_output(def.abs_tol, def.rel_tol, def.max_step_s, odeint::runge_kutta_dopri5<State>()), rule,
      path, cM0, T_s, def);
}

bool satisfies_linearity(const Mechanism& m, int trials) {
  std::uint64_t state = 0x9E3779B97F4A7C15ull;
  const auto uniform = [&] {  // splitmix64: deterministic, no global state
    state += 0x9E3779B97F4A7C15ull;
    std::uint64_t z = state;
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * 0x1.0p-53 * 8.0 - 4.0;  // [-4, 4)
  };
  for (int i = 0; i < trials; ++i) {
    const Vec2 cN(uniform(), uniform());
    const Vec2 cM = cN + Vec2(uniform(), uniform());
    const Vec2 X1(uniform(), uniform()), X2(uniform(), uniform());
    const double k = uniform();
    const Vec2 sum = m.velocity(cM, cN, X1 + X2), parts = m.velocity(cM, cN, X1) + m.velocity(cM, cN, X2);
    const Vec2 scaled = m.velocity(cM, cN, k * X1), times = k * m.velocity(cM, cN, X1);
    const double scale = 1.0 + parts.norm() + times.norm();
    if ((sum - parts).norm() > 1e-12 * scale || (scaled - times).norm() > 1e-12 * scale) return false;
  }
  return true;
}

double repel_distance(double d0, double lambda, double t) { return std::exp(lambda * t) * d0; }

std::optional<double> repel_touch_time(double d0, double lambda) {
  if (!(lambda < 0.0) || !(d0 > kContactDistance)) return std::nullopt;
  return std::log(kContactDistance / d0) / lambda;
}

Mat2 matrix_A(double a, double b) {
  Mat2 A;
  A << a, -b, b, a;  // a I + b J, J = [[0, -1], [1, 0]]
  return A;
}

Mat2 matrix_B(double a, double b) { return matrix_A(a, b) - Mat2::Identity(); }

Vec2 linear_cM(double a, double b, const Vec2& cM0, const Vec2& cN0, const Vec2& cN_t) {
  const Mat2 A = matrix_A(a, b);
  const Vec2 c0 = A * cN0 - cM0;
  return A * cN_t - c0;
}

Vec2 collision_centre(double a, double b, const Vec2& cM0, const Vec2& cN0) {
  const Mat2 B = matrix_B(a, b);
  if (std::abs(B.determinant()) < 1e-300)
    throw std::invalid_argument("(a, b) = (1, 0): B is singular, no collision domain");
  const Mat2 Binv = B.inverse();
  return (Mat2::Identity() + Binv) * cN0 - Binv * cM0;
}

double collision_radius(double a, double b) {
  const double normB = std::hypot(a - 1.0, b);  // B = (a-1) I + b J is a similarity
  return kContactDistance / normB;
}

bool in_collision_domain(double a, double b, const Vec2& cM0, const Vec2& cN0, const Vec2& cN_t) {
  return (cN_t - collision_centre(a, b, cM0, cN0)).norm() < collision_radius(a, b);
}

double forced_contact_time(double a, double b, const Vec2& cM0, const Vec2& cN0, double speed) {
  const double gap = (collision_centre(a, b, cM0, cN0) - cN0).norm() - collision_radius(a, b);
  return std::max(0.0, gap / speed);
}

Vec2 plan(const Vec2& a, const Vec2& b, const Vec2& cN, double clearance, double tau) {
  tau = std::clamp(tau, 0.0, 1.0);
  const Vec2 ab = b - a;
  const double L2 = ab.squaredNorm();
  // Closest point of the segment to c_N.
  const double s = L2 > 0.0 ? std::clamp((cN - a).dot(ab) / L2, 0.0, 1.0) : 0.0;
  const double da = (a - cN).norm(), db = (b - cN).norm();
  if ((a + s * ab - cN).norm() >= clearance || da < clearance || db < clearance) return a + tau * ab;
  // Tangent - arc - tangent, the shorter way round.
  const double pa = std::atan2(a.y() - cN.y(), a.x() - cN.x()), pb = std::atan2(b.y() - cN.y(), b.x() - cN.x());
  const double ta = std::acos(clearance / da), tb = std::acos(clearance / db);
  const auto wrap2pi = [](double x) {
    x = std::fmod(x, 2.0 * kPi);
    return x < 0 ? x + 2.0 * kPi : x;
  };
  const double arc_ccw = wrap2pi((pb - tb) - (pa + ta)), arc_cw = wrap2pi((pa - ta) - (pb + tb));
  const bool ccw = arc_ccw <= arc_cw;
  const double la = std::sqrt(da * da - clearance * clearance), lb = std::sqrt(db * db - clearance * clearance);
  const double arc = ccw ? arc_ccw : arc_cw;
  const double total = la + clearance * arc + lb;
  const double start_angle = ccw ? pa + ta : pa - ta, end_angle = ccw ? pb - tb : pb + tb;
  const Vec2 Ta = cN + clearance * Vec2(std::cos(start_angle), std::sin(start_angle));
  const Vec2 Tb = cN + clearance * Vec2(std::cos(end_angle), std::sin(end_angle));
  const double u = tau * total;
  if (u <= la) return a + (Ta - a) * (u / la);
  if (u <= la + clearance * arc) {
    const double ang = start_angle + (ccw ? 1.0 : -1.0) * (u - la) / clearance;
    return cN + clearance * Vec2(std::cos(ang), std::sin(ang));
  }
  return Tb + (b - Tb) * ((u - la - clearance * arc) / lb);
}

Vec2 extended(const Lifting& L, const Vec2& cM0, const Vec2& cM1, const NPath& path, double T, double t,
              double clearance) {
  // (14): s~(gamma, e, e')(t) = L(s(e, e')(t), gamma)(t), the plan made over c_N(0).
  return L(plan(cM0, cM1, path.position(0.0), clearance, t / T), t);
}

Vec2 navigate(const Lifting& L, const Vec2& cM0, const std::function<Vec2(double)>& target, const NPath& path, double T,
              double t, double clearance) {
  // (17): s^(e, v)(t) = s(L(e, p o v)(t), v(t))(t), a plan over c_N(t) evaluated at parameter t.
  return plan(L(cM0, t), target(t), path.position(t), clearance, t / T);
}

}  // namespace liftcheck::disks
