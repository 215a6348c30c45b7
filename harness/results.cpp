#include "harness/results.hpp"

#include <chrono>
#include <ctime>
#include <fmt/format.h>
#include <fstream>
#include <thread>
#include <unistd.h>
#include <sys/utsname.h>

#include "liftcheck_errata.hpp"
#include "liftcheck_tune_table.hpp"
#include "liftcheck_version.hpp"

namespace liftcheck {

nlohmann::json context_json(const std::vector<const EngineInfo*>& engines, double wall_s) {
  nlohmann::json es = nlohmann::json::array();
  for (const EngineInfo* e : engines) {
    nlohmann::json settings = nlohmann::json::object();
    for (const auto& [k, v] : e->settings) settings[k] = v;
    // The settings a user may change (--set), with their defaults: part of what the engine is.
    for (const SettingSpec& k : e->knobs)
      settings[fmt::format("--set {} ({})", k.key, to_string(k.vehicle))] =
          fmt::format("{}; default {}; {}", k.help, k.default_text, k.range_text());
    nlohmann::json knobs = nlohmann::json::array();
    for (const SettingSpec& k : e->knobs) {
      nlohmann::json j{{"key", k.key},
                       {"vehicle", k.vehicle},
                       {"default", k.default_text},
                       {"help", k.help},
                       {"kind", k.kind_name()}};
      if (k.role == SettingRole::kSolverIterations) j["role"] = "solver_iterations";
      if (k.role == SettingRole::kDamping) j["role"] = "damping";
      if (k.numeric())
        j["min"] = k.min, j["max"] = k.max, j["min_exclusive"] = k.min_exclusive;
      else
        j["choices"] = k.choices;
      knobs.push_back(j);
    }
    es.push_back({{"name", e->name},
                  {"library", e->library},
                  {"version", e->version},
                  {"description", e->description},
                  {"color", e->color},
                  {"is_reference", e->is_reference},
                  {"vehicles", vehicles_of(*e)},
                  {"contact_dynamics", e->contact_dynamics},
                  {"brakes", e->brakes},
                  {"settings", settings},
                  {"knobs", knobs}});
  }
  // liftcheck tune's committed answers (data/tune/table.json) for the configurations of this run.
  nlohmann::json tune_table = nlohmann::json::object();
  const nlohmann::json table = nlohmann::json::parse(kTuneTableJson, nullptr, false);
  if (table.is_object() && table.contains("entries"))
    for (const auto& [pair, entry] : table["entries"].items())
      for (const auto& e : es)
        if (pair.substr(pair.find(' ') + 1) == e["name"].get<std::string>()) tune_table[pair] = entry;
  char host[256] = "unknown";
  gethostname(host, sizeof host - 1);
  utsname u{};
  uname(&u);
  const std::time_t now = std::time(nullptr);
  char date[32] = "unknown";
  std::tm utc{};
  if (gmtime_r(&now, &utc)) std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return {{"liftcheck", {{"version", LIFTCHECK_VERSION}, {"commit", LIFTCHECK_COMMIT}}},
          {"date", date},
          {"machine",
           {{"host", host},
            {"os", fmt::format("{} {} {}", u.sysname, u.release, u.machine)},
            {"cpus", std::thread::hardware_concurrency()},
            {"compiler", LIFTCHECK_COMPILER}}},
          {"engines", es},
          {"wall_s", wall_s},
          {"errata", kErrataMarkdown},
          {"tune_table", tune_table}};
}

nlohmann::json results_json(const std::vector<RunRecord>& runs, const nlohmann::json& context) {
  nlohmann::json rs = nlohmann::json::array();
  for (const auto& r : runs) rs.push_back(r.to_json());
  return results_from_records(rs, context);
}

nlohmann::json results_from_records(const nlohmann::json& runs, const nlohmann::json& context) {
  // Counted by verdict: a known failure is not a fail, an unexpected pass is not a pass.
  std::map<std::string, int> counts{{"pass", 0}, {"known failure", 0}, {"unexpected pass", 0},
                                    {"fail", 0}, {"error", 0},         {"skip", 0}};
  int unexpected = 0;
  for (const auto& r : runs) {
    ++counts[r.at("verdict").get<std::string>()];
    unexpected += r.at("as_expected").get<bool>() ? 0 : 1;
  }
  nlohmann::json summary(counts);
  summary["total"] = runs.size();
  summary["unexpected"] = unexpected;
  return {{"context", context}, {"summary", summary}, {"runs", runs}};
}

}  // namespace liftcheck
