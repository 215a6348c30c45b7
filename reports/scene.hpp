// An engine-independent scene, in world metres (z up), and the camera that looks at it. Scene
// building (reports/scene_build) is separate from drawing (reports/gl_render).
#pragma once

#include <Eigen/Dense>
#include <string>
#include <vector>

namespace liftcheck::render {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

struct Color {
  float r = 0, g = 0, b = 0, a = 1;
};

namespace colors {
inline constexpr Color kUnknown{0.50f, 0.50f, 0.50f, 1.0f};  ///< a configuration without a colour
inline constexpr Color kGround{0.97f, 0.97f, 0.95f, 1.0f};
inline constexpr Color kGrid{0.82f, 0.82f, 0.80f, 1.0f};
inline constexpr Color kGridMajor{0.65f, 0.65f, 0.63f, 1.0f};
inline constexpr Color kContact{0.85f, 0.05f, 0.05f, 1.0f};
}  // namespace colors

/// "#rrggbb" (a configuration's colour, EngineInfo::color) as a Color; kUnknown if malformed.
Color color_from_hex(const std::string& hex);

struct Polyline {
  std::vector<Vec2> points;
  Color color;
  float width_px = 2.0f;
  bool dashed = false;
};

/// A circle on the ground: outline, fill, or both.
struct Circle {
  Vec2 centre;
  double radius_m;
  Color edge;
  Color fill{0, 0, 0, 0};  ///< alpha 0: no fill
  float width_px = 2.0f;
  bool dashed = false;
};

/// An upright cylinder standing on the ground (a disk vehicle).
struct Puck {
  Vec2 centre;
  double radius_m, height_m;
  Color color;
};

/// A wheel of radius R rolling on the ground: axle horizontal, centre at height R. Its tread has
/// alternating coloured segments and its sides carry spokes, so the rolling angle shows.
struct Wheel {
  Vec2 centre;  ///< below the axle centre, on the ground
  double radius_m, width_m;
  double heading_rad;  ///< rolling direction
  double spin_rad;     ///< rolling angle alpha
  Color tyre, spokes;
};

/// A box resting at height z0 (chassis, axles, tie rod).
struct Box {
  Vec2 centre;
  double heading_rad, length_m, width_m, z0_m, height_m;
  Color color;
};

struct Arrow {
  Vec2 from, to;
  Color color;
  float width_px = 3.0f;
};

/// A cross marking a point (first contact).
struct Marker {
  Vec2 at;
  double size_m;
  Color color;
};

/// Text at a world point (anchored left) or at pixel coordinates from the top-left.
struct Label {
  std::string text;  ///< UTF-8
  Vec2 at;
  bool screen = false;
  float size_px = 16.0f;
  Color color{0.1f, 0.1f, 0.1f, 1.0f};
};

struct Camera {
  enum class Kind { kTopDown, kPerspective } kind = Kind::kTopDown;
  Vec2 centre = Vec2::Zero();                        ///< top-down: centre of the view
  double half_height_m = 5.0;                        ///< top-down: half the visible height
  Vec3 eye = Vec3(0, -8, 6), target = Vec3::Zero();  ///< perspective
  double fov_y_deg = 40.0;
};

struct Scene {
  int width_px = 720, height_px = 540;
  Camera camera;
  double grid_step_m = 1.0;  ///< 0: no grid
  bool scale_bar = true;     ///< top-down only
  std::vector<Polyline> lines;
  std::vector<Circle> circles;
  std::vector<Puck> pucks;
  std::vector<Wheel> wheels;
  std::vector<Box> boxes;
  std::vector<Arrow> arrows;
  std::vector<Marker> markers;
  std::vector<Label> labels;
};

}  // namespace liftcheck::render
