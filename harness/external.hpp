// Any simulator liftcheck does not link: the scenario's commanded path written out (`liftcheck
// path`), and what the simulator did read back and scored exactly as an engine run (`liftcheck
// score`, `validate --trace-dir`). The scenario function runs unchanged: a recording engine
// captures the path it commands, a replaying engine hands it the simulator's trace.
#pragma once

#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engines/engine.hpp"
#include "input/params.hpp"
#include "scenarios/scenario.hpp"
#include "input/trace.hpp"

namespace liftcheck {

/// Columns of the commanded paths (the trace columns: input/trace.hpp).
const std::vector<std::string>& path_columns(Vehicle vehicle);

/// The commanded path of one scenario run: {"scenario", "vehicle", "params", "settings", "start",
/// "columns", "rows"}. Cars: t, alpha, beta every sample_dt from 0 to the path's end, start
/// (alpha, beta, x, y, phi). Disks: t, cNx, cNy, start cM and the horizon T. InputError for bad
/// parameters or a scenario that drives more than one run (it has no single path to hand out).
nlohmann::json scenario_path(const Scenario& scenario, const Overrides& overrides);
/// The same as CSV: '#' comment lines (scenario, every parameter, the start), a header, rows.
std::string path_csv(const nlohmann::json& path);

/// A configuration that replays `trace` for `scenario` (and no other): scored with the "default"
/// tolerances like every engine. Its car reports the trace's (alpha, beta, x, y, phi) and no
/// contact slip; its disks report the trace's positions, first contact at the first sample with
/// |c_M - c_N| <= 2 r, no contact log.
EngineInfo replay_engine(const std::string& name, const Scenario& scenario, const Trace& trace);

/// `validate --trace-dir`: an outside simulator whose folder's name is its configuration, each
/// SCENARIO.csv (or .json) in it a run of a scenario matched by `globs`. Every trace is read at
/// once, so a malformed one stops validate before anything runs. `engine` is the configuration as
/// results.json lists it.
struct TraceFolder {
  EngineInfo engine;
  std::map<std::string, Trace> traces;  ///< by scenario name
};
TraceFolder read_trace_folder(const std::string& dir, const std::vector<std::string>& globs);

}  // namespace liftcheck
