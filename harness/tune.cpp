#include "harness/tune.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>
#include <set>
#include <span>

namespace liftcheck {

namespace {

/// The first phase's multipliers of a default, nearest first: a setting's on powers of 4 (an
/// iteration count from a sixteenth to 64 times, a stiffness or an accuracy two decades either
/// way); the step's on powers of 2 (dt from a quarter to 8 times: a step 16 times shorter costs 16
/// times the default and is no setting a user runs).
constexpr double kSettingLadder[] = {0.25, 4.0, 1.0 / 16.0, 16.0, 64.0};
constexpr double kStepLadder[] = {2.0, 0.5, 4.0, 0.25, 8.0};

std::string value_text(const TuneDimension& d, double v) {
  return d.kind == ParamKind::kInteger ? fmt::format("{}", static_cast<long long>(std::llround(v)))
                                       : fmt::format("{:.4g}", v);
}

/// `v` within the dimension's range (an integer rounded), or nullopt outside it.
std::optional<double> in_range(const TuneDimension& d, double v) {
  if (d.kind == ParamKind::kInteger) v = std::round(v);
  if (!(v >= d.min && v <= d.max) || (d.min_exclusive && v <= d.min)) return std::nullopt;
  return v;
}

TuneDimension numeric(const ParamSpec& p, std::span<const double> ladder) {
  TuneDimension d{.key = p.key,
                  .kind = p.kind,
                  .default_text = p.default_text,
                  .min = p.min,
                  .max = p.max,
                  .min_exclusive = p.min_exclusive};
  d.default_value = std::stod(p.default_text);
  std::set<std::string> seen{value_text(d, d.default_value)};
  for (const double m : ladder)
    if (const auto v = in_range(d, d.default_value * m))
      if (seen.insert(value_text(d, *v)).second) d.ladder.push_back(value_text(d, *v));
  return d;
}

double number_of(const std::string& text) { return std::stod(text); }

double cost_of(const nlohmann::json& r) {
  const double sim = r.value("simulated_s", 0.0);
  const double spent = r.contains("engine_s") && r["engine_s"].is_number()
                           ? r["engine_s"].get<double>()
                           : r.value("wall_s", std::numeric_limits<double>::quiet_NaN());
  return sim > 0.0 ? 1e3 * spent / sim : NAN;
}

TuneStep step_of(std::string phase, Overrides change, nlohmann::json record) {
  TuneStep s{.phase = std::move(phase), .change = std::move(change), .record = std::move(record)};
  s.pass = s.record.value("status", "") == "pass";
  if (s.record.contains("worst_ratio") && s.record["worst_ratio"].is_number())
    s.worst_ratio = s.record["worst_ratio"].get<double>();
  if (s.record.value("status", "") == "error") s.worst_ratio = std::numeric_limits<double>::infinity();
  s.cost_ms_per_s = cost_of(s.record);
  return s;
}

/// The walk so far, and the budget left; runs each batch as one (in parallel where the runner can).
struct Walk {
  const TuneDef& def;
  const TuneRunner& run;
  std::vector<TuneStep> steps;
  std::set<std::string> tried;

  int left() const { return def.budget_runs - static_cast<int>(steps.size()); }
  void batch(const std::string& phase, std::vector<Overrides> changes) {
    std::vector<Overrides> fresh;
    for (auto& c : changes) {
      std::sort(c.begin(), c.end());
      if (static_cast<int>(fresh.size()) < left() && tried.insert(change_text(c)).second) fresh.push_back(c);
    }
    if (fresh.empty()) return;
    std::vector<nlohmann::json> records = run(fresh);
    for (size_t i = 0; i < fresh.size(); ++i) steps.push_back(step_of(phase, fresh[i], std::move(records.at(i))));
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

/// Phase 1: each dimension's ladder, one at a time, the nearest rungs of every dimension first.
void ladder_phase(Walk& w, const std::vector<TuneDimension>& dims) {
  std::vector<Overrides> changes;
  size_t depth = 0;
  for (const auto& d : dims) depth = std::max(depth, d.ladder.size());
  for (size_t k = 0; k < depth; ++k)
    for (const auto& d : dims)
      if (k < d.ladder.size()) changes.push_back({{d.key, d.ladder[k]}});
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

/// Phase 3, where nothing passed: the values that came closest in each dimension, combined two
/// at a time (the two closest first) and all together.
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

/// A passing step that changes one dimension with a known cost direction, beaten along it by
/// another passing step (a longer step, fewer iterations): no candidate, whatever the clock said.
bool dominated(const std::vector<TuneStep>& steps, size_t i, const std::vector<TuneDimension>& dims) {
  const TuneStep& s = steps[i];
  if (s.change.size() != 1) return false;
  for (const TuneDimension& d : dims) {
    if (d.key != s.change[0].first || d.cost_direction == 0) continue;
    const double v = number_of(s.change[0].second);
    for (const TuneStep& o : steps) {
      const double ov = o.change.empty()                                     ? d.default_value
                        : o.change.size() == 1 && o.change[0].first == d.key ? number_of(o.change[0].second)
                                                                             : NAN;
      if (o.pass && (ov - v) * d.cost_direction < 0.0) return true;
    }
  }
  return false;
}

/// The cheapest passing step: along a dimension with a known cost direction the verdicts decide;
/// between the candidates left, measured costs within def.cost_tie of the cheapest are a tie,
/// broken by the fewest changes, then the walk's order.
std::optional<size_t> cheapest_pass(const std::vector<TuneStep>& steps, const TuneDef& def,
                                    const std::vector<TuneDimension>& dims) {
  std::vector<size_t> candidates;
  for (size_t i = 0; i < steps.size(); ++i)
    if (steps[i].pass && !dominated(steps, i, dims)) candidates.push_back(i);
  double least = std::numeric_limits<double>::infinity();
  for (const size_t i : candidates) least = std::min(least, steps[i].cost_ms_per_s);
  std::optional<size_t> pick;
  for (const size_t i : candidates) {
    const bool tie = steps[i].cost_ms_per_s <= least * (1.0 + def.cost_tie) || !std::isfinite(least);
    if (tie && (!pick || steps[i].change.size() < steps[*pick].change.size())) pick = i;
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
    } else if (k.kind == ParamKind::kVec2 || !(std::stod(k.default_text) > 0.0)) {
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
  Walk w{def, run, {}, {}};
  w.batch("default", {Overrides{}});
  ladder_phase(w, dims);
  refine_phase(w, dims);
  TuneResult r{.budget_runs = def.budget_runs};
  r.answer = cheapest_pass(w.steps, def, dims);
  if (!r.answer) {
    combine_phase(w, dims);
    refine_phase(w, dims);
    r.answer = cheapest_pass(w.steps, def, dims);
  }
  for (size_t i = 1; i < w.steps.size(); ++i)
    if (w.steps[i].worst_ratio < w.steps[r.closest].worst_ratio) r.closest = i;
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
         {"record", s.record}});
  }
  return {{"budget_runs", budget_runs},
          {"answer", answer ? nlohmann::json(*answer) : nlohmann::json()},
          {"closest", closest},
          {"walked", steps}};
}

}  // namespace liftcheck
