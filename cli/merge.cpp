// liftcheck merge: the shares of validate --shard I/N joined into one suite.
#include <filesystem>
#include <fmt/format.h>
#include <iostream>
#include <set>

#include "cli/baseline.hpp"
#include "cli/command.hpp"
#include "cli/lookup.hpp"
#include "cli/suite_output.hpp"
#include "harness/results.hpp"
#include "input/trace.hpp"  // printable
#include "liftcheck_version.hpp"

namespace liftcheck::cli {

namespace {

/// The most shares a suite is split into (as many as it has items is already more than useful).
constexpr long kMaxShards = 100000;

/// The field `path` ("plan.selection.engines") of a shard, or InputError naming it and `want`.
const nlohmann::json& field(const nlohmann::json& j, const std::string& file, const std::string& path, const char* want,
                            bool (nlohmann::json::*is)() const noexcept) {
  const nlohmann::json* at = &j;
  for (size_t from = 0; from <= path.size();) {
    const size_t dot = std::min(path.find('.', from), path.size());
    const std::string key = path.substr(from, dot - from);
    if (!at->is_object() || !at->contains(key))
      throw InputError(fmt::format("'{}' is not a shard's results: no '{}' (run validate --shard I/N)", file, path));
    at = &(*at)[key];
    from = dot + 1;
  }
  if (!((*at).*is)())
    throw InputError(fmt::format("'{}': '{}' must be {}, not {}", file, path, want, printable(at->dump(), 60)));
  return *at;
}

/// Every field merge reads from a shard, present and of its type: a wrong one is bad input.
void check_shard(const nlohmann::json& j, const std::string& file) {
  using J = nlohmann::json;
  for (const char* k : {"index", "total"}) {
    const J& n = field(j, file, fmt::format("shard.{}", k), "a whole number", &J::is_number_integer);
    if (n.get<long>() < 1 || n.get<long>() > kMaxShards)
      throw InputError(fmt::format("'{}': 'shard.{}' must be from 1 to {}, not {}", file, k, kMaxShards, n.dump()));
  }
  if (j["shard"]["index"].get<long>() > j["shard"]["total"].get<long>())
    throw InputError(fmt::format("'{}': 'shard.index' {} is beyond 'shard.total' {}", file, j["shard"]["index"].dump(),
                                 j["shard"]["total"].dump()));
  for (const char* k : {"version", "commit"})
    field(j, file, fmt::format("context.liftcheck.{}", k), "a string", &J::is_string);
  field(j, file, "context.set", "an object", &J::is_object);
  for (const char* k : {"engines", "filter", "set"})
    for (const J& v : field(j, file, fmt::format("plan.selection.{}", k), "an array of strings", &J::is_array))
      if (!v.is_string())
        throw InputError(fmt::format("'{}': 'plan.selection.{}' must be an array of strings", file, k));
  field(j, file, "plan.selection.sweeps", "true or false", &J::is_boolean);
  if (j["plan"]["selection"].contains("all_points"))
    field(j, file, "plan.selection.all_points", "true or false", &J::is_boolean);
  if (j["plan"]["selection"].contains("timeout_s"))
    field(j, file, "plan.selection.timeout_s", "a number", &J::is_number);
  for (const J& v : field(j, file, "plan.keys", "an array of strings", &J::is_array))
    if (!v.is_string()) throw InputError(fmt::format("'{}': 'plan.keys' must be an array of strings", file));
  for (const char* k : {"wall_s", "runs_s", "points_s"})
    if (j["context"].contains(k)) field(j, file, fmt::format("context.{}", k), "a number", &J::is_number);
  if (j["context"].contains("jobs")) field(j, file, "context.jobs", "a whole number", &J::is_number_integer);
  for (const auto& [key, r] : field(j, file, "points", "an object", &J::is_object).items())
    if (!r.is_object())
      throw InputError(fmt::format("'{}': point '{}' must be a record (an object)", file, printable(key, 80)));
}

/// Every folder's results.json, each a shard's.
std::vector<nlohmann::json> read_shards(const std::vector<std::string>& dirs) {
  std::vector<nlohmann::json> shards;
  for (const auto& d : dirs) {
    const std::string file = (std::filesystem::path(d) / "results.json").string();
    nlohmann::json j = read_results(file);
    if (!j.contains("shard") || !j["shard"].is_object() || !j.contains("plan") || !j.contains("points"))
      throw InputError(fmt::format("'{}' is not a shard's results (run validate --shard I/N)", file));
    check_shard(j, printable(file, 200));
    shards.push_back(std::move(j));
  }
  return shards;
}

/// Refuses shards of another liftcheck or another selection, a missing or repeated share; returns
/// the number of shares.
int check_shards(const std::vector<std::string>& dirs, const std::vector<nlohmann::json>& shards) {
  const auto version = [](const nlohmann::json& j) {
    return fmt::format("{} ({})", j["context"]["liftcheck"].value("version", "?"),
                       j["context"]["liftcheck"].value("commit", "?"));
  };
  const std::string mine = fmt::format("{} ({})", LIFTCHECK_VERSION, LIFTCHECK_COMMIT);
  long total = 0;
  std::set<long> seen;
  for (size_t k = 0; k < shards.size(); ++k) {
    const auto& j = shards[k];
    if (version(j) != mine)
      throw InputError(fmt::format("'{}' was made by liftcheck {}, this is liftcheck {}", dirs[k], version(j), mine));
    if (j["plan"]["selection"] != shards[0]["plan"]["selection"] || j["context"]["set"] != shards[0]["context"]["set"])
      throw InputError(fmt::format("'{}' ran other settings than '{}': {} against {}", dirs[k], dirs[0],
                                   j["plan"]["selection"].dump(), shards[0]["plan"]["selection"].dump()));
    const long i = j["shard"]["index"].get<long>(), n = j["shard"]["total"].get<long>();
    if (k == 0) total = n;
    if (n != total) throw InputError(fmt::format("'{}' is a share of {}, '{}' of {}", dirs[k], n, dirs[0], total));
    if (!seen.insert(i).second) throw InputError(fmt::format("'{}' repeats shard {}/{}", dirs[k], i, n));
  }
  if (static_cast<long>(seen.size()) != total)
    throw InputError(fmt::format("{} of {} shards given; every share is needed", seen.size(), total));
  return static_cast<int>(total);
}

/// The selection the shards ran, planned again by this liftcheck.
SuiteDef selection_of(const nlohmann::json& shard) {
  const nlohmann::json& sel = shard["plan"]["selection"];
  SuiteDef def;
  for (const auto& n : sel.at("engines")) def.engines.push_back(&engine_or_throw(n.get<std::string>()));
  def.globs = sel.at("filter").get<std::vector<std::string>>();
  for (const auto& a : sel.at("set")) def.set.push_back(split_assignment(a.get<std::string>()));
  def.sweeps = sel.at("sweeps").get<bool>();
  def.all_points = sel.value("all_points", false);
  def.timeout_s = sel.value("timeout_s", 120.0);
  return def;
}

int cmd_merge(const std::vector<std::string>& dirs, const OutputOptions& o) {
  const nlohmann::json baseline = read_baseline(o.baseline_path, o.update_baseline);
  std::vector<nlohmann::json> shards = read_shards(dirs);
  const int total = check_shards(dirs, shards);
  // The output folder is checked (and its staging folder made) before anything is printed.
  std::vector<std::pair<std::string, std::string>> inputs{{o.baseline_path, "--baseline"}};
  for (const auto& d : dirs) inputs.emplace_back(d, "shard folder");
  StagedOutput staged(o.out_dir, inputs);
  const SuiteDef def = selection_of(shards[0]);
  const SuitePlan plan = plan_suite(def);
  nlohmann::json keys = nlohmann::json::array();
  for (const SuiteItem& it : plan.items) keys.push_back(it.key);
  if (keys != shards[0]["plan"]["keys"])
    throw InputError(fmt::format("'{}' was planned with another catalogue than this liftcheck's", dirs[0]));
  std::map<std::string, nlohmann::json> by_key;
  double wall = 0.0, runs_s = 0.0, points_s = 0.0;
  for (auto& j : shards) {
    for (auto& r : j["runs"]) {
      const std::string key = run_key(r["scenario"].get<std::string>(), r["engine"].get<std::string>());
      by_key[key] = std::move(r);
    }
    for (auto& [key, r] : j["points"].items()) by_key[key] = std::move(r);
    wall = std::max(wall, j["context"].value("wall_s", 0.0));
    runs_s += j["context"].value("runs_s", 0.0);
    points_s += j["context"].value("points_s", 0.0);
  }
  size_t ran = 0;
  for (const SuiteItem& it : plan.items)
    if (it.same_as < 0 && (++ran, !by_key.count(it.key))) throw InputError(fmt::format("no shard holds '{}'", it.key));
  if (by_key.size() != ran) throw InputError("the shards hold runs outside their plan");
  nlohmann::json context = context_json(def.engines, wall);
  context["runs_s"] = runs_s;
  context["points_s"] = points_s;
  context["jobs"] = shards[0]["context"].value("jobs", 1);
  context["set"] = shards[0]["context"]["set"];
  context["merged_shards"] = total;
  context["timeout_s"] = def.timeout_s;
  nlohmann::json results = suite_results(plan, by_key, context);
  std::cout << fmt::format("merged {} shards: {} runs and points ({} run)\n", total, by_key.size(), ran);
  return finish_suite(results, o, baseline, staged);
}

}  // namespace

Command add_merge(CLI::App& app) {
  struct Options {
    std::vector<std::string> dirs;
    OutputOptions out{"build/report"};
    bool no_report = false;
  };
  auto m = std::make_shared<Options>();
  auto* merge = app.add_subcommand(
      "merge", "join the output folders of validate --shard I/N into one suite (results, JUnit, summary, report)");
  merge->add_option("dirs", m->dirs, "every shard's output folder")->required();
  merge->add_option("--out", m->out.out_dir, "output folder")->capture_default_str();
  merge->add_option("--baseline", m->out.baseline_path, "compare the merged runs with this baseline");
  add_report_memory_option(merge, m->out);
  merge->add_flag("--no-report", m->no_report, "write results.json only (no snapshots, plots or HTML)");
  return {merge, [m] {
            m->out.report = !m->no_report;
            try {
              return cmd_merge(m->dirs, m->out);
            } catch (const nlohmann::json::exception& e) {
              // A record in a shard that the checks above do not cover: the shards are bad input.
              throw InputError(
                  fmt::format("the shards do not hold the records of validate --shard: {}", printable(e.what(), 300)));
            }
          }};
}

}  // namespace liftcheck::cli
