// Two results files compared run by run (the regression diff), and the baseline a results file is
// compared with: what `liftcheck diff` and `validate --baseline` read, with no engine.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

#include "input/results_index.hpp"

namespace liftcheck {

/// Whether a stored run record is as expected (files written before verdicts: pass or skip).
bool record_as_expected(const nlohmann::json& record);

/// A baseline of a results file: its runs' records only (scenario, configuration, parameters,
/// settings, status, verdict, metrics), without traces, details or timings, so it stays small and
/// reviewable in a diff; `diff_results` compares a results file with it.
nlohmann::json baseline_json(const nlohmann::json& results);

struct DiffDef {
  /// A metric counts as worse when its error grows by more than this factor and ends above
  /// `floor` of its tolerance (changes deep inside the tolerance are noise, not regressions).
  double growth = 10.0;
  double floor = 0.01;
};

/// Compares two results files run by run: status changes (a run that was as expected and is no
/// longer is a regression), runs added or removed, and metrics whose errors grew.
/// Returns {"regressions": [...], "worse": [...], "better": [...], "added": [...], "removed": [...]}.
nlohmann::json diff_results(const ResultsIndex& base, const ResultsIndex& head, const DiffDef& def = {});

/// The same on two documents (index_of each).
nlohmann::json diff_results(const nlohmann::json& base, const nlohmann::json& head, const DiffDef& def = {});

/// The diff as plain text, one line per finding.
std::string diff_text(const nlohmann::json& diff);

}  // namespace liftcheck
