// The registrations of the outside configurations (docs/protocol.md, "Registering a
// configuration"): the files NAME.json of the default suite's folder and of LIFTCHECK_ENGINE_PATH,
// each an entry of the registry not yet described, and the adapter script a registration runs.
#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <string>
#include <system_error>
#include <vector>

#include "engines/protocol/child.hpp"  // kProtocolLineMax
#include "engines/protocol/outside.hpp"
#include "input/params.hpp"  // InputError
#include "input/read_file.hpp"
#include "input/trace.hpp"  // parse_json_text, printable

#ifndef LIFTCHECK_OUTSIDE_DIR
#define LIFTCHECK_OUTSIDE_DIR "engines/outside"
#endif

namespace liftcheck {

using nlohmann::json;

namespace {

std::string registration_problem(const std::filesystem::path& file, const std::string& what) {
  return fmt::format("engine registration '{}': {}", file.string(), what);
}

/// One registration file, or a problem.
bool read_registration(const std::filesystem::path& file, EngineInfo& e, std::string& problem) {
  // Read as every JSON file a user gives: bounded, 64 levels at most, no key twice in an object.
  json j;
  try {
    j = parse_json_text(read_text_file(file, kProtocolLineMax, "engine registration"), file.filename().string());
  } catch (const InputError& err) {
    return problem = registration_problem(file, err.what()), false;
  }
  const auto str = [&](const char* key) {
    return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
  };
  if (!j.is_object()) return problem = registration_problem(file, "not a JSON object"), false;
  e.name = str("name");
  if (e.name.empty() || e.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789.-_") != std::string::npos)
    return problem = registration_problem(file, "'name' must be lower-case letters, digits, '.', '-' and '_'"), false;
  if (e.name != file.stem().string())
    return problem = registration_problem(file, fmt::format("'name' '{}' must be the file's name", e.name)), false;
  if (!j.contains("command") || !j["command"].is_array() || j["command"].empty())
    return problem = registration_problem(file, "'command' must be a non-empty array of strings (an argument vector)"),
           false;
  for (const auto& a : j["command"]) {
    if (!a.is_string() || a.get<std::string>().empty())
      return problem = registration_problem(file, "'command' must hold non-empty strings"), false;
    // An argument vector holds C strings: a NUL would cut the argument short, unseen.
    if (a.get<std::string>().find('\0') != std::string::npos)
      return problem =
                 registration_problem(file, fmt::format("'command' argument {} holds a NUL byte ('{}')",
                                                        e.outside.command.size(), printable(a.get<std::string>(), 80))),
             false;
    e.outside.command.push_back(a.get<std::string>());
  }
  e.description = str("description");
  e.color = str("color");
  const bool hex = e.color.size() == 7 && e.color[0] == '#' &&
                   e.color.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos;
  if (!hex) return problem = registration_problem(file, "'color' must be \"#rrggbb\""), false;
  // "points": "map": the configuration joins a suite's runs and its speed-accuracy map only; "runs":
  // its runs only, the map showing its default run (the rest with validate --all-points).
  const std::string points = j.contains("points") ? str("points") : "all";
  if (points != "all" && points != "map" && points != "runs")
    return problem = registration_problem(file, "'points' must be \"all\", \"map\" or \"runs\""), false;
  e.points = points == "all" ? SuitePoints::kAll : points == "map" ? SuitePoints::kMap : SuitePoints::kRuns;
  e.outside.registration = std::filesystem::absolute(file).lexically_normal().string();
  return true;
}

}  // namespace

std::string default_suite_dir() {
  static const std::string dir = [] {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      const std::filesystem::path beside = exe.parent_path() / "outside" / "suite";
      if (std::filesystem::is_directory(beside, ec)) return beside.string();
    }
    return std::string(LIFTCHECK_OUTSIDE_DIR);
  }();
  return dir;
}

bool default_suite_is_beside_binary() { return default_suite_dir() != LIFTCHECK_OUTSIDE_DIR; }

std::string adapter_path(const EngineInfo& e) {
  if (e.outside.registration.empty()) return {};
  const std::filesystem::path cwd = std::filesystem::path(e.outside.registration).parent_path();
  std::error_code ec;
  for (size_t i = 0; i < e.outside.command.size(); ++i) {
    const std::string& a = e.outside.command[i];
    // A bare command[0] is looked up on PATH (the interpreter); options are not files.
    if ((i == 0 && a.find('/') == std::string::npos) || a.empty() || a[0] == '-') continue;
    const std::filesystem::path p = cwd / a;  // an absolute argument stands for itself
    if (std::filesystem::is_regular_file(p, ec)) return std::filesystem::weakly_canonical(p, ec).string();
  }
  return {};
}

std::vector<std::string> engine_dirs() {
  std::vector<std::string> dirs{default_suite_dir()};
  if (const char* path = std::getenv("LIFTCHECK_ENGINE_PATH")) {
    std::stringstream ss(path);
    std::string d;
    while (std::getline(ss, d, ':'))
      if (!d.empty()) dirs.push_back(d);
  }
  return dirs;
}

std::vector<EngineInfo> outside_engines(const std::vector<std::string>& compiled_names,
                                        std::vector<std::string>& problems) {
  std::vector<EngineInfo> out;
  std::set<std::string> taken(compiled_names.begin(), compiled_names.end());
  std::set<std::string> dirs_seen;
  for (const std::string& dir : engine_dirs()) {
    std::error_code ec;
    const std::filesystem::path d = std::filesystem::weakly_canonical(std::filesystem::absolute(dir), ec);
    if (!dirs_seen.insert(d.string()).second) continue;
    if (!std::filesystem::is_directory(d, ec)) {
      if (dir != default_suite_dir())
        problems.push_back(
            fmt::format("engine folder '{}' (--engine-dir or LIFTCHECK_ENGINE_PATH) is not a folder", dir));
      continue;
    }
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(d, ec)) {
      const std::string name = entry.path().filename().string();
      if (entry.path().extension() == ".json" && name != "package.json" && name != "package-lock.json")
        files.push_back(entry.path());
    }
    // By configuration name (the file's stem), so that "cannon" comes before "cannon-accurate".
    std::sort(files.begin(), files.end(),
              [](const auto& a, const auto& b) { return a.stem().string() < b.stem().string(); });
    for (const auto& f : files) {
      EngineInfo e;
      std::string problem;
      if (!read_registration(f, e, problem)) {
        problems.push_back(problem);
        continue;
      }
      if (!taken.insert(e.name).second) {
        problems.push_back(registration_problem(
            f, fmt::format("the name '{}' is taken (by a compiled-in configuration or another registration)", e.name)));
        continue;
      }
      e.library = "outside";
      e.version = "?";
      e.contact_dynamics = true;
      e.outside.described = false;
      out.push_back(std::move(e));
    }
  }
  return out;
}

EngineInfo outside_engine(const std::string& name, const std::vector<std::string>& command, const std::string& dir) {
  EngineInfo e;
  e.name = name;
  e.outside.command = command;
  e.outside.registration = (std::filesystem::path(dir) / (name + ".json")).string();
  e.color = "#e7298a";
  e.contact_dynamics = true;
  e.outside.described = false;
  describe_outside(e);
  return e;
}

}  // namespace liftcheck
