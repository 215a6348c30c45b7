// liftcheck: validation harness for physics engines against the analytic car and disk models.
#include <CLI/CLI.hpp>
#include <chrono>
#include <filesystem>
#include <fmt/format.h>
#include <fnmatch.h>
#include <fstream>
#include <iostream>
#include <set>
#include <sstream>
#include <thread>
#include <unistd.h>
#include <csignal>
#include <cstring>

#include "engines/protocol/outside.hpp"
#include "engines/protocol/serve.hpp"
#include "harness/external.hpp"
#include "harness/results.hpp"
#include "harness/suggest.hpp"
#include "liftcheck_version.hpp"
#include "harness/runner.hpp"
#include "harness/suite.hpp"
#include "harness/sweeps.hpp"
#include "reports/ci.hpp"
#include "reports/report.hpp"

using namespace liftcheck;

namespace {

std::vector<std::string> split_list(const std::string& s) {
  std::vector<std::string> out;
  std::stringstream ss(s);
  std::string item;
  while (std::getline(ss, item, ','))
    if (!item.empty()) out.push_back(item);
  return out;
}

const Scenario& scenario_or_throw(const std::string& name) {
  if (const Scenario* s = find_scenario(name)) return *s;
  std::vector<std::string> names;
  for (const auto& s : scenarios()) names.push_back(s.name);
  throw InputError(fmt::format("unknown scenario '{}' (see 'liftcheck list'){}", printable(name), did_you_mean(name, names)));
}

const EngineInfo& engine_or_throw(const std::string& name) {
  if (const EngineInfo* e = find_engine(name)) return *e;
  std::vector<std::string> names;
  for (const auto& e : engines()) names.push_back(e.name);
  throw InputError(fmt::format("unknown engine configuration '{}' (available: {}){}", printable(name), fmt::join(names, ", "), did_you_mean(name, names)));
}

/// --set KEY=VALUE arguments for `s` (run on `e`, if given): a key that is no parameter of the
/// scenario and no setting of any configuration is refused with the nearest of the scenario's
/// parameters and the configuration's settings (the runner words a setting of another engine).
Overrides overrides_or_throw(const std::vector<std::string>& sets, const Scenario& s, const EngineInfo* e) {
  Overrides ov;
  for (const auto& a : sets) ov.push_back(split_assignment(a));
  std::vector<std::string> own, all;
  for (const auto& p : s.params) own.push_back(p.key), all.push_back(p.key);
  for (const auto& engine : engines())
    for (const SettingSpec& k : engine.knobs)
      if (k.vehicle == s.vehicle) {
        all.push_back(k.key);
        if (!e || e == &engine) own.push_back(k.key);
      }
  for (const auto& [key, value] : ov)
    if (std::find(all.begin(), all.end(), key) == all.end())
      throw InputError(fmt::format("unknown parameter '{}' for scenario '{}'{}", printable(key), s.name, did_you_mean(key, own)));
  return ov;
}

int cmd_list(bool json) {
  if (json) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& s : scenarios()) j.push_back(s.to_json());
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  for (const auto& s : scenarios()) {
    std::cout << s.name << "  [" << s.vehicle << "; " << s.equations << "]\n  " << s.summary << "\n";
    for (const auto& p : s.params)
      std::cout << fmt::format("    {:<14} {:<10} {:<6} {}\n", p.key, p.default_text, p.unit, p.help);
  }
  std::cout << "engine configurations (see 'liftcheck engines'):";
  for (const auto& e : engines()) std::cout << " " << e.name;
  std::cout << "\n";
  return 0;
}

/// Every configuration: what it is, the fixed settings it applies and the ones --set may change.
int cmd_engines(bool json) {
  const std::vector<EngineInfo>& all_engines = described_engines();
  close_idle_children();
  if (json) {
    std::cout << context_json([&] {
      std::vector<const EngineInfo*> all;
      for (const auto& e : all_engines) all.push_back(&e);
      return all;
    }(), 0.0)["engines"].dump(2) << "\n";
    return 0;
  }
  for (const auto& e : all_engines) {
    std::vector<std::string> vehicles;
    if (e.make_car) vehicles.push_back("car");
    if (e.make_disks) vehicles.push_back("disks");
    if (!e.unavailable.empty()) vehicles = {"UNAVAILABLE"};
    std::cout << fmt::format("{}  [{} {}; {}{}; {}; colour {}{}]\n  {}\n", e.name, e.library, e.version, fmt::join(vehicles, ", "),
                             e.is_reference ? "; the reference" : "", e.precision, e.color,
                             e.registration.empty() ? "" : "; outside: " + e.registration, e.description);
    for (const auto& [k, v] : e.settings) std::cout << fmt::format("    {:<22} {}\n", k, v);
    for (const SettingSpec& k : e.knobs)
      std::cout << fmt::format("    --set {:<16} {} ({}): {}; default {}, {}\n", k.key, k.vehicle, k.kind == SettingSpec::kChoice ? "choice" : k.kind == SettingSpec::kInteger ? "integer" : "real",
                               k.help, k.default_text, k.range_text());
  }
  return 0;
}

/// SIGINT or SIGTERM: the runner stops at its next event, the outputs are left as they were.
volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_signal(int sig) { g_signal = sig; }
void catch_interrupts() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}
/// Thrown when a signal stopped the work: exit 128 + the signal.
struct Interrupted : std::runtime_error {
  int sig;
  Interrupted(int s, const std::string& where) : std::runtime_error(where), sig(s) {}
};
void throw_if_interrupted(const std::string& where) {
  if (g_signal) throw Interrupted(g_signal, where);
}

