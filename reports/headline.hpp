// The figures the summary shows: a run's headline (its scenario's declared metric, the engine's
// own error) and, for a run that is not as expected, the metric that failed worst.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>

namespace liftcheck {

struct Figure {
  std::string metric;        ///< the metric the figure comes from
  double value = 0;          ///< the shown value, in `unit`
  std::string unit;          ///< "" (a ratio), "mm", "µm/s", "steps", or the metric's own
  double ratio = 0;          ///< its compared error over its tolerance (below 1 passes)
  std::string text() const;  ///< "1.1e-7", "257 µm/s"
};

/// The scenario's headline definition as results["scenarios"] records it; null when it has none.
nlohmann::json headline_def(const nlohmann::json& results, const std::string& scenario);

/// The run's headline figure: the largest compared error among the declared metrics it measured
/// (informational ones are skipped), scaled as declared. None when the run measured none of them.
std::optional<Figure> headline_figure(const nlohmann::json& run, const nlohmann::json& def);

/// The counted metric out of tolerance by the largest ratio, its compared error in the metric's unit.
std::optional<Figure> worst_failing(const nlohmann::json& run);

/// A number in two significant digits, short: "0", "0.65", "21", "257", "6.8e-4", "1.5e9".
std::string short_number(double v);

}  // namespace liftcheck
