// Parking cycles of section 5 and appendix E: closed loops in the base whose lift ends displaced
// along the fibre. Steps are listed in the order they are driven (first step first).
//
// Convention checked in tests/test_holonomy.cpp: driving U by s, V by s, U by -s, V by -s moves a
// point by +s^2 [U, V] + O(s^3). The printed (E.1) and (5.3) carry the opposite sign; see ERRATA.md.
#pragma once

#include <vector>

#include "models/car.hpp"
#include "models/path.hpp"

namespace liftcheck::car {

enum class Field { kAlpha, kBeta };

struct Step {
  Field field;
  double amount_rad;
};

/// Section 5, steps i-iv: drive +eps_alpha, steer +eps_beta, drive -eps_alpha, steer -eps_beta.
std::vector<Step> simple_cycle(double eps_alpha_rad, double eps_beta_rad);

/// Ten-step cycle of (E.3) for fields U, W, Z (printed right to left, returned in driving order):
/// Z_{-e} W_{-e} Z_{e} W_{e} U_{-e^2} W_{-e} Z_{-e} W_{e} Z_{e} U_{e^2}.
std::vector<Step> iterated_cycle(Field U, Field W, Field Z, double eps);
/// (5.8): U = W = H_alpha, Z = H_beta. Net motion -eps^4 [H_a,[H_a,H_b]] + ..., i.e. (5.9).
std::vector<Step> iterated_cycle_alpha(double eps);
/// (5.10): U = H_beta, W = H_alpha, Z = H_beta. Net motion -eps^4 [H_b,[H_a,H_b]] + ...
std::vector<Step> iterated_cycle_beta(double eps);

/// Composes the exact flows of the steps (appendix D arcs and steering): the finite-eps holonomy.
Config apply_exact(const CarDef& car, const Config& q, const std::vector<Step>& steps);

/// The steps as base-path segments for an engine to drive.
std::vector<Segment> to_segments(const std::vector<Step>& steps);

/// Leading-order predictions of the net change of P from the brackets.
Vec5 predicted_simple(const CarDef& car, const Config& q, double eps_alpha_rad, double eps_beta_rad);
Vec5 predicted_iterated_alpha(const CarDef& car, const Config& q, double eps);
Vec5 predicted_iterated_beta(const CarDef& car, const Config& q, double eps);

}  // namespace liftcheck::car
