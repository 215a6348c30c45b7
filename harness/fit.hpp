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

}  // namespace liftcheck
