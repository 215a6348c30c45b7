// The driver's path in the base M = {(alpha, beta)}: straight segments driven one after another,
// each with a smooth speed profile (cosine ramps, cruise), so that rigid-body engines can follow it.
#pragma once

#include <vector>

namespace liftcheck::car {

/// One straight segment in the base: alpha and beta change together by these amounts.
struct Segment {
  double d_alpha_rad = 0.0;
  double d_beta_rad = 0.0;
  /// A segment with no change in alpha or beta lasts this long (a pause: the car parked with its
  /// wheel angle and steering held); ignored when the segment moves.
  double hold_s = 0.0;
};

/// How fast the driver moves through the base. The accelerations bound every segment, long or
/// short, so that a rigid-body car can follow without exceeding its traction.
struct DriveDef {
  double R_m = 0.3;                 ///< front wheel radius: converts alpha to front-wheel travel
  double speed_mps = 0.5;           ///< cruise speed of the front wheel's contact point
  double steer_rate_radps = 0.5;    ///< cruise rate of the steering angle
  double accel_mps2 = 1.0;          ///< peak acceleration of the front wheel's contact point
  double steer_accel_radps2 = 4.0;  ///< peak angular acceleration of the steering
};

/// Smooth rest-to-rest motion over a distance D with cruise rate V and peak acceleration A:
/// cosine ramps of duration pi V / (2 A), cruise, cosine ramp down; a single cosine bell of the
/// same peak acceleration when D is too short to reach V.
class Profile {
 public:
  Profile() = default;
  Profile(double distance, double cruise_rate, double peak_accel);
  /// Standing still for T seconds (position 0, rate 0).
  static Profile pause(double T_s);
  double duration() const { return T_; }
  double position(double t) const;  ///< in [0, D]
  double rate(double t) const;

 private:
  double D_ = 0.0, V_ = 1.0, ramp_ = 0.0, T_ = 0.0;
  bool bell_ = false;
  bool pause_ = false;
};

/// Commanded base point and its rate at one time.
struct BaseSample {
  double alpha_rad, beta_rad;
  double alpha_rate_radps, beta_rate_radps;
};

/// Segments in time order with their profiles.
class BasePath {
 public:
  BasePath(std::vector<Segment> segments, double alpha0_rad, double beta0_rad, const DriveDef& drive);

  double duration_s() const { return start_s_.empty() ? 0.0 : start_s_.back() + profile_.back().duration(); }
  const std::vector<Segment>& segments() const { return segments_; }
  std::size_t size() const { return segments_.size(); }
  double segment_start_s(std::size_t i) const { return start_s_[i]; }
  double segment_end_s(std::size_t i) const { return start_s_[i] + profile_[i].duration(); }
  /// Base point at the start of segment i (i == size() gives the end point).
  BaseSample corner(std::size_t i) const;
  /// Segment index at time t (the last one past the end).
  std::size_t segment_at(double t_s) const;
  BaseSample at(double t_s) const;

 private:
  std::vector<Segment> segments_;
  std::vector<Profile> profile_;  // progress along each segment, normalised to [0, 1]
  std::vector<double> start_s_;
  std::vector<double> alpha0_, beta0_;  // base point at each segment start, plus the end
};

}  // namespace liftcheck::car
