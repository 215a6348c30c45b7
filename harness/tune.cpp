#include "harness/tune.hpp"

#include <algorithm>
#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <map>
#include <set>
#include <span>

#include "input/results_codec.hpp"

namespace liftcheck {

namespace {

/// The first phase's multipliers of a default, nearest first: a setting's on powers of 4 (an
/// iteration count from a sixteenth to 16 times, a stiffness or an accuracy a decade and more either
/// way; 64 times an iteration count costs minutes a run on the costliest engines and is no setting a
/// user runs); the step's on powers of 2 (dt from a quarter to 8 times: a step 16 times shorter
/// costs 16 times the default).
constexpr double kSettingLadder[] = {0.25, 4.0, 1.0 / 16.0, 16.0};
constexpr double kStepLadder[] = {2.0, 0.5, 4.0, 0.25, 8.0};

std::string value_text(const TuneDimension& d, double v) {
  return d.kind == ParamKind::kInteger ? fmt::format("{}", static_cast<long long>(std::llround(v)))
                                       : fmt::format("{:.4g}", v);
}

/// `v` clamped into the dimension's range (an integer rounded); nullopt below an exclusive minimum.
std::optional<double> in_range(const TuneDimension& d, double v) {
  v = std::min(v, d.max);
  if (v < d.min) v = d.min;
  if (d.kind == ParamKind::kInteger) v = std::clamp(std::round(v), std::ceil(d.min), std::floor(d.max));
  if (d.min_exclusive && v <= d.min) return std::nullopt;
  return v;
}

double number_of(const std::string& text) {
  double v = NAN;
  std::from_chars(text.data(), text.data() + text.size(), v);
  return v;
}

TuneDimension numeric(const ParamSpec& p, std::span<const double> ladder) {
  TuneDimension d{.key = p.key,
                  .kind = p.kind,
                  .default_text = p.default_text,
                  .min = p.min,
                  .max = p.max,
                  .min_exclusive = p.min_exclusive};
  d.default_value = number_of(p.default_text);
  std::set<std::string> seen{value_text(d, d.default_value)};
  for (const double m : ladder)
    if (const auto v = in_range(d, d.default_value * m))
      if (seen.insert(value_text(d, *v)).second) d.ladder.push_back(value_text(d, *v));
  return d;
}

double cost_of(const RunResult& r) {
  const double spent = std::isfinite(r.engine_s) ? r.engine_s : r.wall_s;
  return r.simulated_s > 0.0 ? 1e3 * spent / r.simulated_s : NAN;
}

/// Each counted metric's tolerance in the default run: every run is judged against them, so a
/// longer step cannot pass by the tolerances that scale with dt.
using Tolerances = std::map<std::string, double>;
Tolerances tolerances_of(const RunResult& record) {
  Tolerances t;
  for (const Metric& m : record.metrics)
    if (m.counted() && m.tolerance > 0.0) t[m.name] = m.tolerance;
  return t;
}

/// The model of a step's cost against the default's, from its settings alone: steps per simulated
/// second (dt) times the work of a step, one unit for the step itself plus one per solver
/// iteration of every declared count (counts add: PhysX's and Jolt's position and velocity
/// iterations are passes of their own), so no count, not even 0, makes a run free; a setting
/// without a cost direction counts 1.
double model_cost(const Overrides& change, const std::vector<TuneDimension>& dims) {
  const auto value_of = [&](const TuneDimension& d) {
    for (const auto& [key, value] : change)
      if (key == d.key) return number_of(value);
    return d.default_value;
  };
  double steps = 1.0, work = 1.0, work0 = 1.0;
  for (const TuneDimension& d : dims) {
    if (d.cost_direction < 0 && d.default_value > 0.0) steps *= d.default_value / value_of(d);
    if (d.cost_direction > 0) work += std::max(0.0, value_of(d)), work0 += std::max(0.0, d.default_value);
  }
  return steps * work / work0;
}

TuneStep step_of(std::string phase, Overrides change, RunResult record, const Tolerances& at_default) {
  TuneStep s{.phase = std::move(phase), .change = std::move(change), .record = std::move(record)};
  const Status status = s.record.status;
  // As the record wrote it: no ratio without metrics, a non-finite one as none (null).
  if (!s.record.metrics.empty() && std::isfinite(s.record.worst_ratio())) s.worst_ratio = s.record.worst_ratio();
  if (status == Status::kError) s.worst_ratio = std::numeric_limits<double>::infinity();
  for (const Metric& m : s.record.metrics)
    if (const auto it = at_default.find(m.name); it != at_default.end() && m.counted()) {
      const double e = m.compared_error();
      s.worst_ratio = std::max(s.worst_ratio, std::isnan(e) ? std::numeric_limits<double>::infinity() : e / it->second);
    }
  s.pass = status == Status::kPass && s.worst_ratio <= 1.0;
  s.cost_ms_per_s = cost_of(s.record);
  return s;
}

/// The walk so far, and the budget left; runs each batch as one (in parallel where the runner can).
struct Walk {
  const TuneDef& def;
  const TuneRunner& run;
  const std::vector<TuneDimension>& dims;
  std::vector<TuneStep> steps;
  std::set<std::string> tried;
  std::set<std::string> unmade_runs;  ///< runs planned and not made (the budget ran out), each once
  int unmade = 0;                     ///< their number

