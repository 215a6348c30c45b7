// The vehicles an engine offers, as the scenarios drive them: a car (CarEngine) and two disks
// (DiskEngine), with what a run gives them (CarSetup, DiskSetup, DiskProblem) and what they report
// (the trace, WheelSlip, DiskRun). The scenarios include this and nothing else of the engines.
#pragma once

#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include "models/car.hpp"
#include "models/disks.hpp"
#include "models/lift.hpp"
#include "models/path.hpp"

namespace liftcheck {

/// What one run may ask for: engine steps (a run's time) and recorded samples (its memory: each
/// is kept, the exact lift's too). dt and sample_dt are bounded below by the run's duration over
/// these, so that no parameter makes a step count overflow or a trace outgrow memory.
constexpr double kMaxRunSteps = 1e8;
constexpr double kMaxRunSamples = 1e6;

/// Everything needed to build and drive one car (the shared scenario parameters).
struct CarSetup {
  car::CarDef car;             ///< R, l
  car::DriveDef drive;         ///< speed, steering rate, ramps
  double dt_s = 1e-3;          ///< engine time step
  double sample_dt_s = 0.01;   ///< spacing of the reported trace
  double mu = 1.0;             ///< Coulomb friction coefficient, wheel against ground
  double gravity_mps2 = 9.81;  ///< magnitude of gravity
  /// Unit direction of gravity in the world frame: down -Z, or tilted (car.slope tilts gravity
  /// instead of the ground, which stays the plane z = 0). Every engine adapter applies it.
  Eigen::Vector3d gravity_dir_W = -Eigen::Vector3d::UnitZ();
  /// 3: the paper's tricycle (one steered, driven front wheel at the front-axle centre); 4: two
  /// steered, driven front wheels at +-track/2 (Ackermann angles, electronic differential;
  /// models/ackermann.hpp). The analytic reference is the same for both.
  int wheels = 3;
  double track_m = 0.8;  ///< distance between the rear wheels (and between the front wheels of a four-wheel car)
  /// Four wheels only: both front wheels at the virtual angle beta instead of their Ackermann
  /// angles (they fight and scrub: a negative control).
  bool parallel_steering = false;
  /// The car's masses (car_params in scenarios/car_scenarios.cpp gives the defaults and why).
  double chassis_mass_kg = 40.0;
  double wheel_mass_kg = 2.0;    ///< each wheel
  double knuckle_mass_kg = 2.0;  ///< each steering knuckle (between the chassis and a steered wheel)
  /// The rear wheels held against spinning by the engine's own joint motors (the braked slides;
  /// EngineInfo::brakes): with the front wheels' servos holding alpha, no wheel rolls.
  bool rear_brake = false;

