#include "harness/sweeps.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

#include "input/record_view.hpp"
#include "scenarios/details.hpp"
#include "scenarios/disk_scenarios.hpp"
#include "scenarios/fit.hpp"
#include "scenarios/sweep_catalogue.hpp"
#include "harness/runner.hpp"
#include "liftcheck_expectations.hpp"

namespace liftcheck {

const std::vector<KnownSweepFailure>& known_sweep_failures() {
  static const std::vector<KnownSweepFailure> all = [] {
    std::vector<KnownSweepFailure> v;
    const nlohmann::json j = nlohmann::json::parse(kExpectationsJson);
    for (const auto& e : j.at("sweep_points"))
      for (const auto& engine : e.at("engines")) {
        KnownSweepFailure k;
        k.sweep = e.at("sweep");
        k.engine = engine;
        k.reason = e.at("reason");
        k.measured = e.at("measured");
        const std::string where = fmt::format("sweep {} on {}", k.sweep, k.engine);
        if (e.contains("fit_problem")) {
          k.kind = KnownSweepFailure::kFit;
          k.pattern = e.at("fit_problem");
          v.push_back(k);
        } else if (e.contains("error_contains")) {
          k.kind = KnownSweepFailure::kError;
          k.pattern = e.at("error_contains");
          for (const auto& x : e.at("x")) k.x = x.get<double>(), v.push_back(k);
        } else if (e.contains("points")) {
          // Each point with its own ceilings: a point may fail only in its listed metrics.
          k.kind = KnownSweepFailure::kPoint;
          for (const auto& pt : e.at("points")) {
            k.x = pt.at("x").get<double>();
            k.metrics = parse_ceilings(pt.at("metrics"), fmt::format("{} at x = {}", where, k.x));
            v.push_back(k);
          }
        } else {
          k.kind = KnownSweepFailure::kAnywhere;
          k.metrics = parse_ceilings(e.at("metrics"), where);
          k.points_max = e.at("points_max").get<int>();
          k.disagreements_max = e.value("disagreements_max", 0);
          v.push_back(k);
        }
      }
    return v;
  }();
  return all;
}

namespace {

/// A failing point's (metric, error) pairs: each of its "failed" metrics with its error from
/// "errors" (infinite when missing, so no ceiling accepts it).
std::vector<std::pair<std::string, double>> point_errors(const nlohmann::json& pt) {
  std::vector<std::pair<std::string, double>> out;
  const nlohmann::json errors = pt.value("errors", nlohmann::json::object());
  for (const auto& name : pt.value("failed", nlohmann::json::array())) {
    const auto it = errors.find(name.get<std::string>());
    out.emplace_back(name.get<std::string>(), it != errors.end() && it->is_number() ? it->get<double>() : INFINITY);
  }
  return out;
}

/// The log-log fit of `entry` against its band: a problem, or its known failure marked on the fit.
void gate_fit(const SweepDef& sweep, const KnownSweepFailure* fit_known, nlohmann::json& entry,
              nlohmann::json& problems) {
  const auto& slope = entry["fit"]["slope"];
  std::string fit_problem;
  if (!slope.is_number())
    fit_problem = "too few points above the noise floor for a slope";
  else if (std::abs(slope.get<double>() - sweep.slope_expected) > sweep.slope_band)
    fit_problem = fmt::format("fitted slope {:.4f} outside {} +- {}", slope.get<double>(), sweep.slope_expected,
                              sweep.slope_band);
  if (fit_known && fit_problem.rfind(fit_known->pattern, 0) == 0 && !fit_problem.empty())
    entry["fit"]["known_failure"] = fit_known->reason + ": " + fit_problem;
  else if (fit_known)
    problems.push_back(fmt::format("the fit is listed as failing with '{}' ({}) but: {}", fit_known->pattern,
                                   fit_known->reason, fit_problem.empty() ? "it lies in its band" : fit_problem));
  else if (!fit_problem.empty())
    problems.push_back(fit_problem);
}

/// A point past the grip limit where the car kept its grip: neither its front radius nor its
/// lateral slip failed by the sliding amounts.
bool kept_grip(const nlohmann::json& pt) {
  bool slid = false;
  for (const auto& [name, err] : point_errors(pt))
    slid = slid || (name == "front_radius" && err >= SweepDef::kSlideRadius) ||
           (name == "slip_across_max" && err >= SweepDef::kSlideAcross_mps);
  return !slid;
}

}  // namespace

bool gate_sweep_entry(const SweepDef& sweep, nlohmann::json& entry) {
  const std::string engine = entry["engine"];
  nlohmann::json problems = nlohmann::json::array();
  int pass = 0, known = 0, error = 0, unexpected = 0;
  const KnownSweepFailure *anywhere = nullptr, *fit_known = nullptr;
  for (const auto& f : known_sweep_failures())
    if (f.sweep == sweep.name && f.engine == engine) {
      if (f.kind == KnownSweepFailure::kAnywhere) anywhere = &f;
      if (f.kind == KnownSweepFailure::kFit) fit_known = &f;
    }
  int anywhere_failed = 0;
  const EngineInfo* info = find_engine(engine);
  const bool must_slide = sweep.slide_past_marker && info && info->contact_dynamics;
  for (auto& pt : entry["points"]) {
    const double x = pt["x"];
    if (must_slide && x > sweep.marker && pt["status"] != "error" && kept_grip(pt)) {
      ++unexpected;
      problems.push_back(
          fmt::format("{} = {}: past the grip limit ({}) the car must slide (front radius +{:g} or lateral slip {:g} "
                      "m/s), but it kept its grip: {}",
                      sweep.param, x, sweep.marker_label, SweepDef::kSlideRadius, SweepDef::kSlideAcross_mps,
                      pt["status"] == "pass" ? "every metric passes" : pt.value("message", "")));
      continue;
    }
    const KnownSweepFailure* k = nullptr;
    for (const auto& f : known_sweep_failures())
      if (f.sweep == sweep.name && f.engine == engine &&
          (f.kind == KnownSweepFailure::kPoint || f.kind == KnownSweepFailure::kError) && f.x == x)
        k = &f;
    const std::string st = pt["status"];
    const std::string message = pt.value("message", "");
    if (!k && anywhere && st == "fail") {
      k = anywhere;
      ++anywhere_failed;
    }
    if (k && k->kind == KnownSweepFailure::kError) {
      if (st == "error" && message.find(k->pattern) != std::string::npos) {
        ++known;
        pt["known_failure"] = k->reason;
      } else {
        ++unexpected;
        problems.push_back(fmt::format("{} = {}: listed as ending in an error containing '{}' ({}) but: {} {}",
                                       sweep.param, x, k->pattern, k->reason, st, message));
      }
    } else if (st == "error") {
      ++error;
      problems.push_back(fmt::format("{} = {}: error: {}", sweep.param, x, message));
    } else if (k && st == "fail") {
      const auto beyond = beyond_ceilings(k->metrics, point_errors(pt));
      if (beyond.empty()) {
        ++known;
        pt["known_failure"] = k->reason;
      } else {
        ++unexpected;
        problems.push_back(fmt::format("{} = {}: worse than its known failure ({}): {}", sweep.param, x, k->reason,
                                       fmt::join(beyond, "; ")));
      }
    } else if (k) {
      ++unexpected;
      problems.push_back(fmt::format("{} = {}: listed as a known failure ({}) but passes", sweep.param, x, k->reason));
    } else if (st == "fail") {
      ++unexpected;
      problems.push_back(fmt::format("{} = {}: {}", sweep.param, x, message));
    } else {
      ++pass;
    }
  }
  if (anywhere && anywhere_failed == 0)
    problems.push_back(fmt::format("listed as failing at some points ({}) but every point passes", anywhere->reason));
  if (anywhere && anywhere_failed > anywhere->points_max)
    problems.push_back(fmt::format("{} points fail where at most {} are known to ({})", anywhere_failed,
                                   anywhere->points_max, anywhere->reason));
  if (sweep.loglog_fit) gate_fit(sweep, fit_known, entry, problems);
  entry["gate"] = {{"pass", problems.empty()},      {"problems", problems},  {"points_pass", pass},
                   {"points_known_failure", known}, {"points_error", error}, {"points_unexpected", unexpected}};
  if (sweep.loglog_fit)
    entry["gate"]["slope_band"] = {sweep.slope_expected - sweep.slope_band, sweep.slope_expected + sweep.slope_band};
  return problems.empty();
}

Overrides point_overrides(const SweepDef& s, double x) {
  Overrides ov = s.fixed;
  const std::string value = fmt::format("{}", x);
  if (s.param_keys.empty()) ov.emplace_back(s.param, value);
  for (const auto& key : s.param_keys) ov.emplace_back(key, value);
  for (const auto& p : s.times_x) ov.emplace_back(p.key, fmt::format("{}", std::max(p.min, p.per_x * x)));
  return ov;
}

namespace {

nlohmann::json value_of(const nlohmann::json& record, const std::string& key) {
  const auto [kind, name] = recorded_field(key);
  if (kind == RecordedField::kMetric) {
    const auto& ms = record["metrics"];
    if (!ms.contains(name)) return nullptr;
    return MetricView(ms[name]).point_figures();
  }
  const auto& d = record["details"];
  return d.contains(name) ? d[name] : nlohmann::json();
}

}  // namespace

namespace {

struct MapPoint {
  std::string knob;
  double value;
  Overrides overrides;
};

/// One configuration's grid: every dt at its default settings and, for an iterative solver, every
/// iteration count at the default dt; the exact model has no step and gets one point, and so does
/// a configuration registered for its runs only (its default run, which steps nothing more).
std::vector<MapPoint> map_grid(const MapDef& map, const EngineInfo& e, bool all_points) {
  std::vector<MapPoint> grid;
  if (e.is_reference || (e.points == SuitePoints::kRuns && !all_points)) return {{kMapDefault, 0.0, {}}};
  for (double dt : map.dt_s) grid.push_back({kMapDt, dt, {{"dt", fmt::format("{}", dt)}}});
  // One ladder of iterations per configuration: its first declared count (an engine with two,
  // position and velocity iterations, is mapped along the first; tune searches both).
  const auto it = std::find_if(e.knobs.begin(), e.knobs.end(), [](const SettingSpec& k) {
    return k.vehicle == Vehicle::kCar && k.role == SettingRole::kSolverIterations;
  });
  if (it != e.knobs.end())
    for (int n : map.iterations)
      grid.push_back({kMapIterations, static_cast<double>(n), {{it->key, fmt::format("{}", n)}}});
  return grid;
}

std::string map_key(const MapDef& map, const MapDef::Panel& panel, const EngineInfo& e, const MapPoint& g) {
  return fmt::format("map/{}/{}/{}/{}={}", map.name, panel.scenario, e.name, g.knob, g.value);
}

}  // namespace

std::vector<PointRun> map_runs(const MapDef& map, const std::vector<const EngineInfo*>& engines, bool all_points) {
  std::vector<PointRun> runs;
  for (const MapDef::Panel& panel : map.panels)
    for (const EngineInfo* e : engines)
      if (e->make_car)
        for (const MapPoint& g : map_grid(map, *e, all_points))
          runs.push_back({map_key(map, panel, *e, g), find_scenario(panel.scenario), e, g.overrides});
  return runs;
}

nlohmann::json assemble_map(const MapDef& map, const std::vector<const EngineInfo*>& engines,
                            const RecordLookup& record, bool all_points) {
  nlohmann::json panels = nlohmann::json::array();
  for (const MapDef::Panel& panel : map.panels) {
    nlohmann::json curves = nlohmann::json::array();
    std::vector<nlohmann::json*> candidates;
    for (const EngineInfo* e : engines) {
      if (!e->make_car) continue;
      nlohmann::json points = nlohmann::json::array();
      for (const MapPoint& g : map_grid(map, *e, all_points)) {
        const nlohmann::json& r = record(map_key(map, panel, *e, g));
        double err = NAN;
        RecordView(r).each_metric([&](const std::string& name, const MetricView& m) {
          if (std::find(panel.error_metrics.begin(), panel.error_metrics.end(), name) != panel.error_metrics.end() &&
              !std::isnan(m.rel_error()))
            err = std::isnan(err) ? m.rel_error() : std::max(err, m.rel_error());
        });
        // An outside engine's cost is its own stepping time as its adapter reports it, so that the
        // protocol's round trip does not count against it; in process, the run's wall clock.
        const double wall_s = r["wall_s"], simulated_s = r["simulated_s"];
        const double spent_s =
            r.contains("engine_s") && r["engine_s"].is_number() ? r["engine_s"].get<double>() : wall_s;
        const double cost = simulated_s > 0.0 ? spent_s / simulated_s : NAN;
        points.push_back(
            {{"knob", g.knob},
             {"value", g.value},
             {"status", r["status"]},
             {"message", r["message"]},
             {"error", r["status"] == "error" || !std::isfinite(err) ? nlohmann::json() : nlohmann::json(err)},
             {"wall_s", wall_s},
             {"simulated_s", simulated_s},
             {"cost_s_per_s", std::isfinite(cost) ? nlohmann::json(cost) : nlohmann::json()},
             {"pareto", false}});
      }
      curves.push_back({{"engine", e->name}, {"points", points}});
    }
    // The Pareto front over every configuration's points: none cheaper and at least as accurate.
    for (auto& c : curves) {
      if (find_engine(c["engine"].get<std::string>())->is_reference) continue;  // the yardstick, not a contender
      for (auto& p : c["points"])
        if (p["error"].is_number() && p["cost_s_per_s"].is_number()) candidates.push_back(&p);
    }
    for (nlohmann::json* p : candidates) {
      const double e0 = (*p)["error"], c0 = (*p)["cost_s_per_s"];
      bool dominated = false;
      for (const nlohmann::json* q : candidates) {
        if (q == p) continue;
        const double e1 = (*q)["error"], c1 = (*q)["cost_s_per_s"];
        if (e1 <= e0 && c1 <= c0 && (e1 < e0 || c1 < c0)) dominated = true;
      }
      (*p)["pareto"] = !dominated;
    }
    panels.push_back({{"scenario", panel.scenario},
                      {"error_metrics", panel.error_metrics},
                      {"error_label", panel.error_label},
                      {"curves", curves}});
  }
  return {{"name", map.name}, {"kind", "map"}, {"title", map.title}, {"dt_s", map.dt_s}, {"iterations", map.iterations},
          {"panels", panels}};
}

namespace {

std::string sweep_key(const SweepDef& s, const EngineInfo& e, double x) {
  return fmt::format("sweep/{}/{}/x={}", s.name, e.name, x);
}

}  // namespace

nlohmann::json point_record(const RunRecord& r) { return point_record(r.to_json()); }

nlohmann::json point_record(nlohmann::json record) {
  for (const char* big : {detail_key::kTrace, detail_key::kReference, detail_key::kContactLog})
    record["details"].erase(big);
  return record;
}

std::vector<PointRun> sweep_runs(const SweepDef& s, const std::vector<const EngineInfo*>& engines) {
  std::vector<PointRun> runs;
  for (const EngineInfo* e : engines)
    if (e->make_car)
      for (double x : s.values)
        runs.push_back({sweep_key(s, *e, x), find_scenario(s.scenario), e, point_overrides(s, x)});
  return runs;
}

nlohmann::json assemble_sweep(const SweepDef& s, const std::vector<const EngineInfo*>& engines,
                              const RecordLookup& record) {
  nlohmann::json per_engine = nlohmann::json::array();
  for (const EngineInfo* e : engines) {
    if (!e->make_car) continue;
    nlohmann::json points = nlohmann::json::array();
    std::vector<double> fx, fy;
    for (double x : s.values) {
      const nlohmann::json& rec = record(sweep_key(s, *e, x));
      nlohmann::json pt{
          {"x", x}, {"status", rec["status"]}, {"message", rec["message"]}, {"failed", nlohmann::json::array()}};
      pt["errors"] = nlohmann::json::object();
      RecordView(rec).each_metric([&](const std::string& name, const MetricView& m) {
        if (!m.pass() && m.counted()) pt["failed"].push_back(name), pt["errors"][name] = m.written_compared_error();
      });
      for (const auto& key : s.record) pt[key] = value_of(rec, key);
      if (s.loglog_fit && rec["status"] != "error") {
        const nlohmann::json y = value_of(rec, s.fit_y), noise = value_of(rec, s.fit_noise);
        // Above the noise floor: the engine's error is under a tenth of what it measures.
        if (y.is_number() && noise.is_number() && y.get<double>() > 10.0 * noise.get<double>()) {
          fx.push_back(x);
          fy.push_back(y.get<double>());
          pt["fitted"] = true;
        }
      }
      points.push_back(pt);
    }
    nlohmann::json entry{{"engine", e->name}, {"points", points}};
    if (s.loglog_fit)
      entry["fit"] = fx.size() >= 2 ? nlohmann::json{{"slope", loglog_slope(fx, fy)}, {"points", fx.size()}}
                                    : nlohmann::json{{"slope", nullptr}, {"points", fx.size()}};
    gate_sweep_entry(s, entry);
    per_engine.push_back(entry);
  }
  nlohmann::json curves = nlohmann::json::array();
  for (const auto& [expr, title] : s.curves) curves.push_back({{"expr", expr}, {"title", title}});
  nlohmann::json j{
      {"name", s.name},
      {"title", s.title},
      {"scenario", s.scenario},
      {"param", s.param},
      {"fixed", s.fixed},
      {"record", s.record},
      {"engines", per_engine},
      {"plot",
       {{"kind", s.plot}, {"x_label", s.x_label}, {"y_label", s.y_label}, {"log_x", s.log_x}, {"curves", curves}}}};
  if (s.marker > 0.0) j["marker"] = {{"x", s.marker}, {"label", s.marker_label}};
  for (const auto& p : s.times_x) j["times_x"].push_back({{"key", p.key}, {"per_x", p.per_x}, {"min", p.min}});
  return j;
}

}  // namespace liftcheck
