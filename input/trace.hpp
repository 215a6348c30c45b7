// A simulator's trace read back (`liftcheck score`, `validate --trace-dir`): CSV or JSON, checked
// cell by cell. No engine is needed to read one (the fuzz target links this alone).
#pragma once

#include <filesystem>
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <vector>

#include "input/params.hpp"
#include "input/vehicle.hpp"

namespace liftcheck {

/// Columns of a car trace and of a disk trace.
const std::vector<std::string>& trace_columns(Vehicle vehicle);

/// A simulator's trace: rows of the vehicle's trace columns, time strictly increasing.
struct Trace {
  std::string file;
  std::vector<std::vector<double>> rows;  ///< in trace_columns(vehicle) order
  /// What the simulator says of itself, optional: CSV comment lines `# precision: float32` and
  /// `# setting: KEY=VALUE`, or JSON {"precision": ..., "settings": {KEY: VALUE}} beside "rows".
  /// The precision scales bookkeeping tolerances as for a stepped engine; settings are recorded.
  std::string precision = "float64";
  std::vector<std::pair<std::string, std::string>> settings;
};

/// Reads CSV (a header naming the columns, '#' comments) or JSON (an array of objects with the
/// columns as keys, or {"rows": [...]}); InputError naming the file, the line and the problem for
/// a missing column, a non-number or non-finite value, time not increasing, fewer than 2 rows.
Trace read_trace(const std::filesystem::path& file, Vehicle vehicle);

/// The same on text already read; `file` names it in errors.
Trace parse_trace(const std::string& text, const std::string& file, Vehicle vehicle);

/// Parses a JSON document that liftcheck reads back; InputError "FILE: is not JSON (...)", or for a
/// document nested deeper than `max_depth` levels (copying or printing one recurses that deep).
nlohmann::json parse_json_text(std::string_view text, const std::string& file, int max_depth = 64);

/// The same, handing each element of the top level's "runs" array to `on_run` as it ends (its
/// index, its value, and the document as read so far: the top level's keys before "runs") and
/// keeping null in its place: a file of a million runs is read one run at a time. The document
/// without its runs is returned.
using RunHook = std::function<void(std::size_t, nlohmann::json&, const nlohmann::json&)>;
nlohmann::json parse_json_runs(std::string_view text, const std::string& file, const RunHook& on_run,
                               int max_depth = 64);

/// The InputError for a document nlohmann's parser refused: "FILE: is not JSON (REASON)".
InputError not_json_error(const nlohmann::json::exception& e, const std::string& file);

/// `s` for a one-line message: control characters as '?', at most `max` characters.
std::string printable(const std::string& s, std::size_t max = 80);

}  // namespace liftcheck
