// Plots with gnuplot (SVG): one script with inline data blocks, run once per report.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace liftcheck {

struct PlotFile {
  std::string group;    ///< a scenario name, or "sweeps"
  std::string file;     ///< relative to the report folder
  std::string caption;
};

/// Writes plots/plots.gp and runs gnuplot on it. Throws std::runtime_error if gnuplot fails.
std::vector<PlotFile> write_plots(const nlohmann::json& results, const std::filesystem::path& out_dir);

}  // namespace liftcheck
