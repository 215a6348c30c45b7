// What the car scenarios share (Fecko): the car's parameters, the setup and start they give, the
// checked drive and the comparisons every car run gets (the trace against the exact lift and the
// command, the contact slip, the realized lift, Coulomb's bound on the centre of mass), and the
// metrics those comparisons report. The scenarios themselves: car_circle.cpp, car_cycles.cpp,
// car_slope.cpp.
#pragma once

#include <nlohmann/json.hpp>
#include <numbers>
#include <string>
#include <utility>
#include <vector>

#include "engines/vehicle.hpp"
#include "models/e2.hpp"
#include "scenarios/declare.hpp"
#include "scenarios/scenario.hpp"

namespace liftcheck::car_common {

using namespace declare;
using car::Config;
using car::Vec5;
constexpr double kHalfPi = std::numbers::pi / 2.0;

/// Parameters every car scenario shares: geometry, start pose, driving, engine settings.
std::vector<ParamSpec> car_params(const std::string& beta_default);
CarSetup setup_from(const Params& p);
Config start_from(const Params& p);

/// Drives `path` and checks the trace: non-empty and finite, or the engine failed.
std::vector<car::TimedConfig> drive_checked(CarEngine& engine, const CarSetup& setup, const Config& q0,
                                            const car::BasePath& path);
/// A simulator outside liftcheck shows only its trace: its whole path is compared with the exact
/// lift of the commanded path at every sample (front-axle position), and its realized shape with
/// the commanded one. An engine liftcheck runs is judged by the same comparisons of its own trace
/// (up to the path's end, as a trace written back covers it), so that its verdict does not depend
/// on the road its results took. A model that reports the commanded shape and its exact lift (the
/// analytic engine) compares them with themselves: informational.
void add_trace_check(Outcome& o, const CarEngine& engine, const CarSetup& setup, const car::BasePath& path,
                     const Config& q0, const std::vector<car::TimedConfig>& trace);
/// At most ~400 rows [t, alpha, beta, x, y, phi] for plots and snapshots.
nlohmann::json trace_json(const std::vector<car::TimedConfig>& trace);
/// The exact lift (4.1) of the commanded path from q0, sampled like the engines' traces: what the
/// reports draw as the analytic reference.
nlohmann::json reference_json(const CarSetup& setup, const car::BasePath& path, const Config& q0);
/// Actuation error against contact error: the lift of the (alpha, beta) path the engine realized
/// tells how far the commanded path was missed (actuation) and how far the car strayed from the
/// lift of what its wheels did (contact: slip, compliance, friction model).
nlohmann::json error_split(const car::CarDef& c, const std::vector<car::TimedConfig>& trace,
                           const Config& commanded_end);
/// Contact-point slip measured by the engine every step (engines with wheels): the worst wheel's
/// largest speed along and across its rolling direction and its RMS slip speed. The analytic lift
/// rolls without slipping by construction and reports none.
void add_slip(Outcome& o, const CarEngine& engine);
/// The trace's timing: the time by which the realized wheel angle alpha and steering angle beta
// trail the commanded path, fitted by least squares over the drive (add_trace_check), in engine
// steps. A servo or motor a step early or late is off by one step however small the angles it
// moves in a step (the 5e-4 rad that steering at 0.5 rad/s turns in 1 ms is half trace_shape_error's
// tolerance); a quarter of a step is the tolerance.
inline const MetricDef STEER_LAG =
    abs_("steer_lag", "steps", 0.0, 0.25,
         "time by which the realized steering angle beta trails the commanded path (negative: leads), fitted by "
         "least squares over the drive's samples, in engine steps dt; informational on a path that does not steer");
inline const MetricDef DRIVE_LAG =
    abs_("drive_lag", "steps", 0.0, 0.25,
         "time by which the realized wheel angle alpha trails the commanded path (negative: leads), fitted by least "
         "squares over the drive's samples, in engine steps dt");
// The connection (3.3) at every sample: the pose the engine reports at sample k against the lift
/// of the (alpha, beta) its own wheels realized over samples 0..k (lift_of_samples, each interval
/// composed of exact flows; exact where only one of alpha and beta changes between two samples:
/// on car.circle the front-axle centre's arc is R times the wheel angle turned). A pose read late,
/// before the step that turned the wheels, or interpolated between steps, is off by its lag's
/// travel at every moving sample. The comparison must start where pose and wheels are known to
/// agree (at rest, t = 0): a lag is invisible to any comparison over a window that starts at a
/// pose which lags too.
///
/// What the comparison may accumulate: (3.3) ties the front-axle centre's velocity to R dalpha/dt
/// along the wheel's heading, so an engine's pose leaves the lift (4.1) of its own realized shape
/// only at the speed its contacts slip, |dp/dt - R alphadot e(theta)| = |v_slip|, and after time t
/// it is at most  int_0^t |v_slip| dt <= u t  from it, u = sqrt(2) x 1e-4 m/s the contact-slip
/// speed the slip metrics let every engine have (1e-4 m/s along and across). The metric is the largest excess over that
/// bound, max_k (|p_k - lift_k| - u t_k)+, in m; its tolerance is a fifth of one engine step's
/// travel v dt at the command's fastest front-wheel speed v (1e-4 m at 0.5 m/s and 1 ms, scaled by
/// v dt / 0.5 mm), so a pose one step late (v dt at the fastest samples) fails it wherever
/// u t_k < 0.8 v dt (the first 2.8 s on car.circle, 0.8 s of car.cycle's 1.9 s). The bound covers
/// the slip's own displacement, not the heading it turns (rear lateral slip turns the car at up to
/// u / l rad/s, a position error growing as v u t^2 / (2 l)): an engine slipping within the slip
/// tolerance can still fail it, which errs towards flagging.
/// A model that reports the commanded shape as its realized one compares its lift with itself:
/// informational.
void add_realized_lift(Outcome& o, const CarEngine& engine, const CarSetup& setup, const car::BasePath& path,
                       const std::vector<car::TimedConfig>& trace);
/// The car's centre of mass in the chassis frame (x forward from the front-axle centre, y left):
/// the chassis box l/2 behind the front axle, the front wheels with their knuckles, the rear wheels.
Eigen::Vector2d com_in_chassis(const CarSetup& s);
/// Coulomb's law for the whole car on flat ground: the ground pushes it horizontally by at most mu
/// times its weight, so its centre of mass never accelerates horizontally by more than mu g. The
/// centre of mass from each sample's pose (the chassis frame's point com_in_chassis), its
/// acceleration by second differences of the samples (the mean over two sample intervals, which
/// also averages the normal load's fluctuations); the excess of the largest over mu g, as a
/// fraction of mu g (0 within the bound). A car that follows a lift needing more, as a kinematic
/// one or one that keeps its grip past the limit does, is not doing physics.
double com_accel_excess(const CarSetup& s, const std::vector<car::TimedConfig>& trace);
/// Largest pairwise distance and heading difference among poses.
std::pair<double, double> pose_spread(const std::vector<e2::Pose>& poses);
MetricDef reference_only(MetricDef m);
std::vector<MetricDef> cycle_metrics();

// Contact-point slip, measured by the engine every step (not produced by the analytic lift). A
// gripping wheel's contact point is at rest: 0.1 mm/s is 2e-4 of the default speed.
inline const MetricDef SLIP_ALONG = abs_("slip_along_max", "m/s", 0.0, 1e-4,
                                         "largest contact-point speed along a wheel's rolling direction (worst wheel)");
inline const MetricDef SLIP_ACROSS =
    abs_("slip_across_max", "m/s", 0.0, 1e-4, "largest contact-point speed along a wheel's axle (worst wheel)");
inline const MetricDef SLIP_RMS =
    abs_("slip_rms", "m/s", 0.0, 1e-4, "RMS contact-point speed over the drive (worst wheel)");
// Newton's third law at the ground: the normal components of the engine's own wheel-ground contact
// forces carry the car's weight, m g cos(theta), at rest and on average over a drive that starts
// and ends at rest. 1% of the weight: gravity 5% weak fails it five times over.
inline const MetricDef LOAD_REST = rel("load_at_rest", "N", 0.0, 1e-2,
                                       "mean normal contact force over the last 0.2 s of the settle, at rest, against "
                                       "the car's weight m g cos(theta)");
inline const MetricDef LOAD_DRIVE = rel("load_over_drive", "N", 0.0, 1e-2,
                                        "mean normal contact force over every step of the drive against the car's "
                                        "weight m g cos(theta)");
// Newton's second law along the ground: the in-plane contact forces hold the parked car against
// gravity's pull down the slope (1% of m g sin(theta): a third measure of gravity), and over the
// drive their impulse with gravity's makes the change of the car's momentum (Sigma F = m a of its
// centre of mass, booked every step; 1% of the largest momentum change, or of a tenth of the car's
// momentum at cruise speed where that is larger: a car steering in place hardly moves).
inline const MetricDef HOLD_REST = rel("hold_at_rest", "N", 0.0, 1e-2,
                                       "|mean in-plane contact force over the last 0.2 s of the settle + m g_plane| "
                                       "against gravity's pull along the ground, m g sin(theta)");
inline const MetricDef MOMENTUM =
    rel("momentum_balance", "N s", 0.0, 1e-2,
        "largest |p(t) - p(0) - integral of (F_plane + m g_plane) dt| over the drive "
        "(p the car's in-plane momentum) against the largest |p(t) - p(0)|, or a tenth of m times the cruise speed if "
        "larger");
// Every sample of the trace (an engine's, or an outside simulator's from liftcheck score) against
// the exact lift and the command.
inline const MetricDef TRACE_PATH =
    abs_("trace_path_error", "m", 0.0, 1e-3,
         "the trace up to the path's end: largest distance of the front-axle centre from the exact lift at any sample");
inline const MetricDef TRACE_SHAPE =
    abs_("trace_shape_error", "rad", 0.0, 1e-3,
         "the trace up to the path's end: largest difference of its (alpha, beta) from the commanded path, or of its "
         "heading from the exact lift's, at any sample");
// The connection (3.3) at every sample: the pose against the lift of the engine's own realized
// (alpha, beta), less what the slip tolerance lets accumulate (add_realized_lift). 0.1 mm is a
// fifth of one engine step's travel at the default 0.5 m/s and 1 ms; the tolerance scales with
// v dt (a pose one step late is off by one step's travel).
inline const MetricDef REALIZED_LIFT =
    abs_("realized_lift_error", "m", 1e-9, 1e-4,
         "largest excess, at any sample t, of the front-axle centre's distance from the lift of the wheel and steering "
         "angles the engine realized up to t over what the contact-slip tolerance lets accumulate (sqrt(2) x 1e-4 m/s "
         "x t): a pose reported late or early; tolerance at 0.5 m/s and dt = 1 ms, x v dt / 0.5 mm with v the "
         "command's fastest front-wheel speed");
// Coulomb: the ground pushes the car by at most mu times its weight. 5% for the normal load's
// fluctuation over two sample intervals and the second differences.
inline const MetricDef COM_ACCEL = abs_("com_accel_excess", "1", 1e-9, 0.05,
                                        "largest horizontal acceleration of the car's centre of mass beyond mu g, as a "
                                        "fraction of mu g (0: within Coulomb's bound)");

}  // namespace liftcheck::car_common

namespace liftcheck {
/// The car scenarios by family, each in catalogue order: car.circle; the parking cycles and
/// car.covariance; car.slope and car.coulomb; past the grip limit (car.beyond-grip, car.slip).
std::vector<Scenario> circle_scenarios();
std::vector<Scenario> cycle_scenarios();
std::vector<Scenario> slope_scenarios();
std::vector<Scenario> grip_scenarios();
}  // namespace liftcheck
