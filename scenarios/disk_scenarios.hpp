#pragma once
#include <vector>
#include "scenarios/scenario.hpp"
namespace liftcheck {
/// disks.copy, disks.actuated, disks.repel, disks.orbit, disks.linear, disks.forced,
/// disks.moving-away, disks.extended, disks.target.
std::vector<Scenario> disk_scenarios();
}  // namespace liftcheck