  int left() const { return def.budget_runs - static_cast<int>(steps.size()); }
  void batch(const std::string& phase, std::vector<Overrides> changes) {
    std::vector<Overrides> fresh;
    for (auto& c : changes) {
      std::sort(c.begin(), c.end());
      if (tried.count(change_text(c))) continue;
      if (static_cast<int>(fresh.size()) >= left()) {
        if (unmade_runs.insert(change_text(c)).second) ++unmade;
        continue;
      }
      tried.insert(change_text(c));
      fresh.push_back(c);
    }
    if (fresh.empty()) return;
    std::vector<RunResult> records = run(fresh);
    const Tolerances at_default = steps.empty() ? Tolerances{} : tolerances_of(steps.front().record);
    for (size_t i = 0; i < fresh.size(); ++i) {
      steps.push_back(step_of(phase, fresh[i], std::move(records.at(i)), at_default));
      steps.back().model_cost = model_cost(steps.back().change, dims);
    }
  }
  /// The steps that change only `key` (and the default run), by value.
  std::vector<std::pair<double, const TuneStep*>> line(const TuneDimension& d) const {
    std::vector<std::pair<double, const TuneStep*>> v;
    for (const TuneStep& s : steps) {
      if (s.change.empty()) v.emplace_back(d.default_value, &s);
      if (s.change.size() == 1 && s.change[0].first == d.key) v.emplace_back(number_of(s.change[0].second), &s);
    }
    std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
    return v;
  }
};

/// Phase 1: each dimension's ladder, one at a time: first the whole ladders of the dimensions with
/// a known cost direction (the step, the solver's iteration count: the settings users turn first;
/// where the default passes, only their cheaper side), then the nearest rungs of every other
/// dimension before the further ones.
void ladder_phase(Walk& w, const std::vector<TuneDimension>& dims) {
  const bool default_passes = w.steps.front().pass;
  std::vector<Overrides> changes;
  for (const auto& d : dims)
    if (d.cost_direction != 0)
      for (const auto& v : d.ladder)
        if (!default_passes || (number_of(v) - d.default_value) * d.cost_direction < 0.0)
          changes.push_back({{d.key, v}});
  size_t depth = 0;
  for (const auto& d : dims) depth = std::max(depth, d.ladder.size());
  for (size_t k = 0; k < depth; ++k)
    for (const auto& d : dims)
      if (d.cost_direction == 0 && k < d.ladder.size()) changes.push_back({{d.key, d.ladder[k]}});
  w.batch("ladder", changes);
}

/// Phase 2: between two neighbouring values of one dimension of which one passed and the other
/// did not, their geometric mean (twice, each round halving the bracket).
void refine_phase(Walk& w, const std::vector<TuneDimension>& dims) {
  for (int round = 0; round < 2; ++round) {
    std::vector<Overrides> changes;
    for (const auto& d : dims) {
      if (d.kind == ParamKind::kChoice || !(d.default_value > 0.0)) continue;
      const auto line = w.line(d);
      for (size_t i = 0; i + 1 < line.size(); ++i) {
        if (line[i].second->pass == line[i + 1].second->pass) continue;
        if (const auto mid = in_range(d, std::sqrt(line[i].first * line[i + 1].first))) {
          const std::string text = value_text(d, *mid);
          if (text != value_text(d, line[i].first) && text != value_text(d, line[i + 1].first))
            changes.push_back({{d.key, text}});
        }
      }
    }
    w.batch("refine", changes);
  }
}

/// Phase 3, where nothing passed: the value that came closest in each dimension; the three
/// closest combined two at a time, then all of them together.
void combine_phase(Walk& w, const std::vector<TuneDimension>& dims) {
  std::vector<std::pair<double, std::pair<std::string, std::string>>> best;  // worst_ratio, (key, value)
  const double base = w.steps.front().worst_ratio;
  for (const auto& d : dims) {
    const TuneStep* top = nullptr;
    for (const TuneStep& s : w.steps)
      if (s.change.size() == 1 && s.change[0].first == d.key && s.worst_ratio < base &&
          (!top || s.worst_ratio < top->worst_ratio))
        top = &s;
    if (top) best.push_back({top->worst_ratio, top->change[0]});
  }
  std::stable_sort(best.begin(), best.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<Overrides> changes;
  for (size_t i = 0; i < best.size(); ++i)
    for (size_t j = i + 1; j < best.size() && j < 3; ++j) changes.push_back({best[i].second, best[j].second});
  if (best.size() > 2) {
    Overrides all;
    for (const auto& b : best) all.push_back(b.second);
    changes.push_back(all);
  }
  w.batch("combine", changes);
}

/// The cheapest passing step by the cost model (deterministic: the verdicts and the settings decide,
/// never the clock), then the fewest changes, then the walk's order.
std::optional<size_t> cheapest_pass(const std::vector<TuneStep>& steps) {
  std::optional<size_t> pick;
  for (size_t i = 0; i < steps.size(); ++i) {
    if (!steps[i].pass) continue;
    if (!pick) {
      pick = i;
      continue;
    }
    const TuneStep &s = steps[i], &p = steps[*pick];
    if (s.model_cost < p.model_cost || (s.model_cost == p.model_cost && s.change.size() < p.change.size())) pick = i;
  }
  return pick;
}

}  // namespace

std::string change_text(const Overrides& change) {
  if (change.empty()) return "defaults";
  std::string s;
  for (const auto& [k, v] : change) s += fmt::format("{}{}={}", s.empty() ? "" : ", ", k, v);
  return s;
}

std::vector<TuneDimension> tune_dimensions(const Scenario& s, const EngineInfo& e, std::vector<std::string>* left_out) {
  std::vector<TuneDimension> dims;
  for (const ParamSpec& p : s.params)
    if (p.key == "dt") {
      dims.push_back(numeric(p, kStepLadder));
      dims.back().cost_direction = -1;
    }
  for (const SettingSpec& k : e.knobs) {
    if (k.vehicle != s.vehicle) continue;
    if (k.kind == ParamKind::kChoice) {
      TuneDimension d{.key = k.key, .kind = k.kind, .default_text = k.default_text};
      for (const auto& c : k.choices)
        if (c != k.default_text) d.ladder.push_back(c);
      dims.push_back(d);
    } else if (k.kind == ParamKind::kVec2 || !(number_of(k.default_text) > 0.0) ||
               !std::isfinite(number_of(k.default_text))) {
      if (left_out)
        left_out->push_back(
            fmt::format("{} (default {}: no scale to search on a ladder of multiples)", k.key, k.default_text));
    } else {
      dims.push_back(numeric(k, kSettingLadder));
      if (k.role == SettingRole::kSolverIterations) dims.back().cost_direction = 1;
    }
  }
  return dims;
}

TuneResult tune(const std::vector<TuneDimension>& dims, const TuneDef& def, const TuneRunner& run) {
  Walk w{def, run, dims, {}, {}};
  w.batch("default", {Overrides{}});
  if (const Status st = w.steps.front().record.status; st == Status::kError || st == Status::kSkip) {
    TuneResult r{.walked = std::move(w.steps), .budget_runs = def.budget_runs, .stopped = to_string(st)};
    return r;
  }
  ladder_phase(w, dims);
  refine_phase(w, dims);
  TuneResult r{.budget_runs = def.budget_runs};
  r.answer = cheapest_pass(w.steps);
  if (!r.answer) {
    combine_phase(w, dims);
    r.answer = cheapest_pass(w.steps);
  }
  for (size_t i = 1; i < w.steps.size(); ++i)
    if (w.steps[i].worst_ratio < w.steps[r.closest].worst_ratio) r.closest = i;
  r.unmade = w.unmade;
  r.walked = std::move(w.steps);
  return r;
}

nlohmann::json TuneResult::to_json() const {
  nlohmann::json steps = nlohmann::json::array();
  for (const TuneStep& s : walked) {
    nlohmann::json change = nlohmann::json::object();
    for (const auto& [k, v] : s.change) change[k] = v;
    steps.push_back(
        {{"phase", s.phase},
         {"change", change},
         {"pass", s.pass},
         {"worst_ratio", std::isfinite(s.worst_ratio) ? nlohmann::json(s.worst_ratio) : nlohmann::json()},
         {"cost_ms_per_s", std::isfinite(s.cost_ms_per_s) ? nlohmann::json(s.cost_ms_per_s) : nlohmann::json()},
         {"model_cost", s.model_cost},
         {"record", encode_run(s.record)}});
  }
  return {{"budget_runs", budget_runs}, {"unmade", unmade},
          {"stopped", stopped},         {"answer", answer ? nlohmann::json(*answer) : nlohmann::json()},
          {"closest", closest},         {"walked", steps}};
}

}  // namespace liftcheck
