#pragma once
#include <vector>
#include "scenarios/scenario.hpp"
namespace liftcheck {
/// The disk scenarios, in catalogue order (scenarios/disk_free.cpp, disk_contact.cpp).
std::vector<Scenario> disk_scenarios();

/// disks.linear's horizon for a collision outcome (the outcome grid's runs): the time after which the
/// exact motion keeps the disks at least `clearance_m` apart up to T, plus `after_s`, but not less
/// than `min_s` (nor more than T). The exact motion is (43) up to a first contact and the contact
/// response after it; a contact that lasts to T keeps T. An engine whose M strays less than
/// `clearance_m` from the exact motion cannot touch N after the horizon, and one whose contact lasts
/// longer than the exact one by `after_s` shows it in its contact duration.
double linear_outcome_horizon_s(const Params& p, double clearance_m, double after_s, double min_s);
}  // namespace liftcheck
