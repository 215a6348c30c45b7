#include "reports/headline.hpp"

#include <cmath>
#include <fmt/format.h>

#include "input/record_view.hpp"

namespace liftcheck {

namespace {

using json = nlohmann::json;

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
  return nullptr;
}

std::optional<Figure> headline_figure(const json& run, const json& def) {
  if (!def.is_object()) return std::nullopt;
  const RecordView record(run);
  std::optional<Figure> best;
  double best_err = -1.0;
  for (const auto& name : def.value("metrics", json::array())) {
    const std::string n = name.get<std::string>();
    if (!record.has(n) || !record.metric(n).counted()) continue;
    const MetricView m = record.metric(n);
    double err = m.compared_error();
    if (!(err > best_err) && best) continue;
    best_err = err;
    Figure f{n, err * def.value("scale", 1.0), def.value("unit", std::string()), m.ratio()};
    if (def.value("per_step", false)) {
      const double dt = run.value("params", json::object()).value("dt", 0.0);
      f.value = dt > 0 ? m.abs_error() / dt : NAN;
    }
    best = f;
  }
  return best;
}

std::optional<Figure> worst_failing(const json& run) {
  std::optional<Figure> worst;
  RecordView(run).each_metric([&](const std::string& name, const MetricView& m) {
    if (m.pass() || !m.counted()) return;
    const double r = m.ratio();
    if (worst && !(r > worst->ratio)) return;
    worst = Figure{name, m.compared_error(), m.relative() ? "" : m.unit(), r};
  });
  return worst;
}

}  // namespace liftcheck
