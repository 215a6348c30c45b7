// The outcome sweep: disks.linear over a grid of (a, b) and N's paths, each configuration's
// collision outcome against the reference's (Farber's collision domains, section 4).
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "harness/runner.hpp"
#include "harness/sweeps.hpp"
#include "scenarios/details.hpp"
#include "scenarios/disk_scenarios.hpp"

namespace liftcheck {

namespace {

struct GridCase {
  double a, b;
  std::string path;
  Overrides overrides;
  double T_s;  ///< its horizon (linear_outcome_horizon_s)
};

const std::vector<double>& outcome_as() {
  static const std::vector<double> v{-1.0, 0.0, 0.5, 0.9, 1.5, 2.0, 3.0};
  return v;
}
const std::vector<double>& outcome_bs() {
  static const std::vector<double> v{-1.0, 0.0, 0.5, 1.0};
  return v;
}
const std::vector<std::string>& outcome_paths() {
  static const std::vector<std::string> v{"line", "circle", "figure8"};
  return v;
}

GridCase outcome_case(double a, double b, const std::string& path) {
  GridCase c{
      a,
      b,
      path,
      {{"a", fmt::format("{}", a)}, {"b", fmt::format("{}", b)}, {"path", path}, {"cN", "4,0"}, {"vN", "-0.6,0.4"}},
      kOutcomeHorizon.t_max_s};
  const Scenario& s = *find_scenario(outcome_sweep_scenario());
  Overrides full = c.overrides;
  full.emplace_back("T", fmt::format("{}", kOutcomeHorizon.t_max_s));
  c.T_s = linear_outcome_horizon_s(Params::resolve(s.params, full, s.name), kOutcomeHorizon.clearance_m,
                                   kOutcomeHorizon.after_s, kOutcomeHorizon.t_min_s);
  c.overrides.emplace_back("T", fmt::format("{}", c.T_s));
  return c;
}

const std::vector<GridCase>& outcome_cases() {
  static const std::vector<GridCase> cases = [] {
    std::vector<GridCase> v;
    for (const auto& path : outcome_paths())
      for (double a : outcome_as())
        for (double b : outcome_bs()) v.push_back(outcome_case(a, b, path));
    return v;
  }();
  return cases;
}

std::string outcome_key(const EngineInfo& e, const GridCase& c) {
  return fmt::format("outcomes/{}/{}/a={}/b={}", e.name, c.path, c.a, c.b);
}

/// A record's failing counted metrics with their errors (a NaN error counts as infinite).
std::vector<std::pair<std::string, double>> failed_metrics(const RunResult& rec) {
  std::vector<std::pair<std::string, double>> failed;
  for (const Metric& m : rec.metrics)
    if (!m.pass && m.counted())
      failed.emplace_back(m.name, std::isnan(m.compared_error()) ? INFINITY : m.compared_error());
  return failed;
}

/// The outcome sweep's gate for one configuration: its problems (none: it passes).
std::vector<std::string> outcome_problems(const OutcomeEngine& e, const KnownSweepFailure* listed,
                                          const std::vector<std::string>& failing_cases) {
  std::vector<std::string> problems;
  const int unexplained = e.unexplained_disagreements;
  if (unexplained > (listed ? listed->disagreements_max : 0))
    problems.push_back(fmt::format("{} disagreements with the reference outcome away from the boundary", unexplained));
  if (listed && listed->disagreements_max > 0 && unexplained == 0)
    problems.push_back(fmt::format("listed with up to {} outcome disagreements ({}) but agrees everywhere",
                                   listed->disagreements_max, listed->reason));
  if (e.errors > 0) problems.push_back(fmt::format("{} error runs", e.errors));
  if (e.runs_out_of_tolerance > 0)
    problems.push_back(
        fmt::format("{} runs out of tolerance ({})", e.runs_out_of_tolerance, fmt::join(failing_cases, "; ")));
  if (listed && e.runs_known_failure == 0)
    problems.push_back(fmt::format("listed as failing in some runs ({}) but every run passes", listed->reason));
  if (listed && e.runs_known_failure > listed->points_max)
    problems.push_back(fmt::format("{} runs fail where at most {} are known to ({})", e.runs_known_failure,
                                   listed->points_max, listed->reason));
  return problems;
}

}  // namespace

std::vector<PointRun> outcome_runs(const std::vector<const EngineInfo*>& engines) {
  const Scenario* sc = find_scenario(outcome_sweep_scenario());
  const EngineInfo* reference = &reference_engine();
  std::vector<PointRun> runs;
  for (const GridCase& c : outcome_cases()) runs.push_back({outcome_key(*reference, c), sc, reference, c.overrides});
  for (const EngineInfo* e : engines)
    if (e->make_disks && e != reference)
      for (const GridCase& c : outcome_cases()) runs.push_back({outcome_key(*e, c), sc, e, c.overrides});
  return runs;
}

namespace {

/// An outcome case with what the reference engine made of it.
struct ReferenceCase {
  const GridCase* c;
  bool collision;
  double t, min_d;
};

/// The detail `key` of a record as a number (NaN when it is not one).
double detail_number(const RunResult& r, const char* key) {
  const auto it = r.details.find(key);
  return it != r.details.end() && it->is_number() ? it->get<double>() : NAN;
}

/// The reference engine's outcome of each case of the grid.
std::vector<ReferenceCase> reference_cases(const RecordLookup& record) {
  const EngineInfo* reference = &reference_engine();
  std::vector<ReferenceCase> cases;
  for (const GridCase& c : outcome_cases()) {
    const RunResult& rec = record(outcome_key(*reference, c));
    if (rec.status == Status::kError)
      throw std::runtime_error(fmt::format("the reference run failed: {}", rec.message));
    const double t = detail_number(rec, detail_key::kTContactMeasured);
    // Closest approach of the lift (21), refined on its dense output (not over samples).
    cases.push_back({&c, !std::isnan(t), t, detail_number(rec, detail_key::kReferenceMinDistance)});
  }
  return cases;
}

/// One case on a configuration against the reference's outcome, counted into `e`.
void count_case(const ReferenceCase& cs, const RunResult& rec, const KnownSweepFailure* listed, double near_m,
                OutcomeEngine& e, std::vector<std::string>& failing_cases) {
  const GridCase& c = *cs.c;
  OutcomeCase row;
  row.a = c.a, row.b = c.b, row.path = c.path, row.T_s = c.T_s, row.reference = cs.collision;
  row.status = rec.status;
  if (rec.status == Status::kError) {  // its own column: no outcome to compare
    ++e.errors;
    row.message = rec.message;
    e.cases.push_back(std::move(row));
    return;
  }
  const double t_hit = detail_number(rec, detail_key::kTContactMeasured);
  const bool hit = !std::isnan(t_hit);
  // A run failing only in metrics the expectations list for this configuration, no worse than
  // their ceilings, is a known failure.
  const auto failed = failed_metrics(rec);
  bool known_fail = false;
  if (listed && rec.status == Status::kFail) {
    known_fail = beyond_ceilings(listed->metrics, failed).empty();
    e.runs_known_failure += known_fail ? 1 : 0;
  }
  if (rec.status != Status::kPass && !known_fail) {
    ++e.runs_out_of_tolerance;
    if (failing_cases.size() < 5)
      failing_cases.push_back(fmt::format("a={} b={} {}: {}", c.a, c.b, c.path, rec.message));
  }
  const bool is_near = std::abs(cs.min_d - 2.0) < near_m;
  (cs.collision ? (hit ? e.both_collide : e.reference_only) : (hit ? e.engine_only : e.neither)) += 1;
  e.near_boundary_cases += is_near ? 1 : 0;
  if (hit != cs.collision && !is_near) ++e.unexplained_disagreements;
  if (hit && cs.collision) {
    row.t_error_steps = (t_hit - cs.t) / 1e-3;
    e.worst_t_error_steps = std::max(e.worst_t_error_steps, std::abs(row.t_error_steps));
  }
  row.engine = hit;
  row.reference_t_contact_s = cs.collision ? cs.t : NAN;
  row.reference_min_distance = cs.min_d;
  row.near_boundary = is_near;
  for (const auto& [name, err] : failed) row.errors[name] = err;
  row.known_failure = known_fail;
  e.cases.push_back(std::move(row));
}

/// Configuration `e`'s outcomes of `cases` against the reference's: its confusion matrix, its rows, its gate.
OutcomeEngine engine_outcomes(const EngineInfo& e, const std::vector<ReferenceCase>& cases, const RecordLookup& record,
                              double near_m) {
  const KnownSweepFailure* listed = nullptr;
  for (const auto& f : known_sweep_failures())
    if (f.sweep == "disk_outcomes" && f.engine == e.name && f.kind == KnownSweepFailure::kAnywhere) listed = &f;
  OutcomeEngine out;
  out.engine = e.name;
  if (listed) out.known_failure = listed->reason + " (" + listed->measured + ")";
  std::vector<std::string> failing_cases;
  // The reference engine's runs are the cases themselves.
  for (const ReferenceCase& cs : cases)
    count_case(cs, record(outcome_key(e, *cs.c)), listed, near_m, out, failing_cases);
  const std::vector<std::string> problems = outcome_problems(out, listed, failing_cases);
  out.gate.pass = problems.empty();
  out.gate.problems = problems;
  return out;
}

}  // namespace

OutcomeSweep assemble_outcome_sweep(const std::vector<const EngineInfo*>& engines, const RecordLookup& record,
                                    double near_m) {
  const std::vector<ReferenceCase> cases = reference_cases(record);
  OutcomeSweep out;
  out.name = "disk_outcomes";
  out.title =
      fmt::format("Collision outcomes of {} over (a, b) and N's paths: each configuration against the reference",
                  outcome_sweep_scenario());
  out.scenario = outcome_sweep_scenario();
  out.grid_a = outcome_as(), out.grid_b = outcome_bs(), out.grid_path = outcome_paths();
  out.fixed = {{"cM", "0,0"}, {"cN", "4,0"}, {"dt", "0.001"}, {"vN", "-0.6,0.4"}};
  out.T_max_s = kOutcomeHorizon.t_max_s, out.clearance_m = kOutcomeHorizon.clearance_m;
  out.after_s = kOutcomeHorizon.after_s, out.T_min_s = kOutcomeHorizon.t_min_s;
  out.near_boundary_m = near_m;
  for (const EngineInfo* e : engines)
    if (e->make_disks) out.engines.push_back(engine_outcomes(*e, cases, record, near_m));
  return out;
}

}  // namespace liftcheck
