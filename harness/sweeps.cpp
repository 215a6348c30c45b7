#include "harness/sweeps.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

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

/// A failing point's (metric, error) pairs: each of its failed metrics with its compared error
/// (infinite when not finite, so no ceiling accepts it).
std::vector<std::pair<std::string, double>> point_errors(const SweepPoint& pt) {
  std::vector<std::pair<std::string, double>> out;
  for (const auto& name : pt.failed) {
    const auto it = pt.errors.find(name);
    out.emplace_back(name, it != pt.errors.end() && std::isfinite(it->second) ? it->second : INFINITY);
  }
  return out;
}

/// The log-log fit of `entry` against its band: a problem, or its known failure marked on the fit.
void gate_fit(const SweepDef& sweep, const KnownSweepFailure* fit_known, SweepEngine& entry,
              std::vector<std::string>& problems) {
  const double slope = entry.fit ? entry.fit->slope : NAN;
  std::string fit_problem;
  if (!std::isfinite(slope))
    fit_problem = "too few points above the noise floor for a slope";
  else if (std::abs(slope - sweep.slope_expected) > sweep.slope_band)
    fit_problem = fmt::format("fitted slope {:.4f} outside {} +- {}", slope, sweep.slope_expected, sweep.slope_band);
  if (fit_known && fit_problem.rfind(fit_known->pattern, 0) == 0 && !fit_problem.empty()) {
    if (!entry.fit) entry.fit = SweepFit{};
    entry.fit->known_failure = fit_known->reason + ": " + fit_problem;
  } else if (fit_known)
    problems.push_back(fmt::format("the fit is listed as failing with '{}' ({}) but: {}", fit_known->pattern,
                                   fit_known->reason, fit_problem.empty() ? "it lies in its band" : fit_problem));
  else if (!fit_problem.empty())
    problems.push_back(fit_problem);
}

/// A point past the grip limit where the car kept its grip: neither its front radius nor its
/// lateral slip failed by the sliding amounts.
bool kept_grip(const SweepPoint& pt) {
  bool slid = false;
  for (const auto& [name, err] : point_errors(pt))
    slid = slid || (name == "front_radius" && err >= SweepDef::kSlideRadius) ||
           (name == "slip_across_max" && err >= SweepDef::kSlideAcross_mps);
  return !slid;
}

/// The listings of `sweep` on `engine` of one kind at `x` (any x for kAnywhere and kFit).
const KnownSweepFailure* listed(const SweepDef& sweep, const std::string& engine, KnownSweepFailure::Kind kind,
                                double x = NAN) {
  const KnownSweepFailure* found = nullptr;
  for (const auto& f : known_sweep_failures())
    if (f.sweep == sweep.name && f.engine == engine && f.kind == kind && (std::isnan(x) || f.x == x)) found = &f;
  return found;
}

/// One point against its listing (if any): its count, and a problem when it is not as listed.
struct PointTally {
  int pass = 0, known = 0, error = 0, unexpected = 0, anywhere_failed = 0;
};
void gate_point(const SweepDef& sweep, const std::string& engine, const KnownSweepFailure* anywhere, SweepPoint& pt,
                PointTally& t, std::vector<std::string>& problems) {
  const double x = pt.x;
  pt.known_failure.clear();  // gated again: its listing's reason set anew
  const KnownSweepFailure* k = listed(sweep, engine, KnownSweepFailure::kPoint, x);
  if (!k) k = listed(sweep, engine, KnownSweepFailure::kError, x);
  if (!k && anywhere && pt.status == Status::kFail) k = anywhere, ++t.anywhere_failed;
  const std::string& message = pt.message;
  if (k && k->kind == KnownSweepFailure::kError) {
    if (pt.status == Status::kError && message.find(k->pattern) != std::string::npos) {
      ++t.known, pt.known_failure = k->reason;
    } else {
      ++t.unexpected;
      problems.push_back(fmt::format("{} = {}: listed as ending in an error containing '{}' ({}) but: {} {}",
                                     sweep.param, x, k->pattern, k->reason, to_string(pt.status), message));
    }
  } else if (pt.status == Status::kError) {
    ++t.error;
    problems.push_back(fmt::format("{} = {}: error: {}", sweep.param, x, message));
  } else if (k && pt.status == Status::kFail) {
    const auto beyond = beyond_ceilings(k->metrics, point_errors(pt));
    if (beyond.empty()) {
      ++t.known, pt.known_failure = k->reason;
    } else {
      ++t.unexpected;
      problems.push_back(fmt::format("{} = {}: worse than its known failure ({}): {}", sweep.param, x, k->reason,
                                     fmt::join(beyond, "; ")));
    }
  } else if (k) {
    ++t.unexpected;
    problems.push_back(fmt::format("{} = {}: listed as a known failure ({}) but passes", sweep.param, x, k->reason));
  } else if (pt.status == Status::kFail) {
    ++t.unexpected;
    problems.push_back(fmt::format("{} = {}: {}", sweep.param, x, message));
  } else {
    ++t.pass;
  }
}

}  // namespace

