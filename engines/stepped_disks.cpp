#include "engines/stepped_disks.hpp"

#include <cmath>
#include <fmt/format.h>

namespace liftcheck {

using disks::Vec2;

DiskRun SteppedDisks::run(const DiskSetup& setup, const DiskProblem& pb) {
  const double dt = setup.dt_s;
  const long steps = static_cast<long>(std::ceil(pb.T_s / dt - 1e-9));
  const long sample_every = std::max(1L, std::lround(setup.sample_dt_s / dt));
  place(setup, pb.cM0, pb.path.position(0.0));

  DiskRun r;
  Vec2 cM = read_M(), cN = read_N();
  r.min_distance = (cM - cN).norm();
  if (in_contact()) r.t_contact_s = 0.0;
  r.trace.push_back({0.0, cM, cN});
  const auto f = [&](double t, const Vec2& x) { return pb.rule(t, x, pb.path.position(t), pb.path.velocity(t)); };
  for (long k = 0; k < steps; ++k) {
    const double t = k * dt, h = std::min(dt, pb.T_s - t);
    const Vec2 k1 = f(t, cM), k2 = f(t + 0.5 * h, cM + 0.5 * h * k1), k3 = f(t + 0.5 * h, cM + 0.5 * h * k2),
               k4 = f(t + h, cM + h * k3);
    move(cM + h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4), pb.path.position(t + h), h);
    cM = read_M();
    cN = read_N();
    if (!cM.allFinite() || !cN.allFinite()) throw EngineError(fmt::format("disk state is not finite at t = {:.4f} s", t + h));
    r.min_distance = std::min(r.min_distance, (cM - cN).norm());
    if (!r.t_contact_s && in_contact()) r.t_contact_s = t + h;
    if ((k + 1) % sample_every == 0 || k + 1 == steps) r.trace.push_back({t + h, cM, cN});
  }
  return r;
}

}  // namespace liftcheck
