#include "input/standing.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>

namespace liftcheck {

Summary summarize(const SuiteResults& results) {
  Summary s;
  for (const RunResult& r : results.runs) {
    ++s.total;
    switch (r.verdict()) {
      case Verdict::kPass:
        ++s.pass;
        break;
      case Verdict::kKnownFailure:
        ++s.known;
        break;
      case Verdict::kUnexpectedPass:
        ++s.unexpected_pass;
        break;
      case Verdict::kFail:
        ++s.fail;
        break;
      case Verdict::kError:
        ++s.error;
        break;
      case Verdict::kSkip:
        ++s.skip;
        break;
    }
    s.runs_unexpected += r.as_expected() ? 0 : 1;
  }
  for (const GateRef& g : gates_of(results)) {
    ++s.sweep_gates;
    s.sweep_gates_failed += g.gate->pass ? 0 : 1;
  }
  if (results.baseline) s.baseline_problems = results.baseline->diff.problems();
  return s;
}

std::vector<GateRef> gates_of(const SuiteResults& results) {
  std::vector<GateRef> out;
  for (const Sweep& sw : results.sweeps)
    for (const SweepEngine& e : sw.engines) out.push_back({sw.name, e.engine, &e.gate});
  if (results.outcomes)
    for (const OutcomeEngine& e : results.outcomes->engines) out.push_back({results.outcomes->name, e.engine, &e.gate});
  return out;
}

std::string times_text(double ratio) { return (std::isinf(ratio) ? "∞" : short_number(ratio)) + "×"; }

std::string Deciding::text() const {
  if (metric.empty()) return "";
  if (std::isnan(error)) return fmt::format("not measured ({})", metric);
  if (std::isinf(ratio))
    return fmt::format("{}{} against a zero tolerance ({})", short_number(error), unit.empty() ? "" : " " + unit,
                       metric);
  return fmt::format("{} ({})", times_text(ratio), metric);
}

Deciding deciding_of(const RunResult& r) {
  Deciding d;
  for (const Metric& m : r.metrics) {
    if (!m.counted()) continue;
    const double ratio = m.ratio();
    if (std::isfinite(ratio)) d.finite = std::max(d.finite, ratio);
    if (m.pass) continue;
    if (!std::isfinite(ratio)) d.zero_tolerance = true;
    const bool better = d.metric.empty() || (std::isfinite(ratio) && (!std::isfinite(d.ratio) || ratio > d.ratio));
    if (better)
      d.metric = m.name, d.ratio = ratio, d.error = m.compared_error(),
      d.unit = m.kind == TolKind::kRelative ? "" : m.unit;
  }
  return d;
}

double standing_rank(const RunResult& r, const Deciding& d) {
  if (r.status == Status::kError) return 0.0;
  return d.finite > 1.0 || !d.zero_tolerance ? d.finite : 0.0;
}

std::string Standing::worst_text() const {
  if (!worst) return "";
  if (worst->status == Status::kError) return fmt::format("an error (listed) in {}", worst->scenario);
  if (!std::isfinite(worst_figure.ratio))
    return fmt::format("{} against a zero tolerance in {} {}", short_number(worst_figure.error), worst->scenario,
                       worst_figure.metric);
  return fmt::format("{} {} {}", times_text(worst_figure.ratio), worst->scenario, worst_figure.metric);
}

std::string Standing::worst_short_text() const {
  if (!worst || worst->status == Status::kError || !std::isfinite(worst_figure.ratio)) return worst_text();
  return times_text(worst_figure.ratio) + " " + worst->scenario;
}

std::string Standing::counts_text() const {
  std::string t = fmt::format("{} pass, {} known, {} skip", pass, known, skip);
  if (unexpected > 0) t += fmt::format(", {} not as expected", unexpected);
  return t;
}

std::vector<Standing> standings(const SuiteResults& results) {
  std::vector<Standing> out;
  for (const EngineContext& e : results.context.engines) {
    Standing s;
    s.engine = e.name;
    s.reference = e.is_reference;
    double worst_rank = -1.0;
    for (const RunResult& r : results.runs) {
      if (r.engine != e.name) continue;
      ++s.runs;
      if (!r.as_expected()) {
        ++s.unexpected, s.unexpected_in.push_back(r.scenario);
        continue;
      }
      if (r.verdict() == Verdict::kPass) ++s.pass;
      if (r.verdict() == Verdict::kSkip) ++s.skip;
      if (r.verdict() != Verdict::kKnownFailure) continue;
      ++s.known;
      if (r.negative_control) {
        ++s.controls;
        continue;
      }
      const Deciding d = deciding_of(r);
      const double rank = standing_rank(r, d);
      if (rank > worst_rank) worst_rank = rank, s.worst = &r, s.worst_figure = d;
    }
    out.push_back(std::move(s));
  }
  return out;
}

std::string short_number(double v) {
  if (std::isnan(v)) return "nan";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  const double a = std::abs(v);
  if (a == 0.0) return "0";
  if (a >= 10 && a < 1e4) return fmt::format("{:.0f}", v);
  if (a >= 1e-2 && a < 10) return fmt::format("{:.2g}", v);
  std::string s = fmt::format("{:.1e}", v);  // "6.8e-04" -> "6.8e-4", "1.5e+09" -> "1.5e9"
  const auto e = s.find('e');
  std::string mant = s.substr(0, e), exp = s.substr(e + 1);
  const bool neg = exp[0] == '-';
  exp = exp.substr(1);
  while (exp.size() > 1 && exp[0] == '0') exp.erase(0, 1);
  return mant + "e" + (neg ? "-" : "") + exp;
}

std::string Figure::text() const { return unit.empty() ? short_number(value) : short_number(value) + " " + unit; }

std::optional<Figure> headline_figure(const RunResult& r, const ScenarioInfo* scenario) {
  if (!scenario || scenario->headline_metrics.empty()) return std::nullopt;
  std::optional<Figure> best;
  double best_err = -1.0;
  for (const std::string& name : scenario->headline_metrics) {
    const Metric* m = r.metric(name);
    if (!m || !m->counted()) continue;
    const double err = m->compared_error();
    if (!(err > best_err) && best) continue;
    best_err = err;
    Figure f{name, err * scenario->headline_scale, scenario->headline_unit, m->ratio()};
    if (scenario->headline_per_step) {
      const double dt = r.params.has("dt") ? r.params.num("dt") : 0.0;
      f.value = dt > 0 ? m->abs_error / dt : NAN;
    }
    best = f;
  }
  return best;
}

std::optional<Figure> worst_failing(const RunResult& r) {
  std::optional<Figure> worst;
  for (const Metric* m : r.metrics_worst_first())
    if (!m->pass && m->counted()) {
      worst = Figure{m->name, m->compared_error(), m->kind == TolKind::kRelative ? "" : m->unit, m->ratio()};
      break;
    }
  return worst;
}

}  // namespace liftcheck
