#include "models/holonomy.hpp"

#include <algorithm>

namespace liftcheck::car {

std::vector<Step> simple_cycle(double eps_alpha_rad, double eps_beta_rad) {
  return {{Field::kAlpha, eps_alpha_rad},
          {Field::kBeta, eps_beta_rad},
          {Field::kAlpha, -eps_alpha_rad},
          {Field::kBeta, -eps_beta_rad}};
}

std::vector<Step> iterated_cycle(Field U, Field W, Field Z, double eps) {
  const double e = eps, e2 = eps * eps;
  // (E.3) as printed, leftmost factor first; the rightmost factor acts first.
  std::vector<Step> printed{{Z, -e}, {W, -e}, {Z, e}, {W, e}, {U, -e2}, {W, -e}, {Z, -e}, {W, e}, {Z, e}, {U, e2}};
  std::reverse(printed.begin(), printed.end());
  return printed;
}

std::vector<Step> iterated_cycle_alpha(double eps) {
  return iterated_cycle(Field::kAlpha, Field::kAlpha, Field::kBeta, eps);
}

std::vector<Step> iterated_cycle_beta(double eps) {
  return iterated_cycle(Field::kBeta, Field::kAlpha, Field::kBeta, eps);
}

Config apply_exact(const CarDef& car, const Config& q, const std::vector<Step>& steps) {
  Config r = q;
  for (const Step& s : steps)
    r = s.field == Field::kAlpha ? flow_alpha(car, r, s.amount_rad) : flow_beta(r, s.amount_rad);
  return r;
}

std::vector<Segment> to_segments(const std::vector<Step>& steps) {
  std::vector<Segment> out;
  out.reserve(steps.size());
  for (const Step& s : steps)
    out.push_back(s.field == Field::kAlpha ? Segment{s.amount_rad, 0.0} : Segment{0.0, s.amount_rad});
  return out;
}

Vec5 predicted_simple(const CarDef& car, const Config& q, double eps_alpha_rad, double eps_beta_rad) {
  return eps_alpha_rad * eps_beta_rad * bracket_alpha_beta(car, q);
}

Vec5 predicted_iterated_alpha(const CarDef& car, const Config& q, double eps) {
  return -eps * eps * eps * eps * bracket_alpha_alpha_beta(car, q);
}

Vec5 predicted_iterated_beta(const CarDef& car, const Config& q, double eps) {
  return -eps * eps * eps * eps * bracket_beta_alpha_beta(car, q);
}

}  // namespace liftcheck::car