RunnerDef runner_def(int jobs, double timeout_s) {
  if (jobs < 1) throw InputError(fmt::format("--jobs {} must be at least 1", jobs));
  if (!(timeout_s > 0.0) || !std::isfinite(timeout_s)) throw InputError(fmt::format("--timeout {} must be a positive number of seconds", timeout_s));
  RunnerDef r;
  r.jobs = jobs;
  r.timeout_s = timeout_s;
  r.stop = [] { return g_signal != 0; };
  // Outside engines' replies are bounded by the run's limit, here and in the worker processes.
  set_protocol_timeout(timeout_s);
  setenv("LIFTCHECK_RUN_TIMEOUT_S", fmt::format("{}", timeout_s).c_str(), 1);
  return r;
}

void print_record(const nlohmann::json& r) {
  const std::string message = r["message"];
  std::cout << fmt::format("{} on {}: {}{}\n", r["scenario"].get<std::string>(), r["engine"].get<std::string>(), r["verdict"].get<std::string>(),
                           message.empty() ? "" : " (" + message + ")");
  if (r["expectation"].is_object())
    std::cout << fmt::format("  {}: {}\n  measured when reviewed: {}\n",
                             r["as_expected"].get<bool>() ? "known failure" : "listed as a known failure (harness/expectations.json)",
                             r["expectation"]["reason"].get<std::string>(), r["expectation"]["measured"].get<std::string>());
  std::cout << fmt::format("  {:<20} {:>14} {:>14} {:>10} {:>10} {:>10}  {}\n", "metric", "expected", "measured",
                           "abs_err", "rel_err", "tolerance", "");
  const auto num = [](const nlohmann::json& v) { return v.is_number() ? v.get<double>() : NAN; };
  const nlohmann::json metrics = r["metrics"];
  for (const auto& [name, m] : metrics.items())
    std::cout << fmt::format("  {:<20} {:>14.8g} {:>14.8g} {:>10.3g} {:>10.3g} {:>6.3g} {:<3} {} {}\n", name,
                             num(m["expected"]), num(m["measured"]), num(m["abs_error"]), num(m["rel_error"]), num(m["tolerance"]),
                             m["tolerance_kind"].get<std::string>(), m["unit"].get<std::string>(),
                             m.value("informational", false) ? "info" : m["pass"].get<bool>() ? "ok" : "FAIL");
}

int cmd_run(const std::string& scenario, const std::string& engine, const std::vector<std::string>& sets, bool json, double timeout_s) {
  const Scenario& s = scenario_or_throw(scenario);
  const RunnerDef runner = runner_def(1, timeout_s);
  const EngineInfo& e = engine_or_throw(engine);
  close_idle_children();
  const Overrides ov = overrides_or_throw(sets, s, &e);
  // Bad names and values are input errors here, not error records.
  (void)Params::resolve(s.params, split_settings(s, e, ov).first, s.name);
  // In a worker process, like every validate run: a hang or a crash of the engine is an error record.
  SuitePlan plan;
  SuiteItem item;
  item.key = "run";
  item.scenario = &s, item.engine = &e, item.overrides = ov;
  plan.items.push_back(item);
  std::vector<nlohmann::json> records;
  try {
    records = run_items(plan, {0}, runner, [](size_t, const nlohmann::json&) {});
  } catch (const RunnerStopped& e) {
    throw Interrupted(g_signal, e.what());
  }
  throw_if_interrupted("during the run");
  const nlohmann::json& r = records.at(0);
  if (r.value("input_error", false)) throw InputError(r["message"].get<std::string>());
  if (json) std::cout << r.dump() << "\n";
  else print_record(r);
  return r["as_expected"].get<bool>() ? 0 : 1;
}

int cmd_path(const std::string& scenario, const std::vector<std::string>& sets, const std::string& format) {
  const Scenario& s = scenario_or_throw(scenario);
  const Overrides ov = overrides_or_throw(sets, s, nullptr);
  const nlohmann::json path = scenario_path(s, ov);
  if (format == "json") std::cout << path.dump() << "\n";
  else std::cout << path_csv(path);
  return 0;
}

int cmd_score(const std::string& scenario, const std::string& trace_file, const std::vector<std::string>& sets, const std::string& name,
              bool json) {
  const Scenario& s = scenario_or_throw(scenario);
  if (name.empty() || find_engine(name)) throw InputError(fmt::format("--name '{}' must be new (not a built-in configuration)", name));
  const Overrides ov = overrides_or_throw(sets, s, nullptr);
  const EngineInfo e = replay_engine(name, s, read_trace(trace_file, s.vehicle));
  const RunRecord r = run_scenario(s, e, ov);
  if (json) std::cout << r.to_json().dump() << "\n";
  else print_record(nlohmann::json::parse(r.to_json().dump()));
  return r.as_expected() ? 0 : 1;
}

/// The output folder, written whole or not at all: everything goes into a hidden folder beside it,
/// which replaces it at the end (an interrupted or failed run leaves the previous one as it was).
/// An existing folder is replaced only when it is a liftcheck output (it holds results.json) or
/// empty, never a folder of the user's.
class StagedOutput {
 public:
  /// The file that marks a folder as liftcheck's output (written into every output folder).
  static constexpr const char* kMarker = ".liftcheck-output";

