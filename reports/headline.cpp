#include "reports/headline.hpp"

#include <cmath>
#include <fmt/format.h>

#include "scenarios/scenario.hpp"

namespace liftcheck {

namespace {

using json = nlohmann::json;

/// The error a metric's tolerance is compared with (relative or absolute, by its kind).
double compared_error(const json& m) {
  const bool rel = m.value("tolerance_kind", "abs") == "rel";
  const json& e = m[rel ? "rel_error" : "abs_error"];
  return e.is_number() ? e.get<double>() : NAN;
}

double ratio_of(const json& m) {
  const double err = compared_error(m), tol = m.value("tolerance", 0.0);
  double r = tol > 0 ? err / tol : (err > 0 ? INFINITY : 0.0);
  if (m.value("floor", 0.0) > 0.0) r = std::min(r, m.value("abs_error", 0.0) / m["floor"].get<double>());
  return r;
}

bool counted(const json& m) { return !m.value("informational", false); }

}  // namespace

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

json headline_def(const json& results, const std::string& scenario) {
  for (const auto& s : results.value("scenarios", json::array()))
    if (s.value("name", "") == scenario && s.contains("headline") && s["headline"].is_object()) return s["headline"];
  if (const Scenario* s = find_scenario(scenario); s && !s->headline.metrics.empty()) return s->headline.to_json();
  return nullptr;
}

std::optional<Figure> headline_figure(const json& run, const json& def) {
  if (!def.is_object() || !run.contains("metrics") || !run["metrics"].is_object()) return std::nullopt;
  std::optional<Figure> best;
  double best_err = -1.0;
  for (const auto& name : def.value("metrics", json::array())) {
    const std::string n = name.get<std::string>();
    if (!run["metrics"].contains(n) || !counted(run["metrics"][n])) continue;
    const json& m = run["metrics"][n];
    double err = compared_error(m);
    if (!(err > best_err) && best) continue;
    best_err = err;
    Figure f{n, err * def.value("scale", 1.0), def.value("unit", std::string()), ratio_of(m)};
    if (def.value("per_step", false)) {
      const double dt = run.value("params", json::object()).value("dt", 0.0);
      f.value = dt > 0 ? m.value("abs_error", 0.0) / dt : NAN;
    }
    best = f;
  }
  return best;
}

std::optional<Figure> worst_failing(const json& run) {
  std::optional<Figure> worst;
  const json metrics = run.value("metrics", json::object());  // items() must not outlive it
  for (const auto& [name, m] : metrics.items()) {
    if (m.value("pass", true) || !counted(m)) continue;
    const double r = ratio_of(m);
    if (worst && !(r > worst->ratio)) continue;
    const bool rel = m.value("tolerance_kind", "abs") == "rel";
    worst = Figure{name, compared_error(m), rel ? "" : m.value("unit", std::string()), r};
  }
  return worst;
}

}  // namespace liftcheck
