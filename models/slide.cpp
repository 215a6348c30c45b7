#include "models/slide.hpp"

#include <algorithm>
#include <cmath>

namespace liftcheck::slide {

SlideAccel slide_accel(const SlideDef& d, Law law) {
  const double drive = d.g_mps2 * std::sin(d.slope_rad), grip = d.mu * d.g_mps2 * std::cos(d.slope_rad);
  // The fall line in the car's frame: x along the axles, y along the heading.
  const Eigen::Vector2d down(std::cos(d.yaw_rad), std::sin(d.yaw_rad));
  if (law == Law::kCone) return {std::max(0.0, drive - grip), 0.0, std::max(0.0, drive - grip) * down};
  Eigen::Vector2d a;
  for (int i = 0; i < 2; ++i) a[i] = std::copysign(std::max(0.0, drive * std::abs(down[i]) - grip), down[i]);
  return {a.dot(down), down.x() * a.y() - down.y() * a.x(), a};
}

}  // namespace liftcheck::slide