  explicit StagedOutput(const std::string& out_dir) : out_(out_dir) {
    if (out_dir.empty()) throw InputError("--out names no folder");
    out_ = std::filesystem::weakly_canonical(std::filesystem::absolute(out_));
    if (!out_.has_filename()) out_ = out_.parent_path();
    std::error_code ec;
    // The working folder or one above it would be swapped away under the user's feet.
    const std::filesystem::path cwd = std::filesystem::weakly_canonical(std::filesystem::current_path(ec));
    const auto [o_end, c_it] = std::mismatch(out_.begin(), out_.end(), cwd.begin(), cwd.end());
    if (o_end == out_.end()) throw InputError(fmt::format("--out '{}' is the working folder or one above it: give a folder of its own", out_dir));
    if (std::filesystem::exists(out_, ec)) {
      if (!std::filesystem::is_directory(out_, ec)) throw InputError(fmt::format("--out '{}' is a file, not a folder", out_dir));
      if (!ours(out_))
        throw InputError(fmt::format("--out '{}' holds files that liftcheck did not write: not a liftcheck output folder, left alone", out_dir));
    }
    std::filesystem::create_directories(out_.parent_path(), ec);
    stage_ = out_.parent_path() / fmt::format(".{}.partial-{}", out_.filename().string(), getpid());
    std::filesystem::remove_all(stage_, ec);
    if (!std::filesystem::create_directory(stage_, ec) || ec) throw InputError(fmt::format("cannot create output folder '{}'", out_dir));
    std::ofstream(stage_ / kMarker) << "written by liftcheck: replaced whole by its next run into this folder\n";
  }
  ~StagedOutput() {
    std::error_code ec;
    if (!published_) std::filesystem::remove_all(stage_, ec);
  }
  const std::filesystem::path& stage() const { return stage_; }
  const std::filesystem::path& final_path() const { return out_; }
  /// A file of the user's (a baseline) inside the folder would be swapped away with it.
  void refuse_inside(const std::string& file, const std::string& what) const {
    if (file.empty()) return;
    const std::filesystem::path f = std::filesystem::weakly_canonical(std::filesystem::absolute(file));
    if (std::mismatch(out_.begin(), out_.end(), f.begin(), f.end()).first == out_.end())
      throw InputError(fmt::format("{} '{}' must not be inside --out '{}': that folder is replaced whole", what, file, out_.string()));
  }
  /// Swaps the staged folder in; the previous output goes only once the new one is in place. A
  /// folder that cannot be renamed (a mount point) has its entries replaced instead.
  void publish() {
    std::error_code ec;
    const std::filesystem::path old = out_.parent_path() / fmt::format(".{}.old-{}", out_.filename().string(), getpid());
    const bool had = std::filesystem::exists(out_, ec);
    if (had) std::filesystem::rename(out_, old, ec);
    if (ec) {
      replace_entries();
      return;
    }
    std::filesystem::rename(stage_, out_, ec);
    if (ec) {
      std::error_code ec2;
      if (had) std::filesystem::rename(old, out_, ec2);
      throw InputError(fmt::format("cannot write '{}': {} (the results are kept in '{}')", out_.string(), ec.message(), stage_.string()));
    }
    published_ = true;
    if (had) std::filesystem::remove_all(old, ec);
  }

 private:
  /// Empty, or marked as liftcheck's, or (written before the marker existed) nothing but the files
  /// liftcheck writes with a results.json that says it is liftcheck's.
  static bool ours(const std::filesystem::path& dir) {
    std::error_code ec;
    if (std::filesystem::is_empty(dir, ec) || std::filesystem::exists(dir / kMarker, ec)) return true;
    for (const auto& entry : std::filesystem::directory_iterator(dir, ec)) {
      const std::string name = entry.path().filename().string(), ext = entry.path().extension().string();
      const bool known = name == "results.json" || name == "junit.xml" || name == "summary.md" || name == "screenshot.png" ||
                         name == "snapshots" || name == "plots" || ext == ".html";
      if (!known) return false;
    }
    try {
      std::ifstream in(dir / "results.json");
      return nlohmann::json::parse(in).at("context").contains("liftcheck");
    } catch (const std::exception&) {
      return false;
    }
  }
  /// The folder stays (it is a mount point): its entries are removed and the staged ones copied in.
  void replace_entries() {
    std::error_code ec;
    for (const auto& entry : std::filesystem::directory_iterator(out_, ec)) std::filesystem::remove_all(entry.path(), ec);
    std::filesystem::copy(stage_, out_, std::filesystem::copy_options::recursive | std::filesystem::copy_options::overwrite_existing, ec);
    if (ec) throw InputError(fmt::format("cannot write '{}': {} (the results are kept in '{}')", out_.string(), ec.message(), stage_.string()));
    published_ = true;
    std::filesystem::remove_all(stage_, ec);
  }

  std::filesystem::path out_, stage_;
  bool published_ = false;
};

/// Where and what validate and merge write.
struct OutputOptions {
  std::string out_dir;
  bool report = true;
  std::string baseline_path;  ///< compare with it (or rewrite it)
  bool update_baseline = false;
};

/// Reads the baseline before anything runs: a malformed one stops at once.
nlohmann::json read_baseline(const OutputOptions& o) {
  if (o.update_baseline && o.baseline_path.empty()) throw InputError("--update-baseline needs --baseline FILE");
  return !o.baseline_path.empty() && !o.update_baseline ? read_results(o.baseline_path) : nlohmann::json();
}

