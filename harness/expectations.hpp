// Known failures of the default suite, reviewed data (harness/expectations.json): each is a
// finding about a configuration, with the reason in one sentence and the measured figure. A
// listed run must fail, and only in its listed metrics; a listed run that passes is unexpected,
// so the file stays true. Negative controls are listed the same way.
#pragma once

#include <string>
#include <vector>

namespace liftcheck {

struct KnownFailure {
  std::string scenario, engine;
  std::vector<std::string> metrics;  ///< the metrics that may fail (at least one must)
  std::string reason, measured;
};

/// The "runs" entries, one per scenario x configuration.
const std::vector<KnownFailure>& known_run_failures();
/// The entry for a default run of `scenario` on `engine`, or null.
const KnownFailure* find_known_failure(const std::string& scenario, const std::string& engine);

}  // namespace liftcheck
