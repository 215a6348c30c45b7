// Plots with gnuplot (SVG): one script with inline data blocks, run once per report.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "input/suite_result.hpp"

namespace liftcheck {

struct PlotFile {
  std::string group;  ///< a scenario name, or "sweeps"
  std::string file;   ///< relative to the report folder
  std::string caption;
};

/// Writes plots/plots.gp and runs gnuplot on it (no shell: gnuplot is spawned with a fixed argument
/// vector in the plots folder, and every name in the script is quoted as gnuplot data). Throws
/// std::runtime_error if gnuplot cannot be started or fails.
std::vector<PlotFile> write_plots(const SuiteResults& results, const std::filesystem::path& out_dir);

/// The walk of `liftcheck tune` (its tune.json) as out_dir/plots/tune.svg: each run's worst error
/// over its tolerance against its cost, passing runs apart from failing ones, the default and the
/// answer marked. Throws std::runtime_error as write_plots.
void write_tune_plot(const nlohmann::json& tune, const std::filesystem::path& out_dir);

/// `s` as a gnuplot single-quoted string: ' doubled, control characters as spaces (no escapes,
/// backquotes or macros are interpreted inside it).
std::string gnuplot_quote(const std::string& s);

}  // namespace liftcheck