/// The sweeps' gates, the baseline comparison (of the runs made only: a filtered or sharded run
/// compares its share), then results.json, junit.xml, summary.md and the report; the exit status.
int finish_suite(nlohmann::json& results, const OutputOptions& o, const nlohmann::json& baseline, StagedOutput& staged) {
  const std::filesystem::path out = staged.stage();
  bool all_pass = results["summary"]["unexpected"].get<int>() == 0;
  // Sweeps are a gate: each engine's entry in each sweep passes or names its problems.
  int gates = 0, gates_failed = 0;
  for (const auto& sw : results["sweeps"])
    for (const auto& entry : sw["engines"]) {
      ++gates;
      if (entry["gate"]["pass"].get<bool>()) continue;
      ++gates_failed;
      std::cout << fmt::format("FAIL   sweep {} on {}: {}\n", sw["name"].get<std::string>(), entry["engine"].get<std::string>(),
                               fmt::join(entry["gate"]["problems"].get<std::vector<std::string>>(), "; "));
    }
  all_pass = all_pass && gates_failed == 0;
  int baseline_problems = 0;
  if (!baseline.is_null()) {
    std::set<std::pair<std::string, std::string>> ran;
    for (const auto& r : results["runs"]) ran.insert({r["scenario"].get<std::string>(), r["engine"].get<std::string>()});
    nlohmann::json base = baseline;
    base["runs"] = nlohmann::json::array();
    for (const auto& r : baseline["runs"])
      if (ran.count({r["scenario"].get<std::string>(), r["engine"].get<std::string>()})) base["runs"].push_back(r);
    nlohmann::json d;
    try {
      d = diff_results(base, results);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(fmt::format("'{}' is not a liftcheck baseline: {}", o.baseline_path, e.what()));
    }
    baseline_problems = static_cast<int>(d["regressions"].size() + d["worse"].size());
    results["baseline"] = {{"file", o.baseline_path}, {"diff", d}};
    std::cout << "against the baseline " << o.baseline_path << ":\n" << diff_text(d);
    all_pass = all_pass && baseline_problems == 0;
  }
  results["summary"]["baseline_problems"] = baseline_problems;
  results["summary"]["sweep_gates"] = gates;
  results["summary"]["sweep_gates_failed"] = gates_failed;
  results["summary"]["unexpected"] = results["summary"]["unexpected"].get<int>() + gates_failed;
  try {
    if (o.report) {
      write_report(results, out);
      std::cout << fmt::format("report {:.2f} s ({} snapshots, {} strips, {} plots){}\n", results["report"]["report_s"].get<double>(),
                               results["report"]["snapshots"].size(), results["report"]["strips"].size(),
                               results["report"]["plots"].size(),
                               results["report"]["errors"].empty() ? "" : fmt::format("; {} problems, see index.html", results["report"]["errors"].size()));
    }
    write_file_atomic(out / "junit.xml", junit_xml(results));
    write_file_atomic(out / "summary.md", summary_markdown(results, o.report ? "index.html" : ""));
    write_file_atomic(out / "results.json", results.dump(1));
    throw_if_interrupted("while writing the outputs");
    staged.publish();
    // After the output folder is in place: a baseline inside it would go with the old folder.
    if (o.update_baseline) {
      write_file_atomic(o.baseline_path, baseline_json(results).dump(1) + "\n");
      std::cout << "baseline written: " << o.baseline_path << "\n";
    }
  } catch (const Interrupted&) {
    throw;
  } catch (const std::runtime_error& err) {
    throw InputError(err.what());
  }
  // A report that could not be built counts: the suite is not whole without it.
  int report_problems = 0;
  if (o.report && results.contains("report"))
    for (const auto& e : results["report"]["errors"]) {
      ++report_problems;
      std::cout << "REPORT " << e.get<std::string>() << "\n";
    }
  const auto& sum = results["summary"];
  std::cout << fmt::format("{}: {} runs and {} sweep gates, {} unexpected ({} pass, {} known failures, {} unexpected passes, {} fail, "
                           "{} error, {} skip; {} sweep gates failed); {}\n",
                           results.contains("shard") ? fmt::format("shard {}/{}", results["shard"]["index"].get<int>(), results["shard"]["total"].get<int>()) : "validate",
                           sum["total"].get<int>(), gates, sum["unexpected"].get<int>(), sum["pass"].get<int>(), sum["known failure"].get<int>(),
                           sum["unexpected pass"].get<int>(), sum["fail"].get<int>(), sum["error"].get<int>(), sum["skip"].get<int>(), gates_failed,
                           o.report ? "report: " + (staged.final_path() / "index.html").string() : "results: " + (staged.final_path() / "results.json").string());
  if (report_problems > 0) std::cout << fmt::format("the report has {} problems (listed above and in index.html)\n", report_problems);
  return all_pass && report_problems == 0 ? 0 : 1;
}

/// "I/N" (1 <= I <= N); GTEST_SHARD_INDEX (0-based) and GTEST_TOTAL_SHARDS when it is empty.
std::pair<int, int> parse_shard(const std::string& text) {
  const auto number = [](const std::string& t, const std::string& what) {
    try {
      size_t used = 0;
      const long v = std::stol(t, &used);
      if (used != t.size() || v < 0 || v > 100000) throw std::invalid_argument(t);
      return static_cast<int>(v);
    } catch (const std::logic_error&) {
      throw InputError(fmt::format("{} '{}' is not a whole number", what, t));
    }
  };
  if (text.empty()) {
    const char* index = std::getenv("GTEST_SHARD_INDEX");
    const char* total = std::getenv("GTEST_TOTAL_SHARDS");
    if (!index || !total) return {0, 0};
    const int n = number(total, "GTEST_TOTAL_SHARDS"), i = number(index, "GTEST_SHARD_INDEX");
    if (n < 1 || i >= n) throw InputError(fmt::format("GTEST_SHARD_INDEX {} is not below GTEST_TOTAL_SHARDS {}", i, n));
    return {i + 1, n};
  }
  const auto slash = text.find('/');
  if (slash == std::string::npos) throw InputError(fmt::format("--shard '{}' must be I/N, the I-th of N shares (1 <= I <= N)", text));
  const int i = number(text.substr(0, slash), "--shard index"), n = number(text.substr(slash + 1), "--shard count");
  if (n < 1 || i < 1 || i > n) throw InputError(fmt::format("--shard '{}' must be I/N with 1 <= I <= N", text));
  return {i, n};
}

