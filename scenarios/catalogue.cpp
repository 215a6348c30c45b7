#include "scenarios/car_scenarios.hpp"
#include "scenarios/disk_scenarios.hpp"
#include "scenarios/scenario.hpp"

namespace liftcheck {

const std::vector<Scenario>& scenarios() {
  static const std::vector<Scenario> all = [] {
    std::vector<Scenario> v = car_scenarios();
    for (auto& s : disk_scenarios()) v.push_back(std::move(s));
    return v;
  }();
  return all;
}

}  // namespace liftcheck
