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
#include "harness/suite_results.hpp"
#include "input/json_in.hpp"
#include "input/results_file.hpp"
#include "input/trace.hpp"  // printable
#include "liftcheck_version.hpp"

namespace liftcheck::cli {

namespace {

/// The most shares a suite is split into (as many as it has items is already more than useful).
constexpr long kMaxShards = 100000;

/// Every folder's results.json, each a shard's (decoded and checked: a malformed one is bad input).
std::vector<SuiteResults> read_shards(const std::vector<std::string>& dirs) {
  std::vector<SuiteResults> shards;
  for (const auto& d : dirs) {
    const std::string file = (std::filesystem::path(d) / "results.json").string();
    SuiteResults j = read_results(file);
    if (!j.shard || j.is_baseline)
      throw InputError(fmt::format("'{}' is not a shard's results (run validate --shard I/N)", printable(file, 200)));
    const ShardInfo& sh = *j.shard;
    if (sh.index < 1 || sh.total < 1 || sh.total > kMaxShards || sh.index > sh.total)
      throw InputError(fmt::format("'{}': shard {}/{} is not I/N with 1 <= I <= N <= {}", printable(file, 200),
                                   sh.index, sh.total, kMaxShards));
    shards.push_back(std::move(j));
  }
  return shards;
}

/// Refuses shards of another liftcheck or another selection, a missing or repeated share; returns
/// the number of shares.
int check_shards(const std::vector<std::string>& dirs, const std::vector<SuiteResults>& shards) {
  const auto version = [](const SuiteResults& j) {
    return fmt::format("{} ({})", j.context.version, j.context.commit);
  };
  const std::string mine = fmt::format("{} ({})", LIFTCHECK_VERSION, LIFTCHECK_COMMIT);
  long total = 0;
  std::set<long> seen;
  for (size_t k = 0; k < shards.size(); ++k) {
    const auto& j = shards[k];
    if (version(j) != mine)
      throw InputError(fmt::format("'{}' was made by liftcheck {}, this is liftcheck {}", dirs[k], version(j), mine));
    if (j.shard->selection != shards[0].shard->selection || j.context.set != shards[0].context.set)
      throw InputError(fmt::format("'{}' ran other settings than '{}': {} against {}", dirs[k], dirs[0],
                                   j.shard->selection.dump(), shards[0].shard->selection.dump()));
    const long i = j.shard->index, n = j.shard->total;
    if (k == 0) total = n;
    if (n != total) throw InputError(fmt::format("'{}' is a share of {}, '{}' of {}", dirs[k], n, dirs[0], total));
    if (!seen.insert(i).second) throw InputError(fmt::format("'{}' repeats shard {}/{}", dirs[k], i, n));
  }
  if (static_cast<long>(seen.size()) != total)
    throw InputError(fmt::format("{} of {} shards given; every share is needed", seen.size(), total));
  return static_cast<int>(total);
}

/// The selection the shards ran, planned again by this liftcheck.
SuiteDef selection_of(const SuiteResults& shard, const std::string& dir) {
  static const std::string kName = "the shard's selection";
  const JsonIn sel(shard.shard->selection, kName, dir);
  SuiteDef def;
  for (const auto& n : sel.strings("engines")) def.engines.push_back(&engine_or_throw(n));
  def.globs = sel.strings("filter");
  for (const auto& a : sel.strings("set")) def.set.push_back(split_assignment(a));
  def.sweeps = sel.boolean("sweeps");
  def.all_points = sel.boolean_or("all_points", false);
  def.timeout_s = sel.num_or("timeout_s", 120.0);
  return def;
}

/// Every shard's records by item key: a key given twice (in two shares) is refused.
Records records_of(std::vector<SuiteResults>& shards, const std::vector<std::string>& dirs) {
  Records by_key;
  const auto take = [&](const std::string& key, RunResult r, size_t k) {
    if (!by_key.emplace(key, std::move(r)).second)
      throw InputError(fmt::format("'{}' holds '{}', which another shard holds too", dirs[k], printable(key, 200)));
  };
  for (size_t k = 0; k < shards.size(); ++k) {
    for (RunResult& r : shards[k].runs) {
      std::string key = run_key(r.scenario, r.engine);  // before r is moved: arguments have no order
      take(key, std::move(r), k);
    }
    for (auto& [key, r] : shards[k].points) take(key, std::move(r), k);
  }
  return by_key;
}

int cmd_merge(const std::vector<std::string>& dirs, const OutputOptions& o) {
  const std::optional<SuiteResults> baseline = read_baseline(o.baseline_path, o.update_baseline);
  std::vector<SuiteResults> shards = read_shards(dirs);
  const int total = check_shards(dirs, shards);
  // The output folder is checked (and its staging folder made) before anything is printed.
  std::vector<std::pair<std::string, std::string>> inputs{{o.baseline_path, "--baseline"}};
  for (const auto& d : dirs) inputs.emplace_back(d, "shard folder");
  StagedOutput staged(o.out_dir, inputs);
  const SuiteDef def = selection_of(shards[0], dirs[0]);
  const SuitePlan plan = plan_suite(def);
  std::vector<std::string> keys;
  for (const SuiteItem& it : plan.items) keys.push_back(it.key);
  if (keys != shards[0].shard->keys)
    throw InputError(fmt::format("'{}' was planned with another catalogue than this liftcheck's", dirs[0]));
  double wall = 0.0, runs_s = 0.0, points_s = 0.0;
  for (const auto& j : shards)
    wall = std::max(wall, j.context.wall_s), runs_s += j.context.runs_s, points_s += j.context.points_s;
  const int jobs = shards[0].context.jobs;
  const Overrides set = shards[0].context.set;
  Records by_key = records_of(shards, dirs);
  size_t ran = 0;
  for (const SuiteItem& it : plan.items)
    if (it.same_as < 0 && (++ran, !by_key.count(it.key))) throw InputError(fmt::format("no shard holds '{}'", it.key));
  if (by_key.size() != ran) throw InputError("the shards hold runs outside their plan");
  SuiteContext context = context_of(def.engines, wall);
  context.runs_s = runs_s;
  context.points_s = points_s;
  context.jobs = jobs;
  context.set = set;
  context.merged_shards = total;
  context.timeout_s = def.timeout_s;
  SuiteResults results = suite_results(plan, by_key, std::move(context));
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
  add_worse_factor_option(merge, m->out);
  merge->add_flag("--no-report", m->no_report, "write results.json only (no snapshots, plots or HTML)");
  return {merge, [m] {
            m->out.report = !m->no_report;
            return cmd_merge(m->dirs, m->out);
          }};
}

}  // namespace liftcheck::cli
