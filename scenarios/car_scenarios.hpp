#pragma once
#include <vector>
#include "scenarios/scenario.hpp"
namespace liftcheck {
/// The car scenarios, in catalogue order (scenarios/car_circle.cpp, car_cycles.cpp, car_slope.cpp).
std::vector<Scenario> car_scenarios();
}  // namespace liftcheck
