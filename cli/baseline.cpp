#include "cli/baseline.hpp"

#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <set>

#include "input/params.hpp"     // InputError
#include "input/read_file.hpp"  // require_utf8
#include "input/results_diff.hpp"
#include "input/results_file.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck::cli {

std::optional<SuiteResults> read_baseline(const std::string& path, bool update_baseline) {
  if (update_baseline && path.empty()) throw InputError("--update-baseline needs --baseline FILE");
  // A baseline is read back by its name (recorded in results.json, JSON holds UTF-8 only): one it
  // could not be read back by is refused before anything runs, not written.
  if (update_baseline) {
    require_utf8(path, "--baseline file name");
    // The baseline is renamed into place last, after --out: a place it cannot take is refused first.
    std::error_code ec;
    const std::filesystem::file_status st = std::filesystem::status(path, ec);
    if (std::filesystem::is_directory(st))
      throw InputError(
          fmt::format("--baseline '{}' is a folder: --update-baseline writes a file (name it)", printable(path, 200)));
    if (std::filesystem::exists(st) && !std::filesystem::is_regular_file(st))
      throw InputError(
          fmt::format("--baseline '{}' is not a regular file: --update-baseline writes a file", printable(path, 200)));
  }
  if (path.empty() || update_baseline) return std::nullopt;
  return read_results(path);
}

int compare_with_baseline(SuiteResults& results, const std::string& path, const SuiteResults& baseline,
                          double worse_factor) {
  // What was run is compared: a filtered or sharded suite compares its share.
  std::set<std::pair<std::string, std::string>> ran;
  for (const RunResult& r : results.runs) ran.insert({r.scenario, r.engine});
  SuiteResults base;
  for (const RunResult& r : baseline.runs)
    if (ran.count({r.scenario, r.engine})) base.runs.push_back(r);
  for (const auto& [key, p] : baseline.points)
    if (results.points.count(key)) base.points.emplace(key, p);
  const auto ran_outcomes = results.outcomes ? outcome_flags(*results.outcomes) : results.baseline_outcomes;
  for (const auto& [key, hit] : baseline.baseline_outcomes)
    if (ran_outcomes.count(key)) base.baseline_outcomes.emplace(key, hit);
  DiffDef def;
  def.growth = worse_factor;
  const ResultsDiff d = diff_results(index_of(base), index_of(results), def);
  results.baseline = BaselineComparison{path, worse_factor, d};
  std::cout << "against the baseline " << printable(path, 200) << ":\n" << diff_text(d);
  return d.problems();
}

}  // namespace liftcheck::cli
