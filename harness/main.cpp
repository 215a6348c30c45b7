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

#include "harness/external.hpp"
#include "harness/results.hpp"
#include "harness/suggest.hpp"
#include "liftcheck_version.hpp"
#include "harness/runner.hpp"
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
  if (json) {
    std::cout << context_json([] {
      std::vector<const EngineInfo*> all;
      for (const auto& e : engines()) all.push_back(&e);
      return all;
    }(), 0.0)["engines"].dump(2) << "\n";
    return 0;
  }
  for (const auto& e : engines()) {
    std::vector<std::string> vehicles;
    if (e.make_car) vehicles.push_back("car");
    if (e.make_disks) vehicles.push_back("disks");
    std::cout << fmt::format("{}  [{} {}; {}{}; colour {}]\n  {}\n", e.name, e.library, e.version, fmt::join(vehicles, ", "),
                             e.is_reference ? "; the reference" : "", e.color, e.description);
    for (const auto& [k, v] : e.settings) std::cout << fmt::format("    {:<22} {}\n", k, v);
    for (const SettingSpec& k : e.knobs)
      std::cout << fmt::format("    --set {:<16} {} ({}): {}; default {}, {}\n", k.key, k.vehicle, k.kind == SettingSpec::kChoice ? "choice" : k.kind == SettingSpec::kInteger ? "integer" : "real",
                               k.help, k.default_text, k.range_text());
  }
  return 0;
}

void print_record(const RunRecord& r) {
  std::cout << fmt::format("{} on {}: {}{}\n", r.scenario, r.engine, r.verdict(),
                           r.message.empty() ? "" : " (" + r.message + ")");
  if (r.known)
    std::cout << fmt::format("  {}: {}\n  measured when reviewed: {}\n",
                             r.as_expected() ? "known failure" : "listed as a known failure (harness/expectations.json)", r.known->reason, r.known->measured);
  std::cout << fmt::format("  {:<20} {:>14} {:>14} {:>10} {:>10} {:>10}  {}\n", "metric", "expected", "measured",
                           "abs_err", "rel_err", "tolerance", "");
  for (const auto& m : r.metrics)
    std::cout << fmt::format("  {:<20} {:>14.8g} {:>14.8g} {:>10.3g} {:>10.3g} {:>6.3g} {:<3} {} {}\n", m.name,
                             m.expected, m.measured, m.abs_error, m.rel_error, m.tolerance,
                             m.kind == TolKind::kRelative ? "rel" : "abs", m.unit, m.informational ? "info" : m.pass ? "ok" : "FAIL");
}

int cmd_run(const std::string& scenario, const std::string& engine, const std::vector<std::string>& sets, bool json) {
  const Scenario& s = scenario_or_throw(scenario);
  const EngineInfo& e = engine_or_throw(engine);
  const Overrides ov = overrides_or_throw(sets, s, &e);
  const RunRecord r = run_scenario(s, e, ov);
  if (json) std::cout << r.to_json().dump() << "\n";
  else print_record(r);
  return r.as_expected() ? 0 : 1;
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
  else print_record(r);
  return r.as_expected() ? 0 : 1;
}