/// A progress line on a terminal (rewritten in place), a plain line every tenth otherwise.
struct Progress {
  bool tty = isatty(STDOUT_FILENO) != 0;
  std::chrono::steady_clock::time_point t0 = std::chrono::steady_clock::now();
  size_t last_tenth = 0;
  bool shown = false;
  void clear() {
    if (shown) std::cout << "\r\033[K" << std::flush;
    shown = false;
  }
  void update(size_t done, size_t total) {
    const double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (tty) {
      std::cout << fmt::format("\r\033[K[{}/{}] {:.1f} s", done, total, s) << std::flush;
      shown = true;
    } else if (total > 0 && done * 10 / total > last_tenth) {
      last_tenth = done * 10 / total;
      std::cout << fmt::format("progress {}/{} runs, {:.1f} s\n", done, total, s);
    }
  }
};

int cmd_validate(const std::string& engine_list, const std::string& filter, bool sweeps, const std::string& trace_dir,
                 const std::vector<std::string>& sets, const OutputOptions& o, int jobs, const std::string& shard_text, double timeout_s) {
  const nlohmann::json baseline = read_baseline(o);
  const auto [shard_index, shard_total] = parse_shard(shard_text);
  const RunnerDef runner = runner_def(jobs, timeout_s);
  SuiteDef def;
  if (engine_list.empty()) {
    for (const auto& e : described_engines()) def.engines.push_back(&e);
  } else {
    for (const auto& n : split_list(engine_list)) def.engines.push_back(&engine_or_throw(n));
  }
  close_idle_children();  // the workers start their own
  def.globs = split_list(filter);
  def.sweeps = sweeps;
  def.timeout_s = runner.timeout_s;
  for (const auto& a : sets) def.set.push_back(split_assignment(a));

  // An outside simulator: the folder's name is its configuration, each SCENARIO.csv (or .json) in
  // it a run. Every trace is read before anything runs, so a malformed one stops validate at once.
  EngineInfo external;
  if (!trace_dir.empty()) {
    if (shard_total > 0) throw InputError("--trace-dir cannot be sharded: score the traces in one run");
    const std::filesystem::path dir(trace_dir);
    if (!std::filesystem::is_directory(dir)) throw InputError(fmt::format("--trace-dir '{}' is not a folder", trace_dir));
    external.name = std::filesystem::absolute(dir).lexically_normal().filename().string();
    if (external.name.empty()) external.name = std::filesystem::absolute(dir).lexically_normal().parent_path().filename().string();
    if (external.name.empty() || find_engine(external.name))
      throw InputError(fmt::format("--trace-dir '{}': its name '{}' must not be a built-in configuration's", trace_dir, external.name));
    for (const auto& s : scenarios())
      for (const char* ext : {".csv", ".json"})
        if (const auto f = dir / (s.name + ext); std::filesystem::exists(f) && !def.traces.count(s.name)) {
          bool wanted = false;
          for (const auto& g : def.globs) wanted = wanted || fnmatch(g.c_str(), s.name.c_str(), 0) == 0;
          if (wanted) def.traces[s.name] = read_trace(f, s.vehicle);
        }
    if (def.traces.empty()) throw InputError(fmt::format("--trace-dir '{}' holds no SCENARIO.csv or .json for the scenarios run", trace_dir));
    def.external_name = external.name;
    external.library = "external";
    external.version = "-";
    external.description = fmt::format("a simulator outside liftcheck, scored from the traces in {}", trace_dir);
    external.color = "#7f7f7f";
    external.contact_dynamics = false;
  }
  const SuitePlan plan = plan_suite(def);
  StagedOutput staged(o.out_dir);
  staged.refuse_inside(o.baseline_path, "--baseline");

  std::vector<size_t> which;
  which = shard_share(plan, shard_total > 0 ? shard_index : 1, shard_total > 0 ? shard_total : 1);
  const auto t0 = std::chrono::steady_clock::now();
  Progress progress;
  double runs_s = 0.0, points_s = 0.0;
  std::map<std::string, double> cost_by_part, cost_by_config;
  std::vector<nlohmann::json> records;
  try {
    records = run_items(plan, which, runner, [&](size_t i, const nlohmann::json& r) {
    const SuiteItem& it = plan.items[i];
    (it.kind == SuiteItem::kRun ? runs_s : points_s) += r["wall_s"].get<double>();
    // Where the time goes: engine seconds by part of the suite and by configuration.
    const std::string part = it.kind == SuiteItem::kRun ? "runs" : it.key.substr(0, it.key.find('/', it.key.find('/') + 1));
    cost_by_part[part.rfind("outcomes/", 0) == 0 ? "outcomes" : part] += r["wall_s"].get<double>();
    cost_by_config[it.engine->name] += r["wall_s"].get<double>();
    if (it.kind != SuiteItem::kRun) return;
    progress.clear();
    const bool known = r["expectation"].is_object() && r["as_expected"].get<bool>();
    std::cout << fmt::format("{:<15} {:<22} {:<16} {:8.3f} s  {}{}\n", r["verdict"].get<std::string>(), it.scenario->name, it.engine->name,
                             r["wall_s"].get<double>(), r["message"].get<std::string>(),
                             known ? fmt::format(" (known: {})", r["expectation"]["reason"].get<std::string>()) : "");
    }, [&](size_t done, size_t total) { progress.update(done, total); });
  } catch (const RunnerStopped& e) {
    progress.clear();
    throw Interrupted(g_signal, e.what());
  }
  progress.clear();
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::map<std::string, nlohmann::json> by_key;
  for (size_t k = 0; k < which.size(); ++k) by_key[plan.items[which[k]].key] = records[k];

  std::vector<const EngineInfo*> listed = def.engines;
  if (!def.traces.empty()) listed.push_back(&external);
  nlohmann::json context = context_json(listed, wall);
  context["runs_s"] = runs_s;
  context["points_s"] = points_s;
  context["engine_s_by_part"] = cost_by_part;
  context["engine_s_by_configuration"] = cost_by_config;
  context["jobs"] = runner.jobs;
  context["timeout_s"] = runner.timeout_s;
  context["set"] = nlohmann::json::object();
  for (const auto& [key, value] : def.set) context["set"][key] = value;
  nlohmann::json results;
  if (shard_total > 0) {
    // A share: its runs and the records of its points, which merge assembles with the others'.
    nlohmann::json runs = nlohmann::json::array(), points = nlohmann::json::object();
    for (size_t i : which)
      (plan.items[i].kind == SuiteItem::kRun ? runs.push_back(by_key.at(plan.items[i].key)) : (void)(points[plan.items[i].key] = by_key.at(plan.items[i].key)));
    results = results_from_records(runs, context);
    results["sweeps"] = nlohmann::json::array();
    results["maps"] = nlohmann::json::array();
    results["shard"] = {{"index", shard_index}, {"total", shard_total}, {"items", which.size()}};
    nlohmann::json keys = nlohmann::json::array();
    for (const SuiteItem& it : plan.items) keys.push_back(it.key);
    results["plan"] = {{"selection", plan.selection()}, {"keys", keys}};
    results["points"] = points;
    std::cout << fmt::format("shard {}/{}: {} of {} runs and points ({} sweep, outcome and map points; their gates are judged at merge)\n",
                             shard_index, shard_total, which.size(), plan.items.size(), points.size());
  } else {
    fill_duplicates(plan, by_key);
    const nlohmann::json assembled = assemble_suite(plan, by_key);
    results = results_from_records(assembled["runs"], context);
    results["sweeps"] = assembled["sweeps"];
    results["maps"] = assembled["maps"];
  }
  results["scenarios"] = nlohmann::json::array();
  for (const Scenario* s : plan.scenarios) results["scenarios"].push_back(s->to_json());
  return finish_suite(results, o, baseline, staged);
}

