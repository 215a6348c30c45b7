// The car scenarios of the catalogue (Fecko), by family: each builds a base path, lets the engine
// drive it, and compares the realized motion with the exact lift of the commanded path.
#include "scenarios/car_scenarios.hpp"

#include "scenarios/car_common.hpp"

namespace liftcheck {

std::vector<Scenario> car_scenarios() {
  std::vector<Scenario> v;
  for (auto family : {circle_scenarios, cycle_scenarios, slope_scenarios, grip_scenarios})
    for (Scenario& s : family()) v.push_back(std::move(s));
  return v;
}

}  // namespace liftcheck
