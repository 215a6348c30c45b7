// liftcheck validate: every scenario on every configuration (or a filtered share), the sweeps, the
// report.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <iostream>
#include <thread>

#include "engines/protocol/outside.hpp"
#include "cli/baseline.hpp"
#include "cli/command.hpp"
#include "cli/interrupts.hpp"
#include "cli/lookup.hpp"
#include "cli/progress.hpp"
#include "cli/terminal.hpp"
#include "cli/shard.hpp"
#include "cli/suite_output.hpp"
#include "harness/results.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck::cli {

namespace {

struct ValidateOptions {
  std::string engine_list, filter = "*", trace_dir, shard;
  std::vector<std::string> sets;
  bool no_sweeps = false, all_points = false, no_report = false;
  bool verbose = false;  ///< each run's line whole (its reason, every failing metric), not fitted to 120 columns
  OutputOptions out{"build/report"};
  int jobs = 1;
  double timeout_s = 120.0;
  double memory_limit_mib = kDefaultRunMemoryMiB;
};

SuiteDef suite_def(const ValidateOptions& v, const RunnerDef& runner) {
  SuiteDef def;
  if (v.engine_list.empty()) {
    for (const auto& e : described_engines()) def.engines.push_back(&e);
  } else {
    for (const auto& n : split_list(v.engine_list)) def.engines.push_back(&engine_or_throw(n));
  }
  close_idle_children();  // the workers start their own
  def.globs = split_list(v.filter);
  def.sweeps = !v.no_sweeps;
  def.all_points = v.all_points;
  def.timeout_s = runner.timeout_s;
  for (const auto& a : v.sets) def.set.push_back(split_assignment(a));
  return def;
}

/// The records of a share by key, with where its time went.
struct Ran {
  Records by_key;
  SuiteTiming timing;
};

/// What a failing run's line says: its three metrics furthest out of tolerance, each with its
/// multiple of tolerance, and how many more fail ("slip_along_max 67x, slip_rms 4.2x, +2 more");
/// the reason of a known failure is for `liftcheck explain`, the figures for the report.
/// A run line's width unless --verbose: a terminal's 120 columns (the reasons are in the report).
constexpr std::size_t kLineColumns = 120;

/// Its failing metrics worst first with their multiples of tolerance, as many as fit in `width`
/// columns (all with width 0), then how many more.
std::string failing_metrics_text(const RunResult& r, std::size_t width) {
  std::vector<const Metric*> out;
  for (const Metric* m : r.metrics_worst_first())
    if (!m->pass && m->counted()) out.push_back(m);
  if (out.empty()) return printable(r.message, 1000);
  std::string text;
  for (std::size_t i = 0; i < out.size(); ++i) {
    const Metric& m = *out[i];
    const std::string item =
        fmt::format("{}{} {}", i ? ", " : "", m.name,
                    std::isfinite(m.ratio()) ? fmt::format("{:.3g}x", m.ratio())
                                             : fmt::format("{:.3g} (tolerance 0)", m.compared_error()));
    const std::string more = fmt::format(", +{} more", out.size() - i - 1);
    if (width > 0 && i > 0 && text.size() + item.size() + (i + 1 < out.size() ? more.size() : 0) > width)
      return text + fmt::format(", +{} more", out.size() - i);
    text += item;
  }
  return text;
}

/// `text` cut to `width` columns (counted in bytes: the messages are ASCII but for a dash) with an ellipsis.
std::string fitted(const std::string& text, std::size_t width) {
  if (width == 0 || text.size() <= width) return text;
  std::size_t cut = width - 3;
  while (cut > 0 && (static_cast<unsigned char>(text[cut]) & 0xC0) == 0x80) --cut;  // not inside a UTF-8 character
  return text.substr(0, cut) + "...";
}

/// A run's line: its verdict, scenario, configuration, engine seconds and what failed, in 120
/// columns (with --verbose, the whole message: the reason of a known failure, every metric).
void print_run_line(const RunResult& r, bool verbose) {
  const std::string message = printable(r.message, 1000);
  const std::string verdict = to_string(r.verdict());
  const std::string head = fmt::format("{:<15} {:<18} {:<18} {:7.3f} s  ", verdict, printable(r.scenario, 200),
                                       printable(r.engine, 200), r.wall_s);
  const std::size_t room = verbose || head.size() >= kLineColumns ? 0 : kLineColumns - head.size();
  std::string what = r.status == Status::kFail   ? failing_metrics_text(r, room)
                     : r.status == Status::kPass ? ""
                                                 : message;
  if (!r.as_expected() && r.status == Status::kFail && verbose) what += " — " + message;
  if (!r.as_expected() && r.status == Status::kPass) what = "passes, and is listed as a known failure";
  std::cout << coloured_verdict(verdict, 15) << head.substr(15) << fitted(what, room) << "\n";
}

/// One line on stderr when an outside configuration of the default suite runs the adapters of the
/// source tree this binary was built from (no outside/suite beside the binary: a copied build
/// without its outside folder), so a user sees whose adapters are judged.
void warn_if_outside_suite_is_the_source_trees(const std::vector<const EngineInfo*>& engines) {
  if (default_suite_is_beside_binary()) return;
  const std::string dir = default_suite_dir();
  for (const EngineInfo* e : engines)
    if (!e->outside.registration.empty() && e->outside.registration.rfind(dir, 0) == 0) {
      std::cerr << fmt::format(
          "liftcheck: note: no outside/suite beside the binary; the outside configurations run the adapters in {}\n",
          dir);
      return;
    }
}

/// One line per run as it ends (the points only count), the progress line between.
Ran run_share(const SuitePlan& plan, const std::vector<size_t>& which, const RunnerDef& runner, bool verbose) {
  Ran ran;
  const auto t0 = std::chrono::steady_clock::now();
  Progress progress;
  std::vector<RunResult> records;
  const auto done = [&](size_t i, const RunResult& r, double held_s) {
    const SuiteItem& it = plan.items[i];
    ran.timing.count(it, r, held_s);
    if (it.kind != SuiteItem::kRun) return;
    progress.clear();
    print_run_line(r, verbose);
    for (const auto& [k, judged] : shared_records(plan, i, r)) print_run_line(judged, verbose);  // judged again
  };
  try {
    records = run_items(plan, which, runner, done, [&](size_t n, size_t total) { progress.update(n, total); });
  } catch (const RunnerStopped& e) {
    progress.clear();
    throw Interrupted(pending_signal(), e.what());
  }
  progress.clear();
  ran.timing.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  for (size_t k = 0; k < which.size(); ++k) ran.by_key[plan.items[which[k]].key] = std::move(records[k]);
  take_shared_records(plan, ran.by_key);
  return ran;
}

/// A share: its runs and the records of its points, which merge assembles with the others'.
SuiteResults shard_results(const SuitePlan& plan, const std::vector<size_t>& which, Ran& ran, SuiteContext context,
                           int shard_index, int shard_total) {
  SuiteResults results;
  results.context = std::move(context);
  ShardInfo shard;
  shard.index = shard_index, shard.total = shard_total, shard.items = which.size();
  shard.selection = plan.selection();
  // Its items and the runs that judged their drives, in plan order (ran.by_key holds exactly those).
  for (const SuiteItem& it : plan.items) {
    shard.keys.push_back(it.key);
    const auto rec = ran.by_key.find(it.key);
    if (rec == ran.by_key.end()) continue;
    if (it.kind == SuiteItem::kRun)
      results.runs.push_back(std::move(rec->second));
    else
      results.points.emplace(it.key, std::move(rec->second));
  }
  for (const Scenario* s : plan.scenarios) results.scenarios.push_back(s->info());
  std::cout << fmt::format(
      "shard {}/{}: {} of {} runs and points ({} sweep, outcome and map points; their gates are judged at merge)\n",
      shard_index, shard_total, which.size(), plan.items.size(), results.points.size());
  results.shard = std::move(shard);
  return results;
}

int cmd_validate(const ValidateOptions& v) {
  const RunnerDef runner = runner_def(v.jobs, v.timeout_s, v.memory_limit_mib);
  OutputOptions o = v.out;
  o.threads = runner.jobs;  // --jobs 1 renders on one core too
  const std::optional<SuiteResults> baseline = read_baseline(o.baseline_path, o.update_baseline);
  const auto [shard_index, shard_total] = parse_shard(v.shard);
  SuiteDef def = suite_def(v, runner);
  std::vector<const EngineInfo*> listed = def.engines;
  TraceFolder outside;
  if (!v.trace_dir.empty()) {
    if (shard_total > 0) throw InputError("--trace-dir cannot be sharded: score the traces in one run");
    outside = read_trace_folder(v.trace_dir, def.globs);
    def.traces = outside.traces;
    def.external_name = outside.engine.name;
    listed.push_back(&outside.engine);
  }
  const SuitePlan plan = plan_suite(def);
  StagedOutput staged(o.out_dir, {{o.baseline_path, "--baseline"}, {v.trace_dir, "--trace-dir"}});

  const std::vector<size_t> which =
      shard_share(plan, shard_total > 0 ? shard_index : 1, shard_total > 0 ? shard_total : 1);
  warn_if_outside_suite_is_the_source_trees(listed);
  Ran ran = run_share(plan, which, runner, v.verbose);
  SuiteContext context = suite_context(listed, ran.timing, runner, def.set);
  SuiteResults results = shard_total > 0 ? shard_results(plan, which, ran, std::move(context), shard_index, shard_total)
                                         : suite_results(plan, ran.by_key, std::move(context));
  return finish_suite(results, o, baseline, staged);
}

}  // namespace

