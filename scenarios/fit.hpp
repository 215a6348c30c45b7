// Geometric fits applied to engine traces.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace liftcheck {

struct CircleFit {
  double cx_m, cy_m, radius_m;
  double rms_residual_m;  ///< root mean square distance of the points from the fitted circle
};

/// Least-squares circle through points: algebraic (Kasa) start, then Gauss-Newton on the
/// geometric distances. Needs at least 3 points not on one line (throws std::invalid_argument).
CircleFit fit_circle(const std::vector<Eigen::Vector2d>& points);

/// Least-squares slope of log y against log x (power-law exponent); x, y > 0, at least 2 points.
double loglog_slope(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace liftcheck
