#include "scenarios/fit.hpp"

#include <cmath>
#include <stdexcept>

namespace liftcheck {

CircleFit fit_circle(const std::vector<Eigen::Vector2d>& points) {
  const auto n = static_cast<Eigen::Index>(points.size());
  if (n < 3) throw std::invalid_argument("circle fit needs at least 3 points");
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const auto& p : points) mean += p;
  mean /= static_cast<double>(n);

  // Kasa: x^2 + y^2 + D x + E y + F = 0 in coordinates centred on the mean.
  Eigen::MatrixXd A(n, 3);
  Eigen::VectorXd b(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Eigen::Vector2d p = points[static_cast<std::size_t>(i)] - mean;
    A.row(i) << p.x(), p.y(), 1.0;
    b[i] = -p.squaredNorm();
  }
  const Eigen::Vector3d k = A.colPivHouseholderQr().solve(b);
  Eigen::Vector2d c(-k[0] / 2.0, -k[1] / 2.0);
  double r = std::sqrt(std::max(0.0, c.squaredNorm() - k[2]));
  if (!std::isfinite(r) || r == 0.0) throw std::invalid_argument("points do not determine a circle");

  // Gauss-Newton on r_i = |p_i - c| - r.
  for (int it = 0; it < 50; ++it) {
    Eigen::MatrixXd J(n, 3);
    Eigen::VectorXd res(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const Eigen::Vector2d d = points[static_cast<std::size_t>(i)] - mean - c;
      const double dist = d.norm();
      res[i] = dist - r;
      J.row(i) << -d.x() / dist, -d.y() / dist, -1.0;
    }
    const Eigen::Vector3d step = J.colPivHouseholderQr().solve(-res);
    c += step.head<2>();
    r += step[2];
    if (step.norm() < 1e-15 * (1.0 + r)) break;
  }
  double ss = 0.0;
  for (const auto& p : points) ss += std::pow((p - mean - c).norm() - r, 2);
  return {c.x() + mean.x(), c.y() + mean.y(), r, std::sqrt(ss / static_cast<double>(n))};
}

double loglog_slope(const std::vector<double>& x, const std::vector<double>& y) {
  if (x.size() != y.size() || x.size() < 2) throw std::invalid_argument("log-log fit needs at least 2 (x, y) pairs");
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace liftcheck
