// CI outputs built from results.json: JUnit XML, and a regression diff between two results files.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace liftcheck {

/// One <testsuite> per scenario, one <testcase> per engine run; fails and errors carry the run's
/// message, skips are skipped, a negative control failing as designed passes.
std::string junit_xml(const nlohmann::json& results);

struct DiffDef {
  /// A metric counts as worse when its error grows by more than this factor and ends above
  /// `floor` of its tolerance (changes deep inside the tolerance are noise, not regressions).
  double growth = 10.0;
  double floor = 0.01;
};

/// Compares two results files run by run: status changes (a run that was as expected and is no
/// longer is a regression), runs added or removed, and metrics whose errors grew.
/// Returns {"regressions": [...], "worse": [...], "better": [...], "added": [...], "removed": [...]}.
nlohmann::json diff_results(const nlohmann::json& base, const nlohmann::json& head, const DiffDef& def = {});

/// The diff as plain text, one line per finding.
std::string diff_text(const nlohmann::json& diff);

}  // namespace liftcheck
