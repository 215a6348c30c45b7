// Two results files compared run by run (the regression diff), and the baseline a results file is
// compared with: what `liftcheck diff` and `validate --baseline` read, with no engine.
#pragma once

#include <string>

#include "input/results_index.hpp"
#include "input/suite_result.hpp"

namespace liftcheck {

/// The regression gate's default factor: a counted metric whose error grows by more than this
/// against the baseline is worse (exit 1). The records reproduce bit for bit on another machine
/// with the same toolchain, so any growth is a change; docs/ci.md says what the factor tolerates.
inline constexpr double kDefaultWorseFactor = 1.25;

struct DiffDef {
  /// A metric counts as worse when its error grows by more than this factor and ends above
  /// `floor` of its tolerance (changes deep inside the tolerance are noise, not regressions);
  /// better when it shrinks so; moved when it changes at all, but neither.
  double growth = kDefaultWorseFactor;
  double floor = 0.01;
};

/// Compares two results files run by run: status changes (a run that was as expected and is no
/// longer is a regression), runs added or removed, and metrics whose errors grew.
ResultsDiff diff_results(const ResultsIndex& base, const ResultsIndex& head, const DiffDef& def = {});

/// "car.circle on ode", or a point's key.
std::string finding_name(const DiffFinding& f);

/// The diff as plain text, one line per finding.
std::string diff_text(const ResultsDiff& diff);

}  // namespace liftcheck
