// The braked slide's closed forms (models/slide.hpp) against a block stepped in time: each step
// adds gravity's pull along the plane, then friction's impulse, bounded as the law bounds it
// (the cone: the speed cut by at most mu g cos(slope) dt along the velocity; the axis pyramid:
// each axis's speed cut apart), as an engine's velocity-level contact solver does.
#include <gtest/gtest.h>

#include <cmath>

#include "models/slide.hpp"

namespace liftcheck::slide {
namespace {

SlideAccel stepped(const SlideDef& d, Law law) {
  const double dt = 1e-4, T = 2.0;
  const Eigen::Vector2d down(std::cos(d.yaw_rad), std::sin(d.yaw_rad));
  const double grip_dv = d.mu * d.g_mps2 * std::cos(d.slope_rad) * dt;
  Eigen::Vector2d v = Eigen::Vector2d::Zero();
  for (int k = 0; k < static_cast<int>(T / dt); ++k) {
    v += d.g_mps2 * std::sin(d.slope_rad) * dt * down;
    if (law == Law::kCone) {
      const double s = v.norm();
      v *= s > grip_dv ? (s - grip_dv) / s : 0.0;
    } else {
      for (int i = 0; i < 2; ++i) v[i] = std::copysign(std::max(0.0, std::abs(v[i]) - grip_dv), v[i]);
    }
  }
  const Eigen::Vector2d a = v / T;
  return {a.dot(down), down.x() * a.y() - down.y() * a.x()};
}

TEST(Slide, ClosedFormsMatchASteppedBlock) {
  for (Law law : {Law::kCone, Law::kAxisPyramid})
    for (double yaw : {0.0, 0.3, 0.6981317, M_PI / 4, 1.2, -0.9, 2.5})
      for (double mu : {0.1, 0.3, 0.45}) {
        const SlideDef d{.g_mps2 = 9.81, .slope_rad = 0.5, .mu = mu, .yaw_rad = yaw};
        const SlideAccel c = slide_accel(d, law), s = stepped(d, law);
        EXPECT_NEAR(c.along_mps2, s.along_mps2, 1e-9) << "law " << int(law) << " yaw " << yaw << " mu " << mu;
        EXPECT_NEAR(c.across_mps2, s.across_mps2, 1e-9) << "law " << int(law) << " yaw " << yaw << " mu " << mu;
      }
}

// The figures the yawed slide's scenario judges: 40 degrees, slope 0.5 rad, mu 0.3. The cone
// slides straight down at g (sin - mu cos) = 2.1198 m/s^2; the pyramid at half of that and
// sideways (1.0645 along, 0.318 across).
TEST(Slide, ThePyramidHalvesTheYawedSlideAndTurnsIt) {
  const SlideDef d{.g_mps2 = 9.81, .slope_rad = 0.5, .mu = 0.3, .yaw_rad = 40.0 * M_PI / 180.0};
  const SlideAccel cone = slide_accel(d, Law::kCone), box = slide_accel(d, Law::kAxisPyramid);
  EXPECT_NEAR(cone.along_mps2, 9.81 * (std::sin(0.5) - 0.3 * std::cos(0.5)), 1e-12);
  EXPECT_EQ(cone.across_mps2, 0.0);
  EXPECT_NEAR(box.along_mps2, 1.06454, 1e-5);
  EXPECT_NEAR(box.across_mps2, -0.31834, 1e-5);
  // Along an axis, or halfway between the axes, the pyramid slides straight down; along an axis
  // it matches the cone.
  const SlideAccel on_axis = slide_accel({.yaw_rad = 0.0}, Law::kAxisPyramid);
  EXPECT_NEAR(on_axis.along_mps2, slide_accel({.yaw_rad = 0.0}, Law::kCone).along_mps2, 1e-12);
  EXPECT_NEAR(slide_accel({.yaw_rad = M_PI / 4}, Law::kAxisPyramid).across_mps2, 0.0, 1e-12);
}

}  // namespace
}  // namespace liftcheck::slide
