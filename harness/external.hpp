// Any simulator liftcheck does not link: the scenario's commanded path written out (`liftcheck
// path`), and what the simulator did read back and scored exactly as an engine run (`liftcheck
// score`, `validate --trace-dir`). The scenario function runs unchanged: a recording engine
// captures the path it commands, a replaying engine hands it the simulator's trace.
#pragma once

#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engines/engine.hpp"
#include "harness/params.hpp"
#include "harness/scenario.hpp"

namespace liftcheck {

/// Columns of a car trace and of a disk trace, and of the commanded paths.
const std::vector<std::string>& trace_columns(const std::string& vehicle);
const std::vector<std::string>& path_columns(const std::string& vehicle);

/// The commanded path of one scenario run: {"scenario", "vehicle", "params", "settings", "start",
/// "columns", "rows"}. Cars: t, alpha, beta every sample_dt from 0 to the path's end, start
/// (alpha, beta, x, y, phi). Disks: t, cNx, cNy, start cM and the horizon T. InputError for bad
/// parameters or a scenario that drives more than one run (it has no single path to hand out).
nlohmann::json scenario_path(const Scenario& scenario, const Overrides& overrides);
/// The same as CSV: '#' comment lines (scenario, every parameter, the start), a header, rows.
std::string path_csv(const nlohmann::json& path);

/// A simulator's trace: rows of the vehicle's trace columns, time strictly increasing.
struct Trace {
  std::string file;
  std::vector<std::vector<double>> rows;  ///< in trace_columns(vehicle) order
};
/// Reads CSV (a header naming the columns, '#' comments) or JSON (an array of objects with the
/// columns as keys, or {"rows": [...]}); InputError naming the file, the line and the problem for
/// a missing column, a non-number or non-finite value, time not increasing, fewer than 2 rows.
Trace read_trace(const std::filesystem::path& file, const std::string& vehicle);

/// A configuration that replays `trace` for `scenario` (and no other): scored with the "default"
/// tolerances like every engine. Its car reports the trace's (alpha, beta, x, y, phi) and no
/// contact slip; its disks report the trace's positions, first contact at the first sample with
/// |c_M - c_N| <= 2 r, no contact log.
EngineInfo replay_engine(const std::string& name, const Scenario& scenario, const Trace& trace);

}  // namespace liftcheck