/// Joins shard folders into one suite: refuses shards of another liftcheck or another selection,
/// a missing or repeated share, then assembles the sweeps from the merged points.
int cmd_merge(const std::vector<std::string>& dirs, const OutputOptions& o) {
  const nlohmann::json baseline = read_baseline(o);
  std::vector<nlohmann::json> shards;
  for (const auto& d : dirs) {
    const std::string file = (std::filesystem::path(d) / "results.json").string();
    nlohmann::json j = read_results(file);
    if (!j.contains("shard") || !j["shard"].is_object() || !j.contains("plan") || !j.contains("points") || !j["points"].is_object())
      throw InputError(fmt::format("'{}' is not a shard's results (run validate --shard I/N)", file));
    shards.push_back(std::move(j));
  }
  const auto version = [](const nlohmann::json& j) {
    return fmt::format("{} ({})", j["context"]["liftcheck"].value("version", "?"), j["context"]["liftcheck"].value("commit", "?"));
  };
  const std::string mine = fmt::format("{} ({})", LIFTCHECK_VERSION, LIFTCHECK_COMMIT);
  int total = 0;
  std::set<int> seen;
  for (size_t k = 0; k < shards.size(); ++k) {
    const auto& j = shards[k];
    if (version(j) != mine) throw InputError(fmt::format("'{}' was made by liftcheck {}, this is liftcheck {}", dirs[k], version(j), mine));
    if (j["plan"]["selection"] != shards[0]["plan"]["selection"] || j["context"]["set"] != shards[0]["context"]["set"])
      throw InputError(fmt::format("'{}' ran other settings than '{}': {} against {}", dirs[k], dirs[0], j["plan"]["selection"].dump(), shards[0]["plan"]["selection"].dump()));
    const int i = j["shard"].value("index", 0), n = j["shard"].value("total", 0);
    if (k == 0) total = n;
    if (n != total) throw InputError(fmt::format("'{}' is a share of {}, '{}' of {}", dirs[k], n, dirs[0], total));
    if (!seen.insert(i).second) throw InputError(fmt::format("'{}' repeats shard {}/{}", dirs[k], i, n));
  }
  if (static_cast<int>(seen.size()) != total)
    throw InputError(fmt::format("{} of {} shards given; every share is needed", seen.size(), total));
  const nlohmann::json& sel = shards[0]["plan"]["selection"];
  SuiteDef def;
  for (const auto& n : sel.at("engines")) def.engines.push_back(&engine_or_throw(n.get<std::string>()));
  def.globs = sel.at("filter").get<std::vector<std::string>>();
  for (const auto& a : sel.at("set")) def.set.push_back(split_assignment(a.get<std::string>()));
  def.sweeps = sel.at("sweeps").get<bool>();
  def.timeout_s = sel.value("timeout_s", 120.0);
  const SuitePlan plan = plan_suite(def);
  nlohmann::json keys = nlohmann::json::array();
  for (const SuiteItem& it : plan.items) keys.push_back(it.key);
  if (keys != shards[0]["plan"]["keys"]) throw InputError(fmt::format("'{}' was planned with another catalogue than this liftcheck's", dirs[0]));
  std::map<std::string, nlohmann::json> by_key;
  double wall = 0.0, runs_s = 0.0, points_s = 0.0;
  for (size_t k = 0; k < shards.size(); ++k) {
    auto& j = shards[k];
    for (auto& r : j["runs"]) {
      const std::string key = fmt::format("run/{}/{}", r["scenario"].get<std::string>(), r["engine"].get<std::string>());
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
  fill_duplicates(plan, by_key);
  const nlohmann::json assembled = assemble_suite(plan, by_key);
  nlohmann::json context = context_json(def.engines, wall);
  context["runs_s"] = runs_s;
  context["points_s"] = points_s;
  context["jobs"] = shards[0]["context"].value("jobs", 1);
  context["set"] = shards[0]["context"]["set"];
  context["merged_shards"] = total;
  context["timeout_s"] = def.timeout_s;
  nlohmann::json results = results_from_records(assembled["runs"], context);
  results["sweeps"] = assembled["sweeps"];
  results["maps"] = assembled["maps"];
  results["scenarios"] = nlohmann::json::array();
  for (const Scenario* s : plan.scenarios) results["scenarios"].push_back(s->to_json());
  std::cout << fmt::format("merged {} shards: {} runs and points ({} run)\n", total, by_key.size(), ran);
  StagedOutput staged(o.out_dir);
  staged.refuse_inside(o.baseline_path, "--baseline");
  return finish_suite(results, o, baseline, staged);
}

int cmd_diff(const std::string& base_path, const std::string& head_path, double growth, bool json) {
  if (!(growth > 1.0)) throw InputError(fmt::format("--growth must be > 1 (got {})", growth));
  const nlohmann::json base = read_results(base_path), head = read_results(head_path);
  DiffDef def;
  def.growth = growth;
  nlohmann::json d;
  try {
    d = diff_results(base, head, def);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("malformed results: {}", e.what()));
  }
  if (json) std::cout << d.dump() << "\n";
  else std::cout << diff_text(d);
  return d["regressions"].empty() && d["worse"].empty() ? 0 : 1;
}

}  // namespace

