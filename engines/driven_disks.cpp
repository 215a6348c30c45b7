#include "engines/driven_disks.hpp"

#include "models/disk_contact.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace liftcheck {

using disks::Vec2;

DiskRun DrivenDisks::run(const DiskSetup& setup, const DiskProblem& pb) {
  const double dt = setup.dt_s, touch = 2.0 * setup.radius_m;
  const long steps = static_cast<long>(std::ceil(pb.T_s / dt - 1e-9));
  const long sample_every = std::max(1L, std::lround(setup.sample_dt_s / dt));
  build(setup, pb.cM0, pb.path.position(0.0));

  DiskRun r;
  DiskContactLog log;
  State s = read();
  double fastest_commanded_mps = 0.0, separation_m = kSeparation_m;
  r.min_distance = (s.cM - s.cN).norm();
  r.trace.push_back({0.0, s.cM, s.cN});
  for (long k = 0; k < steps; ++k) {
    const double t = k * dt, h = std::min(dt, pb.T_s - t);
    const Vec2 vN = pb.path.velocity(t);
    const double d = (s.cM - s.cN).norm();
    const Vec2 vM_cmd = pb.rule(t, s.cM, s.cN, vN);
    const StepContacts c = step(vM_cmd, pb.path.position(t + h), vN, h);
    fastest_commanded_mps = std::max({fastest_commanded_mps, vM_cmd.norm(), vN.norm()});
    stepped_s_ += h;
    // The collision pass ran on the state at t, whose distance is d.
    // Contact is what the engine's collision pass reports as touching: a speculative contact it
    // generated ahead of touching (an outside engine reports its signed distance) is not one yet.
    const bool touching = c.count > 0 && !(c.distance_min_m > touching_distance_m());
    const bool first = touching && !r.t_contact_s;
    if (touching) {
      if (first) {
        r.t_contact_s = t;
        r.contact_state = disks::Sample{t, s.cM, s.cN};
        separation_m = std::max(kSeparation_m, disks::kSeparationSteps * (vM_cmd - vN).norm() * dt);
        log.distance_at_first_m = d;
      }
      ++log.steps_in_contact;
      log.depth_reported_max_m = std::max(log.depth_reported_max_m, c.depth_max_m);
      log.gap_reported_max_m = std::max(log.gap_reported_max_m, d - touch);
      log.depth_error_max_m = std::max(log.depth_error_max_m, std::abs(c.depth_max_m - std::max(0.0, touch - d)));
    } else {
      log.overlap_unreported_m = std::max(log.overlap_unreported_m, touch - d);
    }
    const Vec2 cM_before = s.cM;
    s = read();
    if (!s.cM.allFinite() || !s.cN.allFinite())
      throw EngineError(fmt::format("disk state is not finite at t = {:.4f} s", t + h));
    // M faster than ten times the fastest commanded speed (or 50 m/s) has blown up; a last step
    // much shorter than dt is left out (a contact's push-out over it is no speed).
    const double runaway_mps = std::max(kRunawaySpeed_mps, kRunawayFactor * fastest_commanded_mps);
    if (const double v = (s.cM - cM_before).norm() / h; h >= 0.5 * dt && !(v <= runaway_mps))
      throw EngineError(
          fmt::format("disk M speed {:.3g} m/s at t = {:.4f} s (a blow-up: above {:g} m/s)", v, t + h, runaway_mps));
    if (!s.wM_radps.allFinite())
      throw EngineError(fmt::format("disk M's angular velocity is not finite at t = {:.4f} s", t + h));
    if (const double w = s.wM_radps.norm(); w > log.spin_M_max_radps)
      log.spin_M_max_radps = w, log.spin_M_max_at_s = t + h;
    const double d1 = (s.cM - s.cN).norm();
    r.min_distance = std::min(r.min_distance, d1);
    // Free: the engine's actuation and integrator alone moved M. The step in which a contact the
    // collision pass made ahead of touching (a speculative one) stops M at the surface is the
    // contact's, not free motion; a speculative contact that slows M before that is counted.
    const bool stopped_at_touch = c.count > 0 && !(d1 - touch > touching_distance_m());
    if (!r.t_contact_s) {
      if (const double e = ((s.cM - cM_before) - vM_cmd * h).norm();
          !stopped_at_touch && e > log.step_displacement_error_max_m)
        log.step_displacement_error_max_m = e, log.step_displacement_error_at_s = t;
    } else if (!r.t_release_s && d1 - touch > separation_m) {
      r.t_release_s = t + h;
    }
    if (r.t_contact_s) log.penetration_max_m = std::max(log.penetration_max_m, touch - d1);
    if (first) log.overlap_growth_first_m = (touch - d1) - (touch - d);
    // N is moved by the engine along its known path: where the engine put it is checked too.
    log.n_path_error_max_m = std::max(log.n_path_error_max_m, (s.cN - pb.path.position(t + h)).norm());
    if ((k + 1) % sample_every == 0 || k + 1 == steps) r.trace.push_back({k + 1 == steps ? pb.T_s : t + h, s.cM, s.cN});
  }
  log.apart_at_end = r.t_contact_s && (r.trace.back().cM - r.trace.back().cN).norm() > touch;
  r.contact_log = log;
  return r;
}

}  // namespace liftcheck