int cmd_validate(const std::string& engine_list, const std::string& filter, const std::string& out_dir, bool sweeps,
                 bool report, const std::string& trace_dir, const std::vector<std::string>& sets, const std::string& baseline_path,
                 bool update_baseline) {
  if (update_baseline && baseline_path.empty()) throw InputError("--update-baseline needs --baseline FILE");
  // Read before anything runs: a malformed baseline stops validate at once.
  nlohmann::json baseline;
  if (!baseline_path.empty() && !update_baseline) baseline = read_results(baseline_path);
  std::vector<const EngineInfo*> es;
  if (engine_list.empty()) {
    for (const auto& e : engines()) es.push_back(&e);
  } else {
    for (const auto& n : split_list(engine_list)) es.push_back(&engine_or_throw(n));
  }
  if (es.empty()) throw InputError("--engines names no engine");
  const std::vector<std::string> globs = split_list(filter);
  const auto matches = [&](const std::string& name) {
    for (const auto& g : globs)
      if (fnmatch(g.c_str(), name.c_str(), 0) == 0) return true;
    return false;
  };
  std::vector<const Scenario*> ss;
  for (const auto& s : scenarios())
    if (matches(s.name)) ss.push_back(&s);
  if (ss.empty()) throw InputError(fmt::format("no scenario matches '{}'", filter));

  // An outside simulator: the folder's name is its configuration, each SCENARIO.csv (or .json) in
  // it a run. Every trace is read before anything runs, so a malformed one stops validate at once.
  std::map<std::string, Trace> traces;
  EngineInfo external;
  if (!trace_dir.empty()) {
    const std::filesystem::path dir(trace_dir);
    if (!std::filesystem::is_directory(dir)) throw InputError(fmt::format("--trace-dir '{}' is not a folder", trace_dir));
    external.name = std::filesystem::absolute(dir).lexically_normal().filename().string();
    if (external.name.empty()) external.name = std::filesystem::absolute(dir).lexically_normal().parent_path().filename().string();
    if (external.name.empty() || find_engine(external.name))
      throw InputError(fmt::format("--trace-dir '{}': its name '{}' must not be a built-in configuration's", trace_dir, external.name));
    for (const Scenario* s : ss)
      for (const char* ext : {".csv", ".json"})
        if (const auto f = dir / (s->name + ext); std::filesystem::exists(f) && !traces.count(s->name)) traces[s->name] = read_trace(f, s->vehicle);
    if (traces.empty()) throw InputError(fmt::format("--trace-dir '{}' holds no SCENARIO.csv or .json for the scenarios run", trace_dir));
    external.library = "external";
    external.version = "-";
    external.description = fmt::format("a simulator outside liftcheck, scored from the traces in {}", trace_dir);
    external.color = "#7f7f7f";
    external.contact_dynamics = false;
  }

  // --set applies to every run whose scenario has the parameter or whose configuration has the
  // setting for the scenario's vehicle; a key no run takes is an input error.
  Overrides global;
  for (const auto& a : sets) global.push_back(split_assignment(a));
  const auto overrides_for = [&](const Scenario& s, const EngineInfo& e) {
    Overrides ov;
    for (const auto& [key, value] : global) {
      const bool param = std::any_of(s.params.begin(), s.params.end(), [&](const ParamSpec& p) { return p.key == key; });
      const bool knob = std::any_of(e.knobs.begin(), e.knobs.end(), [&](const SettingSpec& k) { return k.key == key && k.vehicle == s.vehicle; });
      if (param || knob) ov.emplace_back(key, value);
    }
    return ov;
  };
  for (const auto& [key, value] : global) {
    bool taken = false;
    for (const Scenario* s : ss)
      for (const EngineInfo* e : es)
        for (const auto& kv : overrides_for(*s, *e)) taken = taken || kv.first == key;
    if (!taken) throw InputError(fmt::format("--set {}: no scenario run here has a parameter or setting '{}'", key, key));
  }

  const std::filesystem::path out(out_dir);
  std::error_code ec;
  std::filesystem::create_directories(out, ec);
  if (ec || !std::filesystem::is_directory(out))
    throw InputError(fmt::format("cannot create output folder '{}'", out_dir));

  const auto t0 = std::chrono::steady_clock::now();
  std::vector<RunRecord> runs;
  bool all_pass = true;
  for (const Scenario* s : ss)
    for (const EngineInfo* e : es) {
      RunRecord r;
      try {
        r = run_scenario(*s, *e, overrides_for(*s, *e));
      } catch (const InputError& err) {  // values rejected by the scenario (a defect at the defaults): reported per run
        r.scenario = s->name;
        r.engine = e->name;
        r.status = Status::kError;
        r.message = err.what();
      }
      all_pass = all_pass && r.as_expected();
      std::cout << fmt::format("{:<15} {:<22} {:<16} {:8.3f} s  {}{}\n", r.verdict(), s->name, e->name, r.wall_s, r.message,
                               r.known && r.as_expected() ? fmt::format(" (known: {})", r.known->reason) : "");
      runs.push_back(std::move(r));
    }
  for (const Scenario* s : ss) {
    if (!traces.count(s->name)) continue;
    const RunRecord r = run_scenario(*s, replay_engine(external.name, *s, traces.at(s->name)));
    all_pass = all_pass && r.as_expected();
    std::cout << fmt::format("{:<15} {:<22} {:<16} {:8.3f} s  {}\n", r.verdict(), s->name, r.engine, r.wall_s, r.message);
    runs.push_back(r);
  }
  const double runs_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const auto t_sweeps = std::chrono::steady_clock::now();
  nlohmann::json sweep_results = nlohmann::json::array();
  if (sweeps)
    for (const SweepDef& sw : sweep_catalogue()) {
      if (!matches(sw.scenario)) continue;
      const auto ts = std::chrono::steady_clock::now();
      sweep_results.push_back(run_sweep(sw, es));
      std::cout << fmt::format("sweep  {:<32} {:8.3f} s\n", sw.name,
                               std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count());
    }
  if (sweeps && matches(outcome_sweep_scenario())) {
    const auto ts = std::chrono::steady_clock::now();
    sweep_results.push_back(run_outcome_sweep(es));
    std::cout << fmt::format("sweep  {:<32} {:8.3f} s\n", "disk_outcomes",
                             std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count());
  }
  nlohmann::json maps = nlohmann::json::array();
  const MapDef& map = speed_accuracy_map();
  if (sweeps && std::any_of(map.panels.begin(), map.panels.end(), [&](const MapDef::Panel& p) { return matches(p.scenario); })) {
    const auto ts = std::chrono::steady_clock::now();
    maps.push_back(run_map(map, es));
    std::cout << fmt::format("map    {:<32} {:8.3f} s\n", map.name, std::chrono::duration<double>(std::chrono::steady_clock::now() - ts).count());
  }
  const double sweeps_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t_sweeps).count();
  // Sweeps are a gate: each engine's entry in each sweep passes or names its problems.
  int gates = 0, gates_failed = 0;
  for (const auto& sw : sweep_results)
    for (const auto& entry : sw["engines"]) {
      ++gates;
      if (entry["gate"]["pass"].get<bool>()) continue;
      ++gates_failed;
      std::cout << fmt::format("FAIL   sweep {} on {}: {}\n", sw["name"].get<std::string>(), entry["engine"].get<std::string>(),
                               fmt::join(entry["gate"]["problems"].get<std::vector<std::string>>(), "; "));
    }
  all_pass = all_pass && gates_failed == 0;
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::vector<const EngineInfo*> listed = es;
  if (!traces.empty()) listed.push_back(&external);
  nlohmann::json results = results_json(runs, context_json(listed, wall));
  results["context"]["runs_s"] = runs_s;
  results["context"]["sweeps_s"] = sweeps_s;
  // Against the baseline: only the runs made here are compared (a filtered run compares its share).
  int baseline_problems = 0;
  if (!baseline.is_null()) {
    std::set<std::pair<std::string, std::string>> ran;
    for (const auto& r : runs) ran.insert({r.scenario, r.engine});
    nlohmann::json base = baseline;
    base["runs"] = nlohmann::json::array();
    for (const auto& r : baseline["runs"])
      if (ran.count({r["scenario"].get<std::string>(), r["engine"].get<std::string>()})) base["runs"].push_back(r);
    nlohmann::json d;
    try {
      d = diff_results(base, results);
    } catch (const nlohmann::json::exception& e) {
      throw InputError(fmt::format("'{}' is not a liftcheck baseline: {}", baseline_path, e.what()));
    }
    baseline_problems = static_cast<int>(d["regressions"].size() + d["worse"].size());
    results["baseline"] = {{"file", baseline_path}, {"diff", d}};
    std::cout << "against the baseline " << baseline_path << ":\n" << diff_text(d);
    all_pass = all_pass && baseline_problems == 0;
  }
  results["summary"]["baseline_problems"] = baseline_problems;
  results["sweeps"] = sweep_results;
  results["context"]["set"] = nlohmann::json::object();
  for (const auto& [key, value] : global) results["context"]["set"][key] = value;
  results["maps"] = maps;
  results["summary"]["sweep_gates"] = gates;
  results["summary"]["sweep_gates_failed"] = gates_failed;
  results["summary"]["unexpected"] = results["summary"]["unexpected"].get<int>() + gates_failed;
  results["scenarios"] = nlohmann::json::array();
  for (const Scenario* s : ss) results["scenarios"].push_back(s->to_json());
  try {
    if (report) {
      write_report(results, out);
      std::cout << fmt::format("report {:.2f} s ({} snapshots, {} strips, {} plots){}\n", results["report"]["report_s"].get<double>(),
                               results["report"]["snapshots"].size(), results["report"]["strips"].size(),
                               results["report"]["plots"].size(),
                               results["report"]["errors"].empty() ? "" : fmt::format("; {} problems, see index.html", results["report"]["errors"].size()));
    }
    write_file_atomic(out / "junit.xml", junit_xml(results));
    write_file_atomic(out / "summary.md", summary_markdown(results, report ? "index.html" : ""));
    if (update_baseline) {
      write_file_atomic(baseline_path, baseline_json(results).dump(1) + "\n");
      std::cout << "baseline written: " << baseline_path << "\n";
    }
    write_file_atomic(out / "results.json", results.dump(1));
  } catch (const std::runtime_error& err) {
    throw InputError(err.what());
  }
  const auto& sum = results["summary"];
  std::cout << fmt::format("validate: {} runs and {} sweep gates, {} unexpected ({} pass, {} known failures, {} unexpected passes, {} fail, "
                           "{} error, {} skip; {} sweep gates failed); {}\n",
                           sum["total"].get<int>(), gates, sum["unexpected"].get<int>(), sum["pass"].get<int>(), sum["known failure"].get<int>(),
                           sum["unexpected pass"].get<int>(), sum["fail"].get<int>(), sum["error"].get<int>(), sum["skip"].get<int>(), gates_failed,
                           report ? "report: " + (out / "index.html").string() : "results: " + (out / "results.json").string());
  return all_pass ? 0 : 1;
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

int main(int argc, char** argv) {
  CLI::App app{"liftcheck: validates physics engines against exact kinematics (rolling without slipping, "
               "reaction mechanisms)"};
  app.require_subcommand(1);
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
    if (*list) return cmd_list(list_json);
    if (*engines_cmd) return cmd_engines(engines_json);
    if (*run) return cmd_run(scenario, engine, sets, run_json);
    if (*validate) return cmd_validate(engine_list, filter, out_dir, !no_sweeps, !no_report, trace_dir, validate_sets, baseline_file, update_baseline);
    if (*path_cmd) return cmd_path(scenario, sets, path_format);
    if (*score) return cmd_score(scenario, trace_file, sets, score_name, score_json);
    if (*diff) return cmd_diff(base_path, head_path, growth, diff_json);
  } catch (const InputError& e) {
    std::cerr << "liftcheck: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "liftcheck: internal error: " << e.what() << "\n";
    return 3;
  }
  return 2;
}
