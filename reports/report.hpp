// Writes the report folder from results.json: snapshots (OSMesa, PNG), plots (gnuplot, SVG) and
// HTML pages. Sets the results' report: every file it wrote.
#pragma once

#include <filesystem>
#include "input/suite_result.hpp"

namespace liftcheck {

struct ReportDef {
  bool snapshots = true;
  bool plots = true;
  int threads = 2;  ///< rendering threads, one OSMesa context each (below 1: one)
};

/// Never throws for a failed picture or plot: the failure is listed in the results' report errors
/// and shown on the index. Throws std::runtime_error only when the HTML cannot be written.
void write_report(SuiteResults& results, const std::filesystem::path& out, const ReportDef& def = {});

}  // namespace liftcheck
