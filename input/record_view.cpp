#include "input/record_view.hpp"

#include <algorithm>

namespace liftcheck {

double metric_ratio(double error, double tolerance, double abs_error, double floor) {
  double r = tolerance > 0 ? error / tolerance : (error > 0 ? INFINITY : 0.0);
  if (floor > 0.0) r = std::min(r, abs_error / floor);
  return r;
}

double MetricView::number_or(const char* key, double none) const {
  if (!m_->is_object()) return none;
  const auto it = m_->find(key);
  return it != m_->end() && it->is_number() ? it->get<double>() : none;
}

double MetricView::ratio() const {
  const auto inf = [](double v) { return std::isnan(v) ? INFINITY : v; };
  return metric_ratio(inf(compared_error()), number_or("tolerance", INFINITY), inf(abs_error()), floor());
}

nlohmann::json MetricView::point_figures() const {
  return {{"expected", raw("expected")},
          {"measured", raw("measured")},
          {"rel_error", raw("rel_error")},
          {"abs_error", raw("abs_error")},
          {"pass", raw("pass")}};
}

const nlohmann::json& MetricView::raw(const char* key) const {
  static const nlohmann::json null;
  if (!m_->is_object()) return null;
  const auto it = m_->find(key);
  return it != m_->end() ? *it : null;
}

std::vector<std::pair<std::string, MetricView>> RecordView::metrics_worst_first() const {
  std::vector<std::pair<std::string, MetricView>> out;
  each_metric([&](const std::string& name, const MetricView& m) { out.emplace_back(name, m); });
  std::stable_sort(out.begin(), out.end(),
                   [](const auto& a, const auto& b) { return a.second.ratio() > b.second.ratio(); });
  return out;
}

std::string RecordView::verdict() const {
  const auto it = r_->find("verdict");
  return it != r_->end() && it->is_string() ? it->get<std::string>() : r_->value("status", std::string());
}

bool RecordView::has(const std::string& name) const {
  return r_->contains("metrics") && (*r_)["metrics"].is_object() && (*r_)["metrics"].contains(name);
}

}  // namespace liftcheck