/// --engine-dir DIR (anywhere on the command line) joins LIFTCHECK_ENGINE_PATH before the registry
/// is first read, and so reaches the worker processes too.
void engine_dirs_from_args(int argc, char** argv) {
  std::vector<std::string> dirs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--engine-dir" && i + 1 < argc) dirs.push_back(argv[++i]);
    else if (a.rfind("--engine-dir=", 0) == 0) dirs.push_back(a.substr(13));
  }
  if (dirs.empty()) return;
  if (const char* old = std::getenv("LIFTCHECK_ENGINE_PATH"); old && *old) dirs.push_back(old);
  setenv("LIFTCHECK_ENGINE_PATH", fmt::format("{}", fmt::join(dirs, ":")).c_str(), 1);
}

int main(int argc, char** argv) {
  engine_dirs_from_args(argc, argv);
  CLI::App app{"liftcheck: validates physics engines against exact kinematics (rolling without slipping, "
               "reaction mechanisms)"};
  app.require_subcommand(1);
  app.fallthrough();
  std::vector<std::string> engine_dir_args;  // read before parsing (engine_dirs_from_args)
  app.add_option("--engine-dir", engine_dir_args, "a folder of outside engine registrations, NAME.json (docs/protocol.md; also LIFTCHECK_ENGINE_PATH)");
  app.set_version_flag("--version", std::string(LIFTCHECK_VERSION_STRING));

  bool list_json = false;
  auto* list = app.add_subcommand("list", "list the scenarios with their parameters, defaults and units");
  list->add_flag("--json", list_json, "print JSON");

  bool engines_json = false;
  auto* engines_cmd = app.add_subcommand("engines", "list every engine configuration with its description and settings");
  engines_cmd->add_flag("--json", engines_json, "print JSON");

  std::string scenario, engine = reference_engine().name;
  std::vector<std::string> sets;
  bool run_json = false;
  auto* run = app.add_subcommand("run", "run one scenario on one engine");
  run->add_option("scenario", scenario, "scenario name (see 'liftcheck list')")->required();
  run->add_option("--engine", engine, "engine configuration (see 'liftcheck engines')")->capture_default_str();
  run->add_option("--set", sets, "override a parameter, KEY=VALUE (repeatable)")->allow_extra_args(false);
  run->add_flag("--json", run_json, "print the run record as one JSON object");
  double run_timeout = 120.0;
  run->add_option("--timeout", run_timeout, "wall-clock limit of the run in seconds: beyond it the engine is stopped and the run is an error")->capture_default_str();

  std::string engine_list, filter = "*", out_dir = "build/report";
  auto* validate = app.add_subcommand("validate", "run every scenario on every engine and write the report");
  validate->add_option("--engines", engine_list, "comma-separated engine configurations (default: all; see 'liftcheck engines')");
  validate->add_option("--filter", filter, "glob on scenario names (comma-separated globs: any may match)")->capture_default_str();
  validate->add_option("--out", out_dir, "output folder")->capture_default_str();
  std::string baseline_file;
  bool update_baseline = false;
  validate->add_option("--baseline", baseline_file, "compare the runs made with this baseline (reports/baselines/default.json): a regression or a metric grown tenfold exits 1");
  validate->add_flag("--update-baseline", update_baseline, "rewrite the --baseline file from this run instead of comparing");
  std::vector<std::string> validate_sets;
  validate->add_option("--set", validate_sets, "KEY=VALUE for every run whose scenario has that parameter or whose configuration has that setting (repeatable; the sweeps keep their own values)")->allow_extra_args(false);
  std::string trace_dir;
  validate->add_option("--trace-dir", trace_dir, "score every SCENARIO.csv (or .json) in this folder as a run of the configuration named after it");
  bool no_sweeps = false, no_report = false;
  validate->add_flag("--no-sweeps", no_sweeps, "skip the parameter sweeps");
  validate->add_flag("--no-report", no_report, "write results.json only (no snapshots, plots or HTML)");
  const int cores = std::max(1u, std::thread::hardware_concurrency());
  int jobs = cores;
  validate->add_option("--jobs,-j", jobs, "runs at once (default: the number of cores)")->capture_default_str();
  double validate_timeout = 120.0;
  validate->add_option("--timeout", validate_timeout, "wall-clock limit of each run or sweep point in seconds: beyond it the engine is stopped and the run is an error")->capture_default_str();
  std::string shard;
  validate->add_option("--shard", shard, "run the I-th of N deterministic shares of the runs and sweep points, I/N (default: GTEST_SHARD_INDEX+1 / GTEST_TOTAL_SHARDS when set); join them with 'liftcheck merge'");

  std::vector<std::string> merge_dirs;
  std::string merge_out = "build/report", merge_baseline;
  bool merge_no_report = false;
  auto* merge = app.add_subcommand("merge", "join the output folders of validate --shard I/N into one suite (results, JUnit, summary, report)");
  merge->add_option("dirs", merge_dirs, "every shard's output folder")->required();
  merge->add_option("--out", merge_out, "output folder")->capture_default_str();
  merge->add_option("--baseline", merge_baseline, "compare the merged runs with this baseline");
  merge->add_flag("--no-report", merge_no_report, "write results.json only (no snapshots, plots or HTML)");

  auto* worker = app.add_subcommand("worker", "");  // hidden: runs validate's items in a process of its own
  worker->group("");

  std::string serve_config;
  auto* serve = app.add_subcommand("serve", "serve a compiled-in configuration over the engine protocol on stdin and stdout (docs/protocol.md)");
  serve->add_option("config", serve_config, "configuration name (see 'liftcheck engines')")->required();

  std::string path_format = "csv";
  auto* path_cmd = app.add_subcommand("path", "write a scenario's commanded path (cars: t,alpha,beta; disks: N's t,cNx,cNy) for a simulator outside liftcheck");
  path_cmd->add_option("scenario", scenario, "scenario name (see 'liftcheck list')")->required();
  path_cmd->add_option("--set", sets, "override a parameter, KEY=VALUE (repeatable)")->allow_extra_args(false);
  path_cmd->add_option("--format", path_format, "csv or json")->check(CLI::IsMember({"csv", "json"}))->capture_default_str();

  std::string trace_file, score_name = "external";
  bool score_json = false;
  auto* score = app.add_subcommand("score", "score a simulator's trace of a scenario exactly as an engine run");
  score->add_option("scenario", scenario, "scenario name (see 'liftcheck list')")->required();
  score->add_option("--trace", trace_file, "CSV with a header t,alpha,beta,x,y,phi (cars) or t,cMx,cMy,cNx,cNy (disks), or JSON")->required();
  score->add_option("--set", sets, "override a parameter, KEY=VALUE (repeatable), as given to 'liftcheck path'")->allow_extra_args(false);
  score->add_option("--name", score_name, "the configuration name in the record")->capture_default_str();
  score->add_flag("--json", score_json, "print the run record as one JSON object");

  std::string base_path, head_path;
  double growth = 10.0;
  bool diff_json = false;
  auto* diff = app.add_subcommand("diff", "compare two results.json files: regressions and metrics whose errors grew");
  diff->add_option("base", base_path, "the earlier results.json")->required();
  diff->add_option("head", head_path, "the later results.json")->required();
  diff->add_option("--growth", growth, "factor by which a metric's error must grow to count as worse")->capture_default_str();
  diff->add_flag("--json", diff_json, "print the diff as one JSON object");

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "liftcheck: error: " << e.what() << "\n";
    return 2;
  }
  try {
    if (!registration_problems().empty()) throw InputError(registration_problems().front());
    if (*serve) return serve_main(serve_config);
    if (*list) return cmd_list(list_json);
    if (*engines_cmd) return cmd_engines(engines_json);
    if (*worker) {
      if (const char* t = std::getenv("LIFTCHECK_RUN_TIMEOUT_S")) set_protocol_timeout(std::strtod(t, nullptr));
      return worker_main();
    }
    catch_interrupts();
    if (*run) return cmd_run(scenario, engine, sets, run_json, run_timeout);
    if (*validate) return cmd_validate(engine_list, filter, !no_sweeps, trace_dir, validate_sets, {out_dir, !no_report, baseline_file, update_baseline}, jobs, shard, validate_timeout);
    if (*merge) return cmd_merge(merge_dirs, {merge_out, !merge_no_report, merge_baseline, false});
    if (*path_cmd) return cmd_path(scenario, sets, path_format);
    if (*score) return cmd_score(scenario, trace_file, sets, score_name, score_json);
    if (*diff) return cmd_diff(base_path, head_path, growth, diff_json);
  } catch (const Interrupted& e) {
    std::cerr << fmt::format("liftcheck: interrupted by {} {}; the previous outputs are left as they were\n", strsignal(e.sig), e.what());
    return 128 + e.sig;
  } catch (const InputError& e) {
    std::cerr << "liftcheck: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "liftcheck: internal error: " << e.what() << "\n";
    return 3;
  }
  return 2;
}
