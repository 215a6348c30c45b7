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

nlohmann::json read_baseline(const std::string& path, bool update_baseline) {
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
  return !path.empty() && !update_baseline ? read_results(path) : nlohmann::json();
}

int compare_with_baseline(nlohmann::json& results, const std::string& path, const nlohmann::json& baseline) {
  std::set<std::pair<std::string, std::string>> ran;
  for (const auto& r : results["runs"]) ran.insert({r["scenario"].get<std::string>(), r["engine"].get<std::string>()});
  nlohmann::json base = baseline;
  base["runs"] = nlohmann::json::array();
  for (const auto& r : baseline["runs"])
    if (ran.count({r["scenario"].get<std::string>(), r["engine"].get<std::string>()})) base["runs"].push_back(r);
  nlohmann::json d;
  try {
    d = diff_results(base, results);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("'{}' is not a liftcheck baseline: {}", printable(path, 200), e.what()));
  }
  results["baseline"] = {{"file", path}, {"diff", d}};
  std::cout << "against the baseline " << printable(path, 200) << ":\n" << diff_text(d);
  return static_cast<int>(d["regressions"].size() + d["worse"].size());
}

}  // namespace liftcheck::cli
