// Two disk vehicles on the plane (Farber, Kurz, Pillin, "Autonomous motion in changing
// environment, fibrations and reaction mechanisms", section 5-6). Unit disks with centres c_M (the
// ego vehicle) and c_N (the other); E = {(c_M, c_N) : |c_M - c_N| >= 2}, p(c_M, c_N) = c_N.
// An infinitesimal reaction mechanism gives M's velocity from the state and N's velocity (35).
#pragma once

#include <Eigen/Dense>
#include <functional>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace liftcheck::disks {

using Vec2 = Eigen::Vector2d;
using Mat2 = Eigen::Matrix2d;

constexpr double kContactDistance = 2.0;  ///< unit disks touch at |c_M - c_N| = 2 (32)

/// J: rotation by +90 degrees (the perp of (40), (41)).
inline Vec2 perp(const Vec2& v) { return {-v.y(), v.x()}; }

/// Actuation function psi of (37), Figure 6: smooth (C-infinity), 1 on [0, 2], 0 on [3, inf).
double actuation(double r);

enum class MechanismKind { kCopy, kActuated, kRepel, kRotation, kLinear };

/// A reaction mechanism (35): v_M = L(c_M, c_N, v_N), optionally plus the moving-away reaction
/// form (31) as in Corollary 4.5: l = psi(|c_M - c_N|) * k * |v_N| * (c_M - c_N)/|c_M - c_N|.
struct Mechanism {
  MechanismKind kind = MechanismKind::kCopy;
  double lambda = 0.0;  ///< (38)
  double omega = 0.0;   ///< (40), the paper's mu
  double a = 1.0;       ///< (41), the paper's alpha
  double b = 0.0;       ///< (41), the paper's beta
  bool moving_away = false;
  double k_away = 2.0;  ///< gain of the moving-away form (the paper's N has unit length: k = 1)

  Vec2 velocity(const Vec2& cM, const Vec2& cN, const Vec2& vN) const;
};

/// N's motion, c_N(t) with c_N(0) = c0.
struct NPath {
  enum class Kind { kLine, kCircle, kFigure8, kToward } kind = Kind::kLine;
  Vec2 c0 = Vec2::Zero();
  Vec2 v = Vec2(1.0, 0.0);   ///< line: velocity; toward: speed |v| towards `goal`
  double radius_m = 3.0;     ///< circle, figure eight
  double omega_radps = 0.5;  ///< circle, figure eight
  Vec2 goal = Vec2::Zero();  ///< toward: N drives in a straight line towards it and stops there

  Vec2 position(double t) const;
  Vec2 velocity(double t) const;
};

/// M's velocity rule: a reaction mechanism (time-independent) or a prescribed motion.
using Rule = std::function<Vec2(double t, const Vec2& cM, const Vec2& cN, const Vec2& vN)>;
Rule rule_of(const Mechanism& m);
/// M follows a prescribed trajectory q(t) on [0, T]: its velocity is q'(t) (central differences,
/// h = 1e-6 s; one-sided at the ends) plus gain (q(t) - c_M), which holds it on the trajectory.
Rule rule_following(std::function<Vec2(double)> q, double T, double gain_per_s = 20.0);

struct Sample {
  double t_s;
  Vec2 cM, cN;
};

/// Odeint steppers with dense output. Expected values in the scenarios are computed with one
/// method and the analytic engine runs the other, so the two are independent computations.
enum class LiftMethod { kDopri5, kBulirschStoer };

struct LiftDef {
  LiftMethod method = LiftMethod::kDopri5;
  double abs_tol = 1e-12, rel_tol = 1e-12;
  /// Largest step: where M's velocity vanishes (M at rest, N far away) the error estimate is zero
  /// and an unbounded step would jump over N's whole approach.
  double max_step_s = 0.01;
  double sample_dt_s = 0.02;
  long max_steps = 200000;  ///< LiftStalled past this (a smooth 10 s problem takes ~1000)
};

