// A run's record as every reader takes it: typed and read-only, over the JSON it was written as
// (scenarios/scenario.cpp writes a metric, harness/runner.cpp a record; input/results_file.cpp
// checks a file read back). The rules of reading one live here and nowhere else: the error a
// tolerance is compared with, its ratio to the tolerance, whether it counts. As google/benchmark's
// reporters all read one `Run`, the sweeps, the diff, the pages, CI's files and `lookup` read this.
#pragma once

#include <array>
#include <cmath>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace liftcheck {

/// The error a tolerance is compared with: a relative tolerance compares rel_error, an absolute
/// one abs_error (Metric::compared_error, as written).
inline double compared_error_of(bool relative, double rel_error, double abs_error) {
  return relative ? rel_error : abs_error;
}

/// Error of a metric as a fraction of its tolerance: `error` over `tolerance`; with a `floor`
/// above 0, at most abs_error over the floor. A figure absent or null (how a NaN or infinite value
/// is written) is passed as infinite.
double metric_ratio(double error, double tolerance, double abs_error, double floor);

/// The fields of a metric that a baseline keeps, in the order written.
inline constexpr std::array<const char*, 9> kBaselineMetricFields{
    "expected", "measured", "abs_error", "rel_error", "tolerance", "tolerance_kind", "floor", "pass", "informational"};

/// One metric of a record (or of a sweep's point, which keeps a metric's figures).
class MetricView {
 public:
  explicit MetricView(const nlohmann::json& m) : m_(&m) {}

  /// Its tolerance is relative ("tolerance_kind": "rel").
  bool relative() const { return m_->is_object() && m_->value("tolerance_kind", "abs") == "rel"; }
  double expected() const { return number("expected"); }    ///< NaN when null or absent
  double measured() const { return number("measured"); }    ///< NaN when null or absent
  double abs_error() const { return number("abs_error"); }  ///< NaN when null or absent
  double rel_error() const { return number("rel_error"); }  ///< NaN when null or absent
  double tolerance() const { return number("tolerance"); }  ///< NaN when null or absent
  double floor() const { return number_or("floor", 0.0); }  ///< 0 when it has none
  bool pass() const { return m_->value("pass", true); }
  bool counted() const { return !m_->value("informational", false); }  ///< not shown only
  std::string unit() const { return m_->value("unit", std::string()); }
  std::string tolerance_kind() const { return m_->value("tolerance_kind", std::string()); }

  /// rel_error for a relative tolerance, abs_error otherwise; NaN when null or absent.
  double compared_error() const { return compared_error_of(relative(), rel_error(), abs_error()); }
  /// The compared error as written: a number, or null for a NaN or infinite one.
  const nlohmann::json& written_compared_error() const { return raw(relative() ? "rel_error" : "abs_error"); }
  /// The compared error over the tolerance (metric_ratio; a null figure counts as infinite).
  double ratio() const;
  /// The figures a sweep's point keeps of it.
  nlohmann::json point_figures() const;
  /// A field as written (to print a number exactly as the file has it).
  const nlohmann::json& raw(const char* key) const;

 private:
  double number(const char* key) const { return number_or(key, NAN); }
  double number_or(const char* key, double none) const;
  const nlohmann::json* m_;
};

/// One record: its key, its verdict and its metrics.
class RecordView {
 public:
  explicit RecordView(const nlohmann::json& r) : r_(&r) {}

  std::string scenario() const { return r_->value("scenario", std::string()); }
  std::string engine() const { return r_->value("engine", std::string()); }
  /// Its verdict, or its status in files written before verdicts.
  std::string verdict() const;
  /// Whether it has a metric of that name.
  bool has(const std::string& name) const;
  /// The metric of that name (has(name) first).
  MetricView metric(const std::string& name) const { return MetricView((*r_)["metrics"][name]); }
  /// Its metrics: name and view, in name order.
  template <class F>
  void each_metric(F&& f) const {
    if (!r_->contains("metrics") || !(*r_)["metrics"].is_object()) return;
    for (const auto& [name, m] : (*r_)["metrics"].items()) f(name, MetricView(m));
  }
  /// Its metrics, worst first (the largest ratio to tolerance), in name order on ties.
  std::vector<std::pair<std::string, MetricView>> metrics_worst_first() const;

 private:
  const nlohmann::json* r_;
};

}  // namespace liftcheck