bool gate_sweep_entry(const SweepDef& sweep, SweepEngine& entry) {
  std::vector<std::string> problems;
  PointTally t;
  const KnownSweepFailure* anywhere = listed(sweep, entry.engine, KnownSweepFailure::kAnywhere);
  const KnownSweepFailure* fit_known = listed(sweep, entry.engine, KnownSweepFailure::kFit);
  const EngineInfo* info = find_engine(entry.engine);
  const bool must_slide = sweep.slide_past_marker && info && info->contact_dynamics;
  for (SweepPoint& pt : entry.points) {
    if (must_slide && pt.x > sweep.marker && pt.status != Status::kError && kept_grip(pt)) {
      ++t.unexpected;
      problems.push_back(
          fmt::format("{} = {}: past the grip limit ({}) the car must slide (front radius +{:g} or lateral slip {:g} "
                      "m/s), but it kept its grip: {}",
                      sweep.param, pt.x, sweep.marker_label, SweepDef::kSlideRadius, SweepDef::kSlideAcross_mps,
                      pt.status == Status::kPass ? "every metric passes" : pt.message));
      continue;
    }
    gate_point(sweep, entry.engine, anywhere, pt, t, problems);
  }
  if (anywhere && t.anywhere_failed == 0)
    problems.push_back(fmt::format("listed as failing at some points ({}) but every point passes", anywhere->reason));
  if (anywhere && t.anywhere_failed > anywhere->points_max)
    problems.push_back(fmt::format("{} points fail where at most {} are known to ({})", t.anywhere_failed,
                                   anywhere->points_max, anywhere->reason));
  if (sweep.loglog_fit) gate_fit(sweep, fit_known, entry, problems);
  entry.gate = Gate{problems.empty(), problems, t.pass, t.known, t.error, t.unexpected, std::nullopt};
  if (sweep.loglog_fit)
    entry.gate.slope_band = {sweep.slope_expected - sweep.slope_band, sweep.slope_expected + sweep.slope_band};
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

struct MapGridPoint {
  std::string knob;
  double value;
  Overrides overrides;
};

/// One configuration's grid: every dt at its default settings and, for an iterative solver, every
/// iteration count at the default dt; the exact model has no step and gets one point, and so does
/// a configuration registered for its runs only (its default run, which steps nothing more).
std::vector<MapGridPoint> map_grid(const MapDef& map, const EngineInfo& e, bool all_points) {
  std::vector<MapGridPoint> grid;
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

std::string map_key(const MapDef& map, const MapDef::Panel& panel, const EngineInfo& e, const MapGridPoint& g) {
  return fmt::format("map/{}/{}/{}/{}={}", map.name, panel.scenario, e.name, g.knob, g.value);
}

/// A map point from its run's record: the panel's error, and the engine's cost per simulated second.
MapPoint map_point(const MapDef::Panel& panel, const MapGridPoint& g, const RunResult& r) {
  double err = NAN;
  for (const Metric& m : r.metrics)
    if (std::find(panel.error_metrics.begin(), panel.error_metrics.end(), m.name) != panel.error_metrics.end() &&
        !std::isnan(m.rel_error))
      err = std::isnan(err) ? m.rel_error : std::max(err, m.rel_error);
  // An outside engine's cost is its own stepping time as its adapter reports it, so that the
  // protocol's round trip does not count against it; in process, the run's wall clock.
  const double spent_s = std::isfinite(r.engine_s) ? r.engine_s : r.wall_s;
  const double cost = r.simulated_s > 0.0 ? spent_s / r.simulated_s : NAN;
  return {g.knob,
          g.value,
          r.status,
          r.message,
          r.status == Status::kError || !std::isfinite(err) ? NAN : err,
          r.wall_s,
          r.simulated_s,
          std::isfinite(cost) ? cost : NAN,
          false,
          r.status == Status::kPass};
}

/// The Pareto front over every configuration's points but the reference's: none cheaper and at
/// least as accurate.
void mark_pareto(std::vector<MapCurve>& curves) {
  std::vector<MapPoint*> candidates;
  for (auto& c : curves) {
    if (find_engine(c.engine)->is_reference) continue;  // the yardstick, not a contender
    for (auto& p : c.points)
      if (std::isfinite(p.error) && std::isfinite(p.cost_s_per_s)) candidates.push_back(&p);
  }
  for (MapPoint* p : candidates) {
    bool dominated = false;
    for (const MapPoint* q : candidates)
      if (q != p && q->error <= p->error && q->cost_s_per_s <= p->cost_s_per_s &&
          (q->error < p->error || q->cost_s_per_s < p->cost_s_per_s))
        dominated = true;
    p->pareto = !dominated;
  }
}

}  // namespace

std::vector<PointRun> map_runs(const MapDef& map, const std::vector<const EngineInfo*>& engines, bool all_points) {
  std::vector<PointRun> runs;
  for (const MapDef::Panel& panel : map.panels)
    for (const EngineInfo* e : engines)
      if (e->make_car)
        for (const MapGridPoint& g : map_grid(map, *e, all_points))
          runs.push_back({map_key(map, panel, *e, g), find_scenario(panel.scenario), e, g.overrides});
  return runs;
}

SpeedMap assemble_map(const MapDef& map, const std::vector<const EngineInfo*>& engines, const RecordLookup& record,
                      bool all_points) {
  SpeedMap out{map.name, map.title, map.dt_s, map.iterations, {}};
  for (const MapDef::Panel& panel : map.panels) {
    MapPanel p{panel.scenario, panel.error_label, panel.error_metrics, {}};
    for (const EngineInfo* e : engines) {
      if (!e->make_car) continue;
      MapCurve curve{e->name, {}};
      for (const MapGridPoint& g : map_grid(map, *e, all_points))
        curve.points.push_back(map_point(panel, g, record(map_key(map, panel, *e, g))));
      p.curves.push_back(std::move(curve));
    }
    mark_pareto(p.curves);
    out.panels.push_back(std::move(p));
  }
  return out;
}

namespace {

std::string sweep_key(const SweepDef& s, const EngineInfo& e, double x) {
  return fmt::format("sweep/{}/{}/x={}", s.name, e.name, x);
}

/// A recorded field of a point's record (metric_field or detail_field) into the point.
void record_field(const RunResult& rec, const std::string& field, SweepPoint& pt) {
  const auto [kind, name] = recorded_field(field);
  if (kind == RecordedField::kMetric) {
    if (const Metric* m = rec.metric(name))
      pt.metrics[name] = {m->expected, m->measured, m->rel_error, m->abs_error, m->pass};
    return;
  }
  pt.details[name] = rec.details.contains(name) ? rec.details[name] : nlohmann::json();
}

/// The value of a recorded field at a point, when it is a finite number.
double recorded_number(const SweepPoint& pt, const std::string& field) {
  const auto [kind, name] = recorded_field(field);
  if (kind == RecordedField::kMetric) {
    const auto it = pt.metrics.find(name);
    return it == pt.metrics.end() ? NAN : it->second.measured;
  }
  const auto it = pt.details.find(name);
  return it != pt.details.end() && it->second.is_number() ? it->second.get<double>() : NAN;
}

SweepPoint sweep_point(const SweepDef& s, double x, const RunResult& rec) {
  SweepPoint pt;
  pt.x = x;
  pt.status = rec.status;
  pt.message = rec.message;
  for (const Metric& m : rec.metrics)
    if (!m.pass && m.counted()) pt.failed.push_back(m.name), pt.errors[m.name] = m.compared_error();
  for (const auto& field : s.record) record_field(rec, field, pt);
  pt.worst_ratio = rec.status == Status::kError ? NAN : rec.worst_ratio();
  return pt;
}

}  // namespace

void trim_to_point(RunResult& r) {
  // A point keeps its scalar details, the fields a sweep records and the outcome grid reads; the
  // traces, contact logs and per-wheel tables of its run (half of results.json) are its run's.
  if (!r.details.is_object()) return;
  for (auto it = r.details.begin(); it != r.details.end();)
    it = it->is_structured() ? r.details.erase(it) : std::next(it);
}

std::vector<PointRun> sweep_runs(const SweepDef& s, const std::vector<const EngineInfo*>& engines) {
  std::vector<PointRun> runs;
  for (const EngineInfo* e : engines)
    if (e->make_car)
      for (double x : s.values)
        runs.push_back({sweep_key(s, *e, x), find_scenario(s.scenario), e, point_overrides(s, x)});
  return runs;
}

Sweep assemble_sweep(const SweepDef& s, const std::vector<const EngineInfo*>& engines, const RecordLookup& record) {
  Sweep out;
  out.name = s.name, out.title = s.title, out.scenario = s.scenario, out.param = s.param;
  out.fixed = s.fixed, out.record = s.record;
  out.plot_kind = s.plot, out.x_label = s.x_label, out.y_label = s.y_label, out.log_x = s.log_x;
  out.curves = s.curves;
  if (s.marker > 0.0) out.marker = {{s.marker, s.marker_label}};
  for (const auto& p : s.times_x) out.times_x.push_back({p.key, p.per_x, p.min});
  for (const EngineInfo* e : engines) {
    if (!e->make_car) continue;
    SweepEngine entry{e->name, {}, std::nullopt, {}};
    std::vector<double> fx, fy;
    for (double x : s.values) {
      const RunResult& rec = record(sweep_key(s, *e, x));
      SweepPoint pt = sweep_point(s, x, rec);
      if (s.loglog_fit && rec.status != Status::kError) {
        const double y = recorded_number(pt, s.fit_y), noise = recorded_number(pt, s.fit_noise);
        // Above the noise floor: the engine's error is under a tenth of what it measures.
        if (std::isfinite(y) && std::isfinite(noise) && y > 10.0 * noise) {
          fx.push_back(x), fy.push_back(y);
          pt.fitted = true;
        }
      }
      entry.points.push_back(std::move(pt));
    }
    if (s.loglog_fit)
      entry.fit = SweepFit{fx.size() >= 2 ? loglog_slope(fx, fy) : NAN, static_cast<int>(fx.size()), ""};
    gate_sweep_entry(s, entry);
    out.engines.push_back(std::move(entry));
  }
  return out;
}

}  // namespace liftcheck
