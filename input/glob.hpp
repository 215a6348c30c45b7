// Scenario name globs (validate --filter, --trace-dir): shell patterns, any of which may match.
#pragma once

#include <string>
#include <vector>

namespace liftcheck {

/// Whether `name` matches any of the globs (fnmatch, no flags).
bool matches_any(const std::vector<std::string>& globs, const std::string& name);

}  // namespace liftcheck
