#pragma once
#include <vector>
#include "scenarios/scenario.hpp"
namespace liftcheck {
/// car.circle, car.cycle, car.iterated, car.iterated-beta, car.steer-in-place, car.reparam.
std::vector<Scenario> car_scenarios();
}  // namespace liftcheck
