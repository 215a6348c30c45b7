#include "models/disk_contact.hpp"

#include <array>
#include <boost/math/tools/roots.hpp>
#include <boost/numeric/odeint.hpp>
#include <cmath>
#include <functional>
#include <numbers>
#include <string>

namespace liftcheck::disks {

Vec2 contact_velocity(const Vec2& v_cmd, const Vec2& vN, const Vec2& n) {
  return v_cmd - std::min(0.0, n.dot(v_cmd - vN)) * n;
}

namespace {

using State = std::array<double, 2>;

/// One phase of the motion: free (x = c_M) or in contact (x[0] = theta, the angle of c_M - c_N).
struct Phase {
  std::function<void(const State&, State&, double)> rhs;
  /// The phase ends where this goes from >= 0 (free: > 0) to < 0.
  std::function<double(double, const State&)> event;
  std::function<Vec2(double, const State&)> cM;
  bool armed_at_zero = false;  ///< a start value of exactly 0 arms the event (contact), or not (free)
  /// Optional: the first time the event's value is <= 0 (at rest against N) is booked here.
  std::optional<double>* first_nonpositive = nullptr;
};

/// Books the trace at t0, at every multiple of the sample spacing after it, and at T.
struct Sampler {
  const NPath& path;
  double dt, T;
  long next;
  std::vector<Sample>& out;
  void upto(double hi, const std::function<Vec2(double)>& cM) {
    for (; next * dt <= hi + 1e-12 && next * dt < T - 1e-12; ++next)
      out.push_back({next * dt, cM(next * dt), path.position(next * dt)});
  }
};

/// Integrates one phase from (t0, x0) with a fresh dense-output stepper until its event or T;
/// returns the end time and state.
template <class Stepper>
std::pair<double, State> run_phase(Stepper st, const Phase& ph, double t0, const State& x0, double T, Sampler& smp,
                                   long& steps, long max_steps) {
  st.initialize(x0, t0, std::min(1e-3, (T - t0) / 16.0));
  const auto value = [&](double t) {
    State x;
    st.calc_state(t, x);
    return ph.event(t, x);
  };
  const auto cM_at = [&](double t) {
    State x;
    st.calc_state(t, x);
    return ph.cM(t, x);
  };
  double e0 = ph.event(t0, x0);
  bool armed = e0 > 0.0 || (ph.armed_at_zero && e0 == 0.0);
  while (st.current_time() < T) {
    if (++steps > max_steps)
      throw LiftStalled("the lift (21) with contact stalled at t = " + std::to_string(st.current_time()) + " s");
    const auto [a, b] = st.do_step(ph.rhs);
    const double hi = std::min(b, T);
    constexpr int kProbe = 8;
    double ta = a, ea = value(a);
    for (int k = 1; k <= kProbe; ++k) {
      const double tb = a + (hi - a) * k / kProbe, eb = value(tb);
      if (ph.first_nonpositive && !*ph.first_nonpositive && eb <= 0.0) {  // bisection: the value may jump to 0
        double lo = ta, up = tb;
        for (int i = 0; i < 60 && up - lo > 1e-15 * std::max(1.0, std::abs(up)); ++i) {
          const double mid = 0.5 * (lo + up);
          (value(mid) <= 0.0 ? up : lo) = mid;
        }
        *ph.first_nonpositive = ea <= 0.0 ? ta : up;
      }
      if (armed && eb < 0.0) {
        double root = tb;
        if (ea > 0.0) {
          boost::uintmax_t iters = 100;
          const auto [lo, up] = boost::math::tools::toms748_solve(value, ta, tb, ea, eb,
                                                                  boost::math::tools::eps_tolerance<double>(52), iters);
          root = up;  // the first point at or past the crossing
        } else if (ea == 0.0) {
          root = ta;
        }
        smp.upto(root, cM_at);
        State x;
        st.calc_state(root, x);
        return {root, x};
      }
      if (eb > 0.0) armed = true;
      ta = tb;
      ea = eb;
    }
    smp.upto(hi, cM_at);
  }
  State x;
  st.calc_state(T, x);
  return {T, x};
}

template <class Stepper>
ResponseResult respond_with(const std::function<Stepper()>& make, const Rule& rule, const NPath& path, const Vec2& cM0,
                            double t0, double T, const LiftDef& def) {
  ResponseResult r;
  Sampler smp{path, def.sample_dt_s, T, static_cast<long>(std::floor(t0 / def.sample_dt_s + 1e-9)) + 1, r.trace};
  r.trace.push_back({t0, cM0, path.position(t0)});
  const Phase free{
      [&](const State& x, State& dx, double t) {
        const Vec2 v = rule(t, Vec2(x[0], x[1]), path.position(t), path.velocity(t));
        dx = {v.x(), v.y()};
      },
      [&](double t, const State& x) { return (Vec2(x[0], x[1]) - path.position(t)).norm() - kContactDistance; },
      [](double, const State& x) { return Vec2(x[0], x[1]); }, false};
  const auto on_circle = [&](double t, double theta) {
    return Vec2(path.position(t) + kContactDistance * Vec2(std::cos(theta), std::sin(theta)));
  };
  const auto pushing = [&](double t, double theta) {  // n.(v_cmd - v_N) <= 0: the command presses M into N
    const Vec2 n(std::cos(theta), std::sin(theta)), vN = path.velocity(t);
    return -n.dot(rule(t, on_circle(t, theta), path.position(t), vN) - vN);
  };
  Phase contact{[&](const State& x, State& dx, double t) {
                  const Vec2 n(std::cos(x[0]), std::sin(x[0])), vN = path.velocity(t);
                  const Vec2 v = rule(t, on_circle(t, x[0]), path.position(t), vN);
                  dx = {perp(n).dot(v - vN) / kContactDistance, 0.0};
                },
                [&](double t, const State& x) { return pushing(t, x[0]); },
                [&](double t, const State& x) { return on_circle(t, x[0]); }, true};
  double t = t0;
  Vec2 cM = cM0;
  bool touching = (cM0 - path.position(t0)).norm() <= kContactDistance;
  long steps = 0;
  while (t < T) {
    if (++steps > def.max_steps)
      throw LiftStalled("the lift (21) with contact stalled at t = " + std::to_string(t) + " s");
    if (!touching) {
      const auto [t1, x] = run_phase(make(), free, t, State{cM.x(), cM.y()}, T, smp, steps, def.max_steps);
      t = t1;
      cM = Vec2(x[0], x[1]);
      if (t < T) {
        touching = true;
        if (!r.t_contact_s) r.t_contact_s = t, r.cM_contact = cM;
      }
      continue;
    }
    const Vec2 rel = cM - path.position(t);
    const double theta = std::atan2(rel.y(), rel.x());
    if (!r.t_contact_s) r.t_contact_s = t, r.cM_contact = on_circle(t, theta);
    double t1 = t;
    State x{theta, 0.0};
    std::optional<double> press_end;
    contact.first_nonpositive = &press_end;
    const double press0 = pushing(t, theta);
    if (press0 <= 0.0) press_end = t;
    if (press0 >= 0.0) std::tie(t1, x) = run_phase(make(), contact, t, x, T, smp, steps, def.max_steps);
    if (!press_end && t1 < T) press_end = t1;
    if (!r.t_release_s && !r.t_press_end_s) r.t_press_end_s = press_end;  // the first contact's
    r.contact_s += t1 - t;
    if (t1 < T && !r.t_release_s) r.t_release_s = t1;
    t = t1;
    cM = on_circle(t, x[0]);
    touching = false;
    if (t >= T) break;
  }
  r.trace.push_back({T, cM, path.position(T)});
  return r;
}

}  // namespace

ResponseResult lift_with_response(const Rule& rule, const NPath& path, const Vec2& cM0, double t0_s, double T_s,
                                  const LiftDef& def) {
  namespace odeint = boost::numeric::odeint;
  if (def.method == LiftMethod::kBulirschStoer) {
    using S = odeint::bulirsch_stoer_dense_out<State>;
    return respond_with<S>([&] { return S(def.abs_tol, def.rel_tol, 1.0, 1.0, def.max_step_s); }, rule, path, cM0, t0_s,
                           T_s, def);
  }
  const auto make = [&] {
    return odeint::make_dense_output(def.abs_tol, def.rel_tol, def.max_step_s, odeint::runge_kutta_dopri5<State>());
  };
  return respond_with<decltype(make())>(make, rule, path, cM0, t0_s, T_s, def);
}

Vec2 ConstantRelativeContact::relative_at(double s) const {
  const double psi = std::atan2(u.y(), u.x());
  const double phi0 = std::remainder(psi - theta0_rad, 2.0 * std::numbers::pi);
  double phi = phi0;
  if (std::abs(phi0) < std::numbers::pi && std::cos(phi0) < 0.0)
    phi = 2.0 * std::atan(std::tan(0.5 * phi0) * std::exp(-0.5 * u.norm() * s));
  const double theta = psi - phi;
  return kContactDistance * Vec2(std::cos(theta), std::sin(theta));
}

std::optional<double> ConstantRelativeContact::release_after_s() const {
  const double phi0 = std::remainder(std::atan2(u.y(), u.x()) - theta0_rad, 2.0 * std::numbers::pi);
  if (std::cos(phi0) >= 0.0) return 0.0;
  if (std::abs(phi0) >= std::numbers::pi) return std::nullopt;
  return 2.0 / u.norm() * std::log(std::abs(std::tan(0.5 * phi0)));
}

}  // namespace liftcheck::disks
