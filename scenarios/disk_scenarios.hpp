#pragma once
#include <vector>
#include "scenarios/scenario.hpp"
namespace liftcheck {
/// disks.copy, disks.actuated, disks.repel, disks.orbit, disks.linear, disks.forced,
/// disks.moving-away, disks.extended, disks.target.
std::vector<Scenario> disk_scenarios();

/// disks.linear's horizon for a collision outcome (the outcome grid's runs): its duration T when the
/// exact motion (43) brings the disks into contact, else the time after which (43) keeps them at
/// least `clearance_m` apart up to T, plus `after_s`, but not less than `min_s`. An engine whose M
/// strays less than `clearance_m` from (43) cannot touch N after it.
double linear_outcome_horizon_s(const Params& p, double clearance_m, double after_s, double min_s);
}  // namespace liftcheck
