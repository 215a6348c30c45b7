#pragma once
// A braked car on a slope steeper than its friction angle slides as a block: Coulomb's law, and
// the per-axis friction "pyramid" that many engines solve instead of it.
#include <Eigen/Dense>

namespace liftcheck::slide {

/// The friction law of every contact, its bound on the friction force f against the normal load N.
enum class Law {
  kCone,         ///< Coulomb's law: |f| <= mu N, opposing the slip whatever its direction
  kAxisPyramid,  ///< per axis of the contact frame: |f_roll| <= mu N and |f_axle| <= mu N, each apart
};

/// The slide of a rigid block (the braked car) from rest on a plane tilted by slope_rad, its
/// contacts' friction frames turned with the car: the fall line makes yaw_rad with the car's
/// axles, towards its heading.
struct SlideDef {
  double g_mps2 = 9.81;
  double slope_rad = 0.5;
  double mu = 0.3;
  double yaw_rad = 0.0;
};

/// Its constant acceleration, m/s^2, along the fall line (positive downhill) and across it
/// (positive to the fall line's left, towards the car's heading when yaw_rad > 0).
struct SlideAccel {
  double along_mps2 = 0.0;
  double across_mps2 = 0.0;
  /// The same acceleration in the car's frame: x along its axles, y along its heading (the fall
  /// line is (cos(yaw), sin(yaw)) there).
  Eigen::Vector2d a_car_mps2 = Eigen::Vector2d::Zero();
};

/// The slide under `law`. The cone: g (sin(slope) - mu cos(slope)) straight down, where positive
/// (zero where friction holds the block). The axis pyramid: each axis of the contact frame apart,
/// the weight's part g sin(slope) d_i along it less mu g cos(slope) (the summed normal loads are
/// the weight's normal part), where positive; the block slides along neither axis's friction
/// bound alone, so it leaves the fall line unless the fall line lies along an axis or halfway
/// between them.
SlideAccel slide_accel(const SlideDef& def, Law law);

}  // namespace liftcheck::slide
