// What happens after contact (Farber, Kurz, Pillin, section 5: E = {|c_M - c_N| >= 2}, the
// admissibility condition (34) on the boundary). A velocity-commanded M that a reaction mechanism
// drives into N meets a frictionless, inelastic contact: the normal part of its command relative
// to N that points into N is removed, so M stays on |c_M - c_N| = 2 and moves with
//   v_M = v_cmd - min(0, n.(v_cmd - v_N)) n,   n = (c_M - c_N) / |c_M - c_N|,
// until the command points away from N again (n.(v_cmd - v_N) > 0). This completes the lift (21)
// past the first contact: the reference for an engine's contact response.
#pragma once

#include <optional>
#include <vector>

#include "models/disks.hpp"

namespace liftcheck::disks {

/// A stepping engine's contact has ended when the disks are apart by more than this many steps of
/// M's travel relative to N at the first contact (and at least kSeparation_m of engines/vehicle.hpp):
/// a tenth of a step, above the chord of a step on the circle, (|v_rel| dt)^2 / 4, which opens a gap
/// of 5 um at 4.4 m/s and 1 ms while the contact holds, and below a bounce's separation (a good part
/// of a step of closing travel).
constexpr double kSeparationSteps = 0.1;

/// M's velocity in contact: v_cmd less the part of v_cmd - v_N along -n (n from N to M, unit).
Vec2 contact_velocity(const Vec2& v_cmd, const Vec2& vN, const Vec2& n);

struct ResponseResult {
  std::optional<double>
      t_contact_s;  ///< first contact at or after t0 (t0 if M starts on or inside the circle, pushing)
  std::optional<double> t_release_s;  ///< end of that first contact; none if it lasts to T (or there is none)
  /// When the command stopped pressing M into N in that contact (n.(v_cmd - v_N) >= 0: at the
  /// release, or earlier where the command comes to rest against N); none if it presses to T.
  std::optional<double> t_press_end_s;
  Vec2 cM_contact = Vec2::Constant(NAN);  ///< M at the first contact
  /// At t0, at every whole multiple of def.sample_dt_s after t0, and at T.
  std::vector<Sample> trace;
  double contact_s = 0.0;  ///< total time in contact over [t0, T]
};

/// The lift (21) from (t0, cM0) to T with the contact response. Free phases integrate
/// c_M' = v_cmd; a phase ends at the first |c_M - c_N| = 2 (TOMS 748 on the dense output). A
/// contact phase keeps M on the circle by integrating the angle theta of c_M - c_N =
/// 2 (cos theta, sin theta): theta' = tangent . (v_cmd - v_N) / 2, and ends when
/// n.(v_cmd - v_N) > 0 (root found likewise). A start with |cM0 - c_N(t0)| <= 2 (an engine's state
/// on which it reported contact, up to a step deep) starts on the circle at its angle.
/// Throws LiftStalled past def.max_steps.
ResponseResult lift_with_response(const Rule& rule, const NPath& path, const Vec2& cM0, double t0_s, double T_s,
                                  const LiftDef& def = {});

/// Closed form in contact for a constant relative command u = v_cmd - v_N != 0 (the linear
/// mechanism (41) with N on a line: u = (A - I) v_N = B v_N, (44)). With theta the angle of
/// c_M - c_N and psi that of u, phi = psi - theta obeys phi' = -|u| sin(phi) / 2, so
/// tan(phi/2) = tan(phi0/2) exp(-|u| t / 2): M slides towards the side u points to and leaves N
/// when |phi| = pi/2, at t = (2/|u|) ln tan(|phi0|/2) after contact (never if phi0 = pi, head-on).
struct ConstantRelativeContact {
  Vec2 u;             ///< v_cmd - v_N
  double theta0_rad;  ///< angle of c_M - c_N at contact
  /// c_M - c_N at time s after contact, while in contact (s <= release_after_s()).
  Vec2 relative_at(double s) const;
  /// Time from contact to release; nullopt for a head-on contact (phi0 = pi) or if u points away
  /// at contact (then 0).
  std::optional<double> release_after_s() const;
};

}  // namespace liftcheck::disks