/// The lift needed more steps than LiftDef::max_steps: the rule is discontinuous in time (a
/// planner switching sides around N, say), and an error-controlled integrator would crawl.
struct LiftStalled : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct LiftResult {
  std::optional<double> t_contact_s;  ///< first time |c_M - c_N| <= 2 (root found; 0 if touching at the start)
  /// Smallest |c_M - c_N| on [0, T]: each step's minimum of the dense output located by Brent's
  /// method (not a minimum over sample points).
  double min_distance = 0.0;
  double final_distance = 0.0;
  Vec2 cM_end;
  Vec2 cM_contact = Vec2::Constant(NAN);  ///< M at the first contact (when there is one)
  std::vector<Sample> trace;
};

/// Integrates the lift (21): c_M' = L(c_M, c_N(t), c_N'(t)) with Boost.Odeint (dense output,
/// def.method) over [0, T]; the first contact is the root of |c_M - c_N| - 2 on the dense output
/// (TOMS 748), bracketed step by step. The trace is sampled at i * sample_dt (and T).
LiftResult lift(const Rule& rule, const NPath& path, const Vec2& cM0, double T_s, const LiftDef& def = {});
inline LiftResult lift(const Mechanism& m, const NPath& path, const Vec2& cM0, double T_s, const LiftDef& def = {}) {
  return lift(rule_of(m), path, cM0, T_s, def);
}

/// Lemma 4.4: does the mechanism satisfy (25) and (26), i.e. come from an Ehresmann connection?
/// Checked at `trials` random states and velocities (fixed seed) to relative precision 1e-12.
bool satisfies_linearity(const Mechanism& m, int trials = 200);

// ---- Closed forms -------------------------------------------------------------------------

/// Lemma 5.1: d(t) = e^{lambda t} d(0) under (38).
double repel_distance(double d0, double lambda, double t);
/// Lemma 5.1: the time the disks touch (lambda < 0 and d0 > 2), ln(2/d0)/lambda.
std::optional<double> repel_touch_time(double d0, double lambda);

/// (42): A = a I + b J.
Mat2 matrix_A(double a, double b);
/// (44): B = A - I.
Mat2 matrix_B(double a, double b);
/// (43): c_M(t) = A c_N(t) - c0 with c0 = A c_N(0) - c_M(0).
Vec2 linear_cM(double a, double b, const Vec2& cM0, const Vec2& cN0, const Vec2& cN_t);
/// (46): the centre of D, c^0 = (I + B^-1) c_N(0) - B^-1 c_M(0). Needs (a, b) != (1, 0).
Vec2 collision_centre(double a, double b, const Vec2& cM0, const Vec2& cN0);
/// Lemma 6.1 / Remark 6.2: radius of D = 2 |B|^-1 (B is a similarity, so D = D' = D-tilde).
double collision_radius(double a, double b);
/// Remark 6.2: M and N are in collision (|c_M - c_N| < 2) iff c_N in the open disk D.
bool in_collision_domain(double a, double b, const Vec2& cM0, const Vec2& cN0, const Vec2& cN_t);
/// Corollary 6.3 for a straight run of N towards c^0 at speed s: contact when it enters D,
/// t = (|c^0 - c_N(0)| - 2/|B|) / s (zero if it starts inside).
double forced_contact_time(double a, double b, const Vec2& cM0, const Vec2& cN0, double speed);

// ---- Motion planning in the fibre and the algorithms (14), (17) ----------------------------

/// A planner in the fibre R^2 minus the open disk of radius `clearance` about the (fixed) c_N:
/// the shortest path from a to b (straight, or tangent-arc-tangent around the disk), as a
/// function of tau in [0, 1] at constant speed.
Vec2 plan(const Vec2& a, const Vec2& b, const Vec2& cN, double clearance, double tau);

/// Lifting function L(e, gamma)(t) of (21) for a point e = (c_M, c_N(0)): M's position at t.
using Lifting = std::function<Vec2(const Vec2& cM0, double t)>;

/// (14): the extended algorithm, M's position at time t in [0, T] for start cM0, target cM1
/// (both in the fibre over c_N(0)) and the known motion of N.
Vec2 extended(const Lifting& L, const Vec2& cM0, const Vec2& cM1, const NPath& path, double T, double t,
              double clearance);

/// (17): navigation to a moving target v(t) (with p(v(t)) = c_N(t)): M's position at time t.
Vec2 navigate(const Lifting& L, const Vec2& cM0, const std::function<Vec2(double)>& target, const NPath& path, double T,
              double t, double clearance);

}  // namespace liftcheck::disks
