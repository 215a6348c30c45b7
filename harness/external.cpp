#include "harness/external.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engines/trace/trace_engines.hpp"
#include "input/glob.hpp"

namespace liftcheck {

const std::vector<std::string>& path_columns(Vehicle vehicle) {
  static const std::vector<std::string> car{"t", "alpha", "beta"}, disks{"t", "cNx", "cNy"};
  return vehicle == Vehicle::kCar ? car : disks;
}

nlohmann::json scenario_path(const Scenario& scenario, const Overrides& overrides) {
  const Params params = Params::resolve(scenario.params, overrides, scenario.name);
  nlohmann::json out{{"scenario", scenario.name},
                     {"vehicle", scenario.vehicle},
                     {"params", params.to_json()},
                     {"columns", path_columns(scenario.vehicle)}};
  RecordingCar car(scenario.name);
  RecordingDisks disks(scenario.name);
  const RecordedPath* recorded = nullptr;
  (void)drive_vehicle(scenario, params,
                      {[&]() -> CarEngine& { return recorded = &car.recorded, car; },
                       [&]() -> DiskEngine& { return recorded = &disks.recorded, disks; }});
  out["start"] = recorded->start;
  out["rows"] = recorded->rows;
  return out;
}

std::string path_csv(const nlohmann::json& path) {
  const Vehicle vehicle = path["vehicle"].get<Vehicle>();
  std::string s = fmt::format(
      "# liftcheck path of {} ({}): the commanded {}; SI units, radians\n", path["scenario"].get<std::string>(),
      to_string(vehicle),
      vehicle == Vehicle::kCar ? "shape path (alpha, beta) from the start below" : "path of N, M starting below");
  for (const auto& [k, v] : path["params"].items())
    s += fmt::format("# param {} = {}\n", k, v.is_string() ? v.get<std::string>() : v.dump());
  for (const auto& [k, v] : path["start"].items()) s += fmt::format("# start {} = {:.17g}\n", k, v.get<double>());
  s += fmt::format("# write back: {}\n", fmt::join(trace_columns(vehicle), ","));
  s += fmt::format("{}\n", fmt::join(path["columns"].get<std::vector<std::string>>(), ","));
  for (const auto& row : path["rows"]) {
    std::string line;
    for (const auto& v : row) line += fmt::format("{}{:.17g}", line.empty() ? "" : ",", v.get<double>());
    s += line + "\n";
  }
  return s;
}

EngineInfo replay_engine(const std::string& name, const Scenario& scenario, const Trace& trace) {
  return replay_engine(name, scenario.name, scenario.vehicle, trace);
}

TraceFolder read_trace_folder(const std::string& trace_dir, const std::vector<std::string>& globs) {
  const std::filesystem::path dir(trace_dir);
  if (!std::filesystem::is_directory(dir)) throw InputError(fmt::format("--trace-dir '{}' is not a folder", trace_dir));
  std::string name = std::filesystem::absolute(dir).lexically_normal().filename().string();
  if (name.empty()) name = std::filesystem::absolute(dir).lexically_normal().parent_path().filename().string();
  if (name.empty() || find_engine(name))
    throw InputError(
        fmt::format("--trace-dir '{}': its name '{}' must not be a built-in configuration's", trace_dir, name));
  TraceFolder folder;
  for (const auto& s : scenarios())
    for (const char* ext : {".csv", ".json"})
      if (const auto f = dir / (s.name + ext);
          std::filesystem::exists(f) && !folder.traces.count(s.name) && matches_any(globs, s.name))
        folder.traces[s.name] = read_trace(f, s.vehicle);
  if (folder.traces.empty())
    throw InputError(fmt::format("--trace-dir '{}' holds no SCENARIO.csv or .json for the scenarios run", trace_dir));
  folder.engine =
      outside_engine(name, fmt::format("a simulator outside liftcheck, scored from the traces in {}", trace_dir));
  return folder;
}

}  // namespace liftcheck
