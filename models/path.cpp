#include "models/path.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>

namespace liftcheck::car {

namespace {
constexpr double kPi = std::numbers::pi;
}

Profile::Profile(double distance, double cruise_rate, double peak_accel) : D_(std::abs(distance)), V_(cruise_rate) {
  if (!(cruise_rate > 0.0) || !(peak_accel > 0.0))
    throw std::invalid_argument("profile rate and acceleration must be positive");
  if (D_ == 0.0) return;
  // A ramp v = V (1 - cos(pi t / ramp)) / 2 has peak acceleration pi V / (2 ramp).
  ramp_ = kPi * V_ / (2.0 * peak_accel);
  if (D_ >= V_ * ramp_) {
    T_ = D_ / V_ + ramp_;  // each ramp covers V ramp / 2
  } else {
    // Bell v = V' (1 - cos(2 pi t / T)) / 2 with T = 2 ramp', covering V' ramp' = D at the same
    // peak acceleration pi V' / (2 ramp') = A.
    bell_ = true;
    ramp_ = std::sqrt(kPi * D_ / (2.0 * peak_accel));
    V_ = D_ / ramp_;
    T_ = 2.0 * ramp_;
  }
}

Profile Profile::pause(double T_s) {
  if (!(T_s >= 0.0)) throw std::invalid_argument("a pause needs a duration >= 0");
  Profile p;
  p.T_ = T_s;
  p.D_ = 0.0;
  p.ramp_ = 0.0;
  p.pause_ = true;
  return p;
}

double Profile::position(double t) const {
  if (pause_) return 0.0;
  if (T_ == 0.0) return 0.0;
  t = std::clamp(t, 0.0, T_);
  if (bell_) return 0.5 * V_ * (t - T_ / (2.0 * kPi) * std::sin(2.0 * kPi * t / T_));
  auto ramp_up = [&](double s) { return 0.5 * V_ * (s - ramp_ / kPi * std::sin(kPi * s / ramp_)); };
  if (t <= ramp_) return ramp_up(t);
  if (t <= T_ - ramp_) return 0.5 * V_ * ramp_ + V_ * (t - ramp_);
  return D_ - ramp_up(T_ - t);
}

double Profile::rate(double t) const {
  if (pause_) return 0.0;
  if (T_ == 0.0 || t <= 0.0 || t >= T_) return 0.0;
  if (bell_) return 0.5 * V_ * (1.0 - std::cos(2.0 * kPi * t / T_));
  if (t <= ramp_) return 0.5 * V_ * (1.0 - std::cos(kPi * t / ramp_));
  if (t <= T_ - ramp_) return V_;
  return 0.5 * V_ * (1.0 - std::cos(kPi * (T_ - t) / ramp_));
}

BasePath::BasePath(std::vector<Segment> segments, double alpha0_rad, double beta0_rad, const DriveDef& drive)
    : segments_(std::move(segments)) {
  if (!(drive.R_m > 0.0) || !(drive.speed_mps > 0.0) || !(drive.steer_rate_radps > 0.0) || !(drive.accel_mps2 > 0.0) ||
      !(drive.steer_accel_radps2 > 0.0))
    throw std::invalid_argument("drive needs R, speed, steer_rate, accel, steer_accel > 0");
  double t = 0.0, a = alpha0_rad, b = beta0_rad;
  for (const Segment& s : segments_) {
    start_s_.push_back(t);
    alpha0_.push_back(a);
    beta0_.push_back(b);
    // Normalised progress u in [0, 1]: the segment takes as long as its slower component needs.
    const Profile pa(s.d_alpha_rad * drive.R_m, drive.speed_mps, drive.accel_mps2);
    const Profile pb(s.d_beta_rad, drive.steer_rate_radps, drive.steer_accel_radps2);
    const bool a_slow = pa.duration() >= pb.duration();
    const double dist = a_slow ? std::abs(s.d_alpha_rad * drive.R_m) : std::abs(s.d_beta_rad);
    const double rate = a_slow ? drive.speed_mps : drive.steer_rate_radps;
    const double accel = a_slow ? drive.accel_mps2 : drive.steer_accel_radps2;
    profile_.push_back(dist > 0.0 ? Profile(1.0, rate / dist, accel / dist) : Profile::pause(s.hold_s));
    t += profile_.back().duration();
    a += s.d_alpha_rad;
    b += s.d_beta_rad;
  }
  alpha0_.push_back(a);
  beta0_.push_back(b);
}

BaseSample BasePath::corner(std::size_t i) const { return {alpha0_[i], beta0_[i], 0.0, 0.0}; }

std::size_t BasePath::segment_at(double t_s) const {
  if (segments_.empty()) return 0;
  const auto it = std::upper_bound(start_s_.begin(), start_s_.end(), t_s);
  return it == start_s_.begin() ? 0 : static_cast<std::size_t>(it - start_s_.begin()) - 1;
}

BaseSample BasePath::at(double t_s) const {
  if (segments_.empty()) return corner(0);
  const std::size_t i = segment_at(t_s);
  const double tau = t_s - start_s_[i];
  const Profile& p = profile_[i];
  const double u = p.duration() > 0.0 ? p.position(tau) : (tau > 0.0 ? 1.0 : 0.0);
  const double du = p.rate(tau);
  const Segment& s = segments_[i];
  return {alpha0_[i] + u * s.d_alpha_rad, beta0_[i] + u * s.d_beta_rad, du * s.d_alpha_rad, du * s.d_beta_rad};
}

}  // namespace liftcheck::car