Command add_validate(CLI::App& app) {
  auto v = std::make_shared<ValidateOptions>();
  v->jobs = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  auto* validate = app.add_subcommand("validate", "run every scenario on every engine and write the report");
  validate->add_option("--engines", v->engine_list,
                       "comma-separated engine configurations (default: all; see 'liftcheck engines')");
  validate->add_option("--filter", v->filter, "glob on scenario names (comma-separated globs: any may match)")
      ->capture_default_str();
  validate->add_option("--out", v->out.out_dir, "output folder")->capture_default_str();
  validate->add_option(
      "--baseline", v->out.baseline_path,
      "compare the runs and points made with this baseline (data/baselines/default.json): a regression "
      "or a metric grown by more than --worse-factor exits 1");
  validate->add_flag("--update-baseline", v->out.update_baseline,
                     "rewrite the --baseline file from this run instead of comparing");
  validate
      ->add_option("--set", v->sets,
                   "KEY=VALUE for every run whose scenario has that parameter or whose configuration has that setting "
                   "(repeatable; the sweeps keep their own values)")
      ->allow_extra_args(false);
  validate->add_option(
      "--trace-dir", v->trace_dir,
      "score every SCENARIO.csv (or .json) in this folder as a run of the configuration named after it");
  validate->add_flag("--no-sweeps", v->no_sweeps, "skip the parameter sweeps");
  validate->add_flag("--verbose,-v", v->verbose,
                     "print each run's line whole (every failing metric, a run's message) instead of 120 columns");
  validate->add_flag("--all-points", v->all_points,
                     "run the parameter sweeps, the outcome grid and the map's axes also on the configurations "
                     "registered for fewer points (\"points\": \"map\" or \"runs\")");
  validate->add_flag("--no-report", v->no_report, "write results.json only (no snapshots, plots or HTML)");
  validate->add_option("--jobs,-j", v->jobs, "runs at once (default: the number of cores)")->capture_default_str();
  validate
      ->add_option("--timeout", v->timeout_s,
                   "limit of each run's or sweep point's own CPU time in seconds: beyond it the engine is stopped and "
                   "the run is an error")
      ->capture_default_str();
  validate
      ->add_option(
          "--memory-limit", v->memory_limit_mib,
          "limit of each worker process's address space in MiB: a run that needs more is an error, the suite goes on")
      ->capture_default_str();
  add_report_memory_option(validate, v->out);
  add_worse_factor_option(validate, v->out);
  validate->add_option("--shard", v->shard,
                       "run the I-th of N deterministic shares of the runs and sweep points, I/N (default: "
                       "GTEST_SHARD_INDEX+1 / GTEST_TOTAL_SHARDS when set); join them with 'liftcheck merge'");
  return {validate, [v] {
            v->out.report = !v->no_report;
            return cmd_validate(*v);
          }};
}

}  // namespace liftcheck::cli
