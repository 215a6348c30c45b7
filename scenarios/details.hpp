// The details a scenario function records (Outcome::details, a run's "details" in results.json)
// that something else reads: the report's pictures and pages, the sweeps' records and gates.
// Scenario functions write them under these keys and readers read them under the same; any other
// detail is free-form, kept in the record for a reader of results.json.
#pragma once

namespace liftcheck::detail_key {

// ---- a run's trace (both vehicles) ----------------------------------------------------------
/// At most ~400 rows (and the last) of the engine's trace (results.json keeps 120 of them, at 9
/// digits: thin_drawn_traces): a car's [t, alpha, beta, x, y, phi] (s, rad, m), the
/// disks' [t, cMx, cMy, cNx, cNy] (s, m). Snapshots, frame strips and the error plots draw it.
inline constexpr char kTrace[] = "trace";
/// The exact lift's rows at the same times, columns as kTrace (grey in the pictures).
inline constexpr char kReference[] = "reference";
/// What kReference is when it is not the exact lift, for the pictures' titles ("the exact
/// Coulomb slide"); absent: the exact lift.
inline constexpr char kReferenceLabel[] = "reference_label";
/// The disks after the engine's first contact: {kFromT: the contact's time, kReference: the exact
/// inelastic response from there, as rows like the trace}.
inline constexpr char kAfterContact[] = "after_contact";
inline constexpr char kFromT[] = "from_t_s";  ///< in kAfterContact

// ---- car ------------------------------------------------------------------------------------
/// The end-pose split {kCommandedLiftEnd, "realized_lift_end", "engine_end", kActuationError,
/// kContactError} (an end pose is [x, y, phi]; errors in m).
inline constexpr char kErrors[] = "errors";
inline constexpr char kCommandedLiftEnd[] = "commanded_lift_end";  ///< in kErrors: the exact lift's end pose
inline constexpr char kActuationError[] = "actuation_error_m";     ///< in kErrors
inline constexpr char kContactError[] = "contact_error_m";         ///< in kErrors
/// The ground's load from the engine's own contact forces, or {kNotMeasured: why} without them.
inline constexpr char kGroundLoad[] = "ground_load";
inline constexpr char kNotMeasured[] = "not_measured";  ///< in kGroundLoad
/// A parking cycle's number of steps: the frame strip shows a frame after each.
inline constexpr char kSteps[] = "steps";
/// Several drives of one scenario: an array of objects, each with its own kTrace.
inline constexpr char kRuns[] = "runs";
/// How the snapshot draws the run: kDrawingStarts, every start of kRuns (car.covariance); absent:
/// one trace.
inline constexpr char kDrawing[] = "drawing";
inline constexpr char kDrawingStarts[] = "starts";
/// Lateral acceleration the exact lift needs over mu g (the grip sweep records it).
inline constexpr char kGripUse[] = "grip_use";
/// The exact holonomy's size, the measured one, and the error between them, m (the eps sweeps fit them).
inline constexpr char kHolonomySize[] = "holonomy_size_m";
inline constexpr char kMeasuredSize[] = "measured_size_m";
inline constexpr char kHolonomyError[] = "holonomy_error_m";

// ---- disks ----------------------------------------------------------------------------------
/// The state on which contact was first reported, s; null without contact (the contact snapshot,
/// the outcome sweep).
inline constexpr char kTContactMeasured[] = "t_contact_measured_s";
/// The exact lift's closest approach |c_M - c_N|, m (the outcome sweep's near-boundary cases).
inline constexpr char kReferenceMinDistance[] = "reference_min_distance";
/// The centre [x, y] and radius (m) of the ball D of Lemma 6.1 (drawn in the snapshots).
inline constexpr char kCollisionCentre[] = "collision_centre";
inline constexpr char kCollisionRadius[] = "collision_radius";
/// What the engine's own contact pipeline reported (DiskContactLog); dropped from sweep points.
inline constexpr char kContactLog[] = "contact_log";

}  // namespace liftcheck::detail_key
