// The outcome sweep: disks.linear over a grid of (a, b) and N's paths, each configuration's
// collision outcome against the reference's (Farber's collision domains, section 4).
#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "harness/runner.hpp"
#include "harness/sweeps.hpp"
#include "input/record_view.hpp"
#include "scenarios/details.hpp"
#include "scenarios/disk_scenarios.hpp"

namespace liftcheck {

namespace {

struct OutcomeCase {
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

OutcomeCase outcome_case(double a, double b, const std::string& path) {
  OutcomeCase c{
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

const std::vector<OutcomeCase>& outcome_cases() {
  static const std::vector<OutcomeCase> cases = [] {
    std::vector<OutcomeCase> v;
    for (const auto& path : outcome_paths())
      for (double a : outcome_as())
        for (double b : outcome_bs()) v.push_back(outcome_case(a, b, path));
    return v;
  }();
  return cases;
}

std::string outcome_key(const EngineInfo& e, const OutcomeCase& c) {
  return fmt::format("outcomes/{}/{}/a={}/b={}", e.name, c.path, c.a, c.b);
}

/// A stored record's failing counted metrics with their errors (a NaN error counts as infinite).
std::pair<std::vector<std::pair<std::string, double>>, nlohmann::json> failed_metrics(const nlohmann::json& rec) {
  std::vector<std::pair<std::string, double>> failed;
  nlohmann::json failed_errors = nlohmann::json::object();
  RecordView(rec).each_metric([&](const std::string& name, const MetricView& m) {
    if (m.pass() || !m.counted()) return;
    const double err = m.compared_error();
    failed.emplace_back(name, std::isnan(err) ? INFINITY : err);
    failed_errors[name] = failed.back().second;
  });
  return {failed, failed_errors};
}

/// The outcome sweep's gate for one configuration: its problems (none: it passes).
nlohmann::json outcome_problems(int unexplained, int errors, int failing, int known_failing,
                                const KnownSweepFailure* listed, const std::vector<std::string>& failing_cases) {
  nlohmann::json problems = nlohmann::json::array();
  if (unexplained > (listed ? listed->disagreements_max : 0))
    problems.push_back(fmt::format("{} disagreements with the reference outcome away from the boundary", unexplained));
  if (listed && listed->disagreements_max > 0 && unexplained == 0)
    problems.push_back(fmt::format("listed with up to {} outcome disagreements ({}) but agrees everywhere",
                                   listed->disagreements_max, listed->reason));
  if (errors > 0) problems.push_back(fmt::format("{} error runs", errors));
  if (failing > 0)
    problems.push_back(fmt::format("{} runs out of tolerance ({})", failing, fmt::join(failing_cases, "; ")));
  if (listed && known_failing == 0)
    problems.push_back(fmt::format("listed as failing in some runs ({}) but every run passes", listed->reason));
  if (listed && known_failing > listed->points_max)
    problems.push_back(fmt::format("{} runs fail where at most {} are known to ({})", known_failing, listed->points_max,
                                   listed->reason));
  return problems;
}

}  // namespace

std::vector<PointRun> outcome_runs(const std::vector<const EngineInfo*>& engines) {
  const Scenario* sc = find_scenario(outcome_sweep_scenario());
  const EngineInfo* reference = &reference_engine();
  std::vector<PointRun> runs;
  for (const OutcomeCase& c : outcome_cases()) runs.push_back({outcome_key(*reference, c), sc, reference, c.overrides});
  for (const EngineInfo* e : engines)
    if (e->make_disks && e != reference)
      for (const OutcomeCase& c : outcome_cases()) runs.push_back({outcome_key(*e, c), sc, e, c.overrides});
  return runs;
}

namespace {

/// An outcome case with what the reference engine made of it.
struct ReferenceCase {
  const OutcomeCase* c;
  bool collision;
  double t, min_d;
};

/// The reference engine's outcome of each case of the grid.
std::vector<ReferenceCase> reference_cases(const RecordLookup& record) {
  const EngineInfo* reference = &reference_engine();
  std::vector<ReferenceCase> cases;
  for (const OutcomeCase& c : outcome_cases()) {
    const nlohmann::json& rec = record(outcome_key(*reference, c));
    if (rec["status"] == "error")
      throw std::runtime_error(fmt::format("the reference run failed: {}", rec["message"].get<std::string>()));
    const auto& d = rec["details"];
    const bool hit = d[detail_key::kTContactMeasured].is_number();
    // Closest approach of the lift (21), refined on its dense output (not over samples).
    cases.push_back({&c, hit, hit ? d[detail_key::kTContactMeasured].get<double>() : NAN,
                     d[detail_key::kReferenceMinDistance].get<double>()});
  }
  return cases;
}

/// Configuration `e`'s outcomes of `cases` against the reference's: its confusion matrix, its rows, its gate.
nlohmann::json engine_outcomes(const EngineInfo& e, const std::vector<ReferenceCase>& cases, const RecordLookup& record,
                               double near_m) {
  int tp = 0, tn = 0, fp = 0, fn = 0, near = 0, unexplained = 0, errors = 0, failing = 0, known_failing = 0;
  const KnownSweepFailure* listed = nullptr;
  for (const auto& f : known_sweep_failures())
    if (f.sweep == "disk_outcomes" && f.engine == e.name && f.kind == KnownSweepFailure::kAnywhere) listed = &f;
  std::vector<std::string> failing_cases;
  double worst_steps = 0.0;
  nlohmann::json rows = nlohmann::json::array();
  for (const ReferenceCase& cs : cases) {
    const OutcomeCase& c = *cs.c;
    // The reference engine's runs are the cases themselves.
    const nlohmann::json& rec = record(outcome_key(e, c));
    // The case and the reference's outcome, which every row of it starts with.
    nlohmann::json row = {{"a", c.a}, {"b", c.b}, {"path", c.path}, {"T_s", c.T_s}, {"reference", cs.collision}};
    if (rec["status"] == "error") {  // its own column: no outcome to compare
      ++errors;
      row.update({{"engine", nullptr}, {"status", "error"}, {"message", rec["message"]}});
      rows.push_back(std::move(row));
      continue;
    }
    const auto& d = rec["details"];
    const bool hit = d[detail_key::kTContactMeasured].is_number();
    // A run failing only in metrics the expectations list for this configuration, no worse than
    // their ceilings, is a known failure.
    bool known_fail = false;
    const auto [failed, failed_errors] = failed_metrics(rec);
    if (listed && rec["status"] == "fail") {
      known_fail = beyond_ceilings(listed->metrics, failed).empty();
      known_failing += known_fail ? 1 : 0;
    }
    if (rec["status"] != "pass" && !known_fail) {
      ++failing;
      if (failing_cases.size() < 5)
        failing_cases.push_back(fmt::format("a={} b={} {}: {}", c.a, c.b, c.path, rec["message"].get<std::string>()));
    }
    const bool is_near = std::abs(cs.min_d - 2.0) < near_m;
    (cs.collision ? (hit ? tp : fn) : (hit ? fp : tn)) += 1;
    near += is_near ? 1 : 0;
    if (hit != cs.collision && !is_near) ++unexplained;
    double steps = NAN;
    if (hit && cs.collision) {
      steps = (d[detail_key::kTContactMeasured].get<double>() - cs.t) / 1e-3;
      worst_steps = std::max(worst_steps, std::abs(steps));
    }
    row.update({{"engine", hit},
                {"reference_t_contact_s", cs.collision ? nlohmann::json(cs.t) : nlohmann::json()},
                {"t_error_steps", std::isfinite(steps) ? nlohmann::json(steps) : nlohmann::json()},
                {"reference_min_distance", cs.min_d},
                {"near_boundary", is_near},
                {"status", rec["status"]},
                {"errors", failed_errors},
                {"known_failure", known_fail}});
    rows.push_back(std::move(row));
  }
  const nlohmann::json problems = outcome_problems(unexplained, errors, failing, known_failing, listed, failing_cases);
  return nlohmann::json(
      {{"engine", e.name},
       {"confusion", {{"both_collide", tp}, {"neither", tn}, {"engine_only", fp}, {"reference_only", fn}}},
       {"errors", errors},
       {"runs_out_of_tolerance", failing},
       {"runs_known_failure", known_failing},
       {"known_failure", listed ? nlohmann::json(listed->reason + " (" + listed->measured + ")") : nlohmann::json()},
       {"near_boundary_cases", near},
       {"unexplained_disagreements", unexplained},
       {"worst_t_error_steps", worst_steps},
       {"cases", rows},
       {"gate", {{"pass", problems.empty()}, {"problems", problems}}}});
}

}  // namespace

nlohmann::json assemble_outcome_sweep(const std::vector<const EngineInfo*>& engines, const RecordLookup& record,
                                      double near_m) {
  const std::vector<ReferenceCase> cases = reference_cases(record);
  nlohmann::json per_engine = nlohmann::json::array();
  for (const EngineInfo* e : engines)
    if (e->make_disks) per_engine.push_back(engine_outcomes(*e, cases, record, near_m));
  return {{"name", "disk_outcomes"},
          {"kind", "outcomes"},
          {"title",
           fmt::format("Collision outcomes of {} over (a, b) and N's paths: each configuration against the reference",
                       outcome_sweep_scenario())},
          {"scenario", outcome_sweep_scenario()},
          {"grid", {{"a", outcome_as()}, {"b", outcome_bs()}, {"path", outcome_paths()}}},
          {"fixed", {{"cM", "0,0"}, {"cN", "4,0"}, {"vN", "-0.6,0.4"}, {"dt", "0.001"}}},
          {"horizon",
           {{"T_max_s", kOutcomeHorizon.t_max_s},
            {"clearance_m", kOutcomeHorizon.clearance_m},
            {"after_s", kOutcomeHorizon.after_s},
            {"T_min_s", kOutcomeHorizon.t_min_s}}},
          {"near_boundary_m", near_m},
          {"engines", per_engine}};
}

}  // namespace liftcheck
