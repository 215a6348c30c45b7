// The two-disk scenarios of the catalogue (Farber, Kurz, Pillin, sections 3, 5, 6), by family.
// Expected values come from the paper's closed forms where it has them, otherwise from the lift
// (21) integrated in models/.
#include "scenarios/disk_scenarios.hpp"

#include <algorithm>

#include "scenarios/disk_common.hpp"

namespace liftcheck {

std::vector<Scenario> disk_scenarios() {
  // The catalogue's order, the families interleaved.
  static const char* const kOrder[] = {"disks.copy",     "disks.actuated", "disks.repel",  "disks.orbit",
                                       "disks.linear",   "disks.oblique",  "disks.forced", "disks.moving-away",
                                       "disks.extended", "disks.target"};
  std::vector<Scenario> all = contact_free_disk_scenarios(), contact = contact_disk_scenarios();
  for (Scenario& s : contact) all.push_back(std::move(s));
  const auto rank = [&](const Scenario& s) {
    return std::find(std::begin(kOrder), std::end(kOrder), s.name) - std::begin(kOrder);
  };
  std::stable_sort(all.begin(), all.end(), [&](const Scenario& a, const Scenario& b) { return rank(a) < rank(b); });
  return all;
}

}  // namespace liftcheck
