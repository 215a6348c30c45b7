// What the disk scenarios share (Farber, Kurz, Pillin): their parameters, the checked run, the
// exact references and the comparisons every disk run gets before and after contact, and the metrics
// those report. The scenarios themselves: disk_free.cpp (no contact) and disk_contact.cpp.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "engines/vehicle.hpp"
#include "models/disk_contact.hpp"
#include "scenarios/declare.hpp"
#include "scenarios/scenario.hpp"

namespace liftcheck::disk_common {

using namespace declare;
using disks::Vec2;

/// Parameters every disk scenario shares; `path` is left out where the scenario fixes N's motion.
std::vector<ParamSpec> disk_params(const std::string& cM, const std::string& cN, const std::string& vN,
                                   const std::string& path, const std::string& T, bool with_path = true,
                                   double T_max = 1e4);
disks::NPath path_from(const Params& p);
/// The trace is sampled every whole number of engine steps closest to sample_dt (at least one).
DiskSetup setup_from(const Params& p);
void check_start(const Vec2& cM, const Vec2& cN);
/// The plans (14), (17) must be continuous in t for M to follow them; where two paths around N
/// are equally short the planner switches sides and the plan jumps. Sampled finely, a jump
/// between neighbours of more than 0.1 m is such a switch (N moves at most 1000 m/s here, so a
/// continuous plan moves far less over T / 20000).
void check_continuous(const std::function<Vec2(double)>& q, double T);
/// The planners keep `clearance` from N: start and goal must lie outside that circle.
void check_clearance(const Vec2& a, const Vec2& b, const Vec2& cN, double clearance);
DiskRun run_checked(DiskEngine& engine, const DiskSetup& setup, const DiskProblem& pb);
nlohmann::json trace_json(const std::vector<disks::Sample>& trace);
/// The first time the relative position rel(t) has |rel| <= 2 on [0, T]: a fine scan, then TOMS 748.
std::optional<double> first_contact(const std::function<Vec2(double)>& rel, double T);
double final_distance(const DiskRun& r);
/// Engines integrate M's commanded velocity step by step: their trajectory errors are first order
/// in dt. Tolerances of trajectory metrics are data at dt = 1 ms, scaled by dt / 1 ms.
double first_order(const Params& p);
/// The lift (21) of the problem, integrated with a different method (Bulirsch-Stoer) from the one
/// the analytic engine runs (dopri5), and sampled where the engines sample.
disks::LiftResult analytic(const DiskProblem& pb, const DiskSetup& setup);
/// Largest |c_M - c_M,ref(t)| over the trace samples up to t_limit.
double path_error(const DiskRun& run, const std::function<Vec2(double)>& cM_ref, double t_limit);
/// The reference lift's c_M at a sample time of the engine's trace (both sample at i * spacing).
std::function<Vec2(double)> at_samples(const disks::LiftResult& ref);
/// The trace sample of `trace` at time t (the traces compared share the grid i * sample spacing).
const disks::Sample& sample_at(const std::vector<disks::Sample>& trace, double t);
/// The contact-time shift of the zero-order hold itself: M stepped by its command held over each
/// step (the forward Euler of the lift (21) at dt, which is what an engine that realises its
/// command does, to round-off) first overlaps N in some step; that step's midpoint against the
/// exact time. It depends on the problem and dt only, never on the engine judged.
double zoh_contact_shift_s(const DiskProblem& pb, double dt, double t_exact);
/// After the first contact (class of faults: contacts that stick, stop M dead or bounce). The
/// frictionless, inelastic response is exact (models/disk_contact.hpp); it is integrated from the
/// state on which the engine first reported contact (its own positions, so the comparison starts
/// where the engine's contact did) to T: M's path against it at every trace sample after
/// contact, and the time the first contact lasts against the reference's. Tolerances in steps:
/// of M's travel relative to N at contact (path), of dt (duration).
void after_contact(Outcome& o, const DiskProblem& pb, const DiskRun& run, const DiskSetup& setup);
/// What every disk scenario measures. Before contact the engine must follow the lift: its path
/// against `cM_ref`, and, where the disks never touch, the closest approach and the final
/// distance. Contact: collision and its time (in steps), and, from the engine's own contact log,
/// that it reported contact on the first state whose disks overlapped and not before, and that
/// its contact response kept the penetration small.
Outcome disk_outcome(const Params& p, const DiskProblem& pb, const DiskRun& run, const disks::LiftResult& ref,
                     const std::optional<double>& expected_t, const std::function<Vec2(double)>& cM_ref);
Outcome disk_outcome(const Params& p, const DiskProblem& pb, const DiskRun& run, const disks::LiftResult& ref,
                     const std::optional<double>& expected_t);
/// Largest |d(t) - d(0)| and largest angle between c(t) = c_M - c_N and c(0) over the trace.
std::pair<double, double> spreads(const DiskRun& r, double t_limit = INFINITY);
DiskProblem problem(const Params& p, const disks::Mechanism& m);
disks::Mechanism linear_from(const Params& p);

// Engines: data at dt = 1 ms, scaled by dt / 1 ms (first-order integration of M's command).
inline const MetricDef kDistanceSpread =
    abs_("distance_spread", "m", 1e-8, 1e-2, "largest change of |c_M - c_N| from its start");
inline const MetricDef kDirectionChange =
    abs_("direction_change", "rad", 1e-8, 5e-3, "largest turn of c_M - c_N from its start (before contact)");
// The plans (14) and (17) turn at the tangent points (velocity kinks) and are followed through
// central differences: two integrators at 1e-12 agree on them to 2e-7 m at the defaults and
// 2.3e-6 m over the parameter ranges.
constexpr double kPlanTol = 1e-5;
// Every velocity of the planners' rules replans: durations are bounded for time. A plan that
// switches sides (the default target's does at t = 15.71 s) is rejected as bad input.
constexpr double kPlannerTmax = 60.0;

/// The metrics every disk scenario reports, then `extra`; the reference's tolerance on the path,
/// the closest approach and the final distance is `analytic_path_tol`.
std::vector<MetricDef> disk_metrics(std::vector<MetricDef> extra, double analytic_path_tol = 1e-8);

}  // namespace liftcheck::disk_common

namespace liftcheck {
// Headlines: the engine's own error. Before contact it is how far each step of M falls from its
// command (path_error and end_error are mostly the zero-order hold of the command, the same for
// every engine that realises it); after contact, M against the exact response from the engine's
// own contact state (t_contact's error is the hold's shift too).
/// The disk scenarios by family, each in catalogue order: without contact (disks.copy,
/// disks.actuated, disks.orbit, disks.extended, disks.target) and with it (disks.repel,
/// disks.linear, disks.oblique, disks.forced, disks.moving-away).
std::vector<Scenario> contact_free_disk_scenarios();
std::vector<Scenario> contact_disk_scenarios();
}  // namespace liftcheck
