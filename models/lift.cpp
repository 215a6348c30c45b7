#include "models/lift.hpp"

#include <array>
#include <boost/numeric/odeint.hpp>
#include <cmath>

namespace liftcheck::car {

namespace odeint = boost::numeric::odeint;

std::vector<TimedConfig> lift(const CarDef& car, const BasePath& path, const Config& q0, const LiftDef& def) {
  using State = std::array<double, 3>;  // x, y, phi
  const auto rhs = [&](const State& s, State& ds, double t) {
    const BaseSample b = path.at(t);
    const double heading = b.beta_rad + s[2];
    ds[0] = b.alpha_rate_radps * car.R_m * std::cos(heading);
    ds[1] = b.alpha_rate_radps * car.R_m * std::sin(heading);
    ds[2] = b.alpha_rate_radps * car.R_m / car.l_m * std::sin(b.beta_rad);
  };

  std::vector<TimedConfig> trace;
  State s{q0.x_m, q0.y_m, q0.phi_rad};
  const auto record = [&](const State& st, double t) {
    const BaseSample b = path.at(t);
    trace.push_back({t, Config{b.alpha_rad, b.beta_rad, st[0], st[1], st[2]}});
  };
  record(s, 0.0);
  for (std::size_t i = 0; i < path.size(); ++i) {
    const double t0 = path.segment_start_s(i), t1 = path.segment_end_s(i);
    if (t1 <= t0) continue;
    // Observation times in this segment: the sampling grid, then the segment end.
    std::vector<double> times{t0};
    if (def.sample_dt_s > 0.0) {
      for (double k = std::floor(t0 / def.sample_dt_s) + 1.0; k * def.sample_dt_s < t1; k += 1.0)
        if (k * def.sample_dt_s > t0) times.push_back(k * def.sample_dt_s);
    }
    times.push_back(t1);
    const double dt0 = std::min(1e-3, (t1 - t0) / 16.0);
    std::size_t obs = 0;
    const auto observe = [&](const State& st, double t) {
      if (obs++ > 0) record(st, t);  // the first observation repeats the previous end
    };
    if (def.method == LiftMethod::kBulirschStoer)
      odeint::integrate_times(odeint::bulirsch_stoer_dense_out<State>(def.abs_tol, def.rel_tol), rhs, s, times.begin(),
                              times.end(), dt0, observe);
    else
      odeint::integrate_times(odeint::make_dense_output(def.abs_tol, def.rel_tol, odeint::runge_kutta_dopri5<State>()),
                              rhs, s, times.begin(), times.end(), dt0, observe);
  }
  return trace;
}

Config lift_of_samples(const CarDef& car, const std::vector<TimedConfig>& samples) {
  if (samples.empty()) return {};
  Config q = samples.front().q;
  for (std::size_t i = 1; i < samples.size(); ++i) {
    const Config& b = samples[i].q;
    const double half = 0.5 * (b.beta_rad - q.beta_rad);
    q = flow_beta(q, half);
    q = flow_alpha(car, q, b.alpha_rad - q.alpha_rad);
    q = flow_beta(q, b.beta_rad - q.beta_rad);
  }
  return q;
}

Config lift_end(const CarDef& car, const BasePath& path, const Config& q0, const LiftDef& def) {
  LiftDef d = def;
  d.sample_dt_s = 0.0;
  return lift(car, path, q0, d).back().q;
}

}  // namespace liftcheck::car