  Eigen::Vector3d gravity_W() const { return gravity_mps2 * gravity_dir_W; }  ///< m/s^2
};

/// How much one wheel's contact point slid over a drive, measured every engine step from the
/// engine's own body state: v_contact = v_hub + omega x (contact point - hub), split along the
/// wheel's rolling direction and across it (along the axle), both horizontal.
struct WheelSlip {
  std::string wheel;            ///< "front", "rear left", ...
  double along_max_mps = 0.0;   ///< largest |v_contact . rolling direction|
  double across_max_mps = 0.0;  ///< largest |v_contact . axle|
  double rms_mps = 0.0;         ///< root mean square of the horizontal |v_contact| over the steps
  /// Mean over the steps of the wheel's rolling speed |omega . axle| x hub height, m/s: 0 for a
  /// wheel held by its brake or servo (the braked slides check it).
  double roll_mean_mps = 0.0;
  /// False where the engine has no wheel spin of its own (a raycast vehicle derives the wheel's
  /// rotation from the chassis speed): the along-slip then compares a value with itself.
  bool along_measured = true;
};

/// What the ground carried over the last drive, from the engine's own wheel-ground contact forces
/// summed over every wheel (the force the ground exerts on the car, world frame). Newton: their
/// normal components carry the car's weight m g cos(theta) while it rests, and on average over a
/// drive that starts and ends at rest on the plane (the vertical momentum then does not change).
struct GroundLoad {
  /// Non-empty where the engine gives no contact forces: why (the checks are then skipped, saying so).
  std::string absent_why;
  double weight_normal_N = NAN;  ///< m g cos(theta): the car's declared mass, gravity's component normal to the ground
  double rest_normal_N = NAN;    ///< mean normal contact force over the settle's last kRestWindow_s, at rest
  double drive_normal_N = NAN;   ///< mean normal contact force over every step of the drive, t = 0 to its end
  /// m |g_plane|: gravity's pull along the ground (m g sin(theta); 0 on the level).
  double plane_weight_N = NAN;
  /// |mean in-plane contact force over the rest window + m g_plane|: what the ground's grip does
  /// not hold of gravity's pull along it while the car rests (0 by Newton: it does not move).
  double rest_hold_gap_N = NAN;
  /// Newton's second law along the ground: the largest |p(t) - p(0) - integral of (F_plane + m
  /// g_plane) dt| over the drive, p the car's in-plane momentum (every body's, from its velocity
  /// as the engine reports it), F_plane the in-plane contact forces. N s.
  double momentum_gap_Ns = NAN;
  double momentum_change_Ns = NAN;  ///< the largest |p(t) - p(0)| over the drive, N s
  /// The gap's scale, N s: the largest momentum change, or kCruiseShare of the car's momentum at
  /// the drive's cruise speed where that is larger (a car steering in place hardly moves).
  double momentum_scale_Ns = NAN;
  /// Non-empty where the engine gives forces but not the velocities the momentum needs: why.
  std::string momentum_absent_why;
  static constexpr double kCruiseShare = 0.1;
  static constexpr double kRestWindow_s = 0.2;
};

/// A car in an engine: reset to a configuration, drive a base path, report (alpha, beta, x, y, phi).
class CarEngine {
 public:
  virtual ~CarEngine() = default;
  virtual void reset(const CarSetup& setup, const car::Config& q0) = 0;
  /// Drives `path` from the reset configuration; returns the realized configuration over time,
  /// starting at t = 0 and ending at the path's end, every setup.sample_dt_s.
  virtual std::vector<car::TimedConfig> drive(const car::BasePath& path) = 0;
  /// Contact-point slip of every wheel over the last drive (from t = 0 to its end). Every engine
  /// must say: empty only for a model without contact points to measure (the analytic lift rolls
  /// without slipping by construction; an outside simulator's trace has no wheel states).
  virtual std::vector<WheelSlip> slip() const = 0;
  /// True only for the analytic engine: it reports the commanded (alpha, beta) and their exact
  /// lift by construction, so comparing its trace with the command or with the lift of its own
  /// shape compares a value with itself (shown, not counted). Every engine that steps physics,
  /// whatever it derives its wheel angles from, is judged by those comparisons.
  virtual bool exact_by_construction() const { return false; }
  /// Simulated time the engine stepped since construction (settling included), s: the
  /// denominator of the cost per simulated second.
  virtual double simulated_s() const = 0;
  /// True for a trace read back from a simulator outside liftcheck: nothing inside it is known,
  /// so its whole path is compared with the exact lift at every sample.
  virtual bool replays_trace() const { return false; }
  /// Seconds the engine itself spent stepping, as an outside engine's adapter reports them
  /// (docs/protocol.md, `engine_s`): the cost per simulated second without the protocol's round
  /// trip. NaN for an engine in liftcheck's process, whose run's wall clock is its cost.
  virtual double reported_engine_s() const { return NAN; }
  /// The contact forces that carried the car over the last drive (GroundLoad).
  virtual GroundLoad ground_load() const { return {.absent_why = "this engine reports no contact forces"}; }
};

/// Two unit disks: N moves along a known path, M's velocity is commanded from a reaction rule.
/// Rigid-body engines realise M's commanded velocity with their own actuation and integrator and
/// detect contact with their own collision pipeline while stepping.
struct DiskSetup {
  double radius_m = 1.0;
  double dt_s = 1e-3;         ///< engine step
  double sample_dt_s = 0.02;  ///< spacing of the reported trace
  /// Coulomb friction between M and N. Farber's disks are frictionless and every scenario runs at
  /// 0; the conformance test sets it to see that each engine holds M's spin (a tangential contact
  /// force then moves M instead of turning it).
  double mu_MN = 0.0;
};

struct DiskProblem {
  disks::Rule rule;
  disks::NPath path;
  disks::Vec2 cM0;
  double T_s = 6.0;
};

/// What an engine's own contact pipeline said over a stepped run. Distances are the engine's
/// reported centre distances |c_M - c_N| at the states its collision passes ran on.
struct DiskContactLog {
  double distance_at_first_m = NAN;     ///< at the state on which contact was first reported
  double overlap_unreported_m = 0.0;    ///< largest 2 - |c_M - c_N| > 0 at any state reported free of contact
  double gap_reported_max_m = 0.0;      ///< largest |c_M - c_N| - 2 > 0 at any state reported in contact
  double depth_error_max_m = 0.0;       ///< largest |reported depth - (2 - |c_M - c_N|)| at states reported in contact
  double overlap_growth_first_m = 0.0;  ///< overlap on the state after the first contact minus that at it (a response
                                        ///< acting at once stops the approach)
  double penetration_max_m =
      0.0;  ///< largest 2 - |c_M - c_N| from the first contact to T (the contact response bounds it)
  double depth_reported_max_m = 0.0;  ///< deepest penetration the engine's contact points reported
  long steps_in_contact = 0;          ///< steps whose collision pass reported contact
  double n_path_error_max_m = 0.0;    ///< largest distance of N from its path, every step
  bool apart_at_end = false;          ///< after contact, |c_M - c_N| > 2 at T (the disks separated)
  /// Largest |(c_M after - c_M before) - v_cmd h| over the steps before the first reported contact:
  /// an engine that realises its command moves M by exactly the commanded velocity times the step.
  double step_displacement_error_max_m = 0.0;
  double step_displacement_error_at_s = 0.0;  ///< the start of the step where it was largest
  /// Largest |omega_M| after any step, rad/s: the engine holds M's spin (a planar vehicle whose
  /// velocity is commanded does not roll on N), and when it does not, friction between the disks
  /// spins M up instead of moving it.
  double spin_M_max_radps = 0.0;
  double spin_M_max_at_s = 0.0;  ///< the end of the step after which it was largest
  /// Contact was reported by the engine's own collision pipeline. False for a trace from outside,
  /// whose "contact" is read off its positions: comparing those with themselves measures nothing.
  bool reported_by_engine = true;
};

/// Disks apart by no more than this are touching (the round-off of |c_M - c_N| = 2 at these scales).
constexpr double kTouchRoundoff_m = 1e-9;
/// A contact has ended when the disks are apart by at least this much more than touching: a
/// micrometre, above the gaps of 0.2 um that Bullet's penetration recovery opens for a step while
/// its contact holds (the larger threshold is a tenth of a step of relative travel, DiskRun).
constexpr double kSeparation_m = 1e-6;

struct DiskRun {
  std::optional<double> t_contact_s;  ///< analytic: root; engines: the state on which contact was first reported
  /// M and N at t_contact_s (engines: the state their collision pass first reported contact on).
  std::optional<disks::Sample> contact_state;
  /// The end of the first contact: the first state after it with the disks apart by more than a
  /// tenth of a step of M's travel relative to N at contact, and at least kSeparation_m
  /// (models/disk_contact.hpp, kSeparationSteps; analytic: the root of the release); none while
  /// they touch to T.
  std::optional<double> t_release_s;
  double min_distance =
      0.0;  ///< smallest |c_M - c_N| (analytic: refined on the dense output; engines: over their steps)
  std::vector<disks::Sample> trace;           ///< at t = i * sample_dt from 0 to T (and T)
  std::optional<DiskContactLog> contact_log;  ///< stepping engines only
};

class DiskEngine {
 public:
  virtual ~DiskEngine() = default;
  virtual DiskRun run(const DiskSetup& setup, const DiskProblem& problem) = 0;
  /// Simulated time stepped since construction, s (the exact model: the problems' horizons).
  virtual double simulated_s() const = 0;
  /// As CarEngine::reported_engine_s.
  virtual double reported_engine_s() const { return NAN; }
};

/// A body has blown up when it is faster than kRunawayFactor times the fastest speed the run
/// commands, or than kRunawaySpeed_mps where that is more. The stepping loops check it at every
/// step, with NaN and bodies through the ground.
constexpr double kRunawaySpeed_mps = 50.0;
constexpr double kRunawayFactor = 10.0;

/// Thrown by an engine whose simulation failed (NaN, explosion, bad setup): reported as an error run.
struct EngineError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

}  // namespace liftcheck
