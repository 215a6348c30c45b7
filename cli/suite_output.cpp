#include "cli/suite_output.hpp"

#include <cstdlib>
#include <fmt/format.h>
#include <iostream>

#include "cli/baseline.hpp"
#include "cli/interrupts.hpp"
#include "input/atomic_file.hpp"
#include "input/params.hpp"  // InputError
#include "reports/ci.hpp"
#include "reports/report.hpp"

namespace liftcheck::cli {

namespace {

struct Gates {
  int total = 0, failed = 0;
};

/// Sweeps are a gate: each engine's entry in each sweep passes or names its problems.
Gates sweep_gates(const nlohmann::json& results) {
  Gates g;
  for (const auto& sw : results["sweeps"])
    for (const auto& entry : sw["engines"]) {
      ++g.total;
      if (entry["gate"]["pass"].get<bool>()) continue;
      ++g.failed;
      std::cout << fmt::format("FAIL   sweep {} on {}: {}\n", sw["name"].get<std::string>(), entry["engine"].get<std::string>(),
                               fmt::join(entry["gate"]["problems"].get<std::vector<std::string>>(), "; "));
    }
  return g;
}

/// Where summary.md points for the report: LIFTCHECK_REPORT_URL when set; on a CI run the run's
/// page, whose artifacts hold the report (GITHUB_SERVER_URL/GITHUB_REPOSITORY/actions/runs/
/// GITHUB_RUN_ID); otherwise the report beside it. A pull-request comment needs an absolute link.
std::string report_link() {
  const auto env = [](const char* k) { const char* v = std::getenv(k); return std::string(v ? v : ""); };
  if (!env("LIFTCHECK_REPORT_URL").empty()) return env("LIFTCHECK_REPORT_URL");
  if (!env("GITHUB_SERVER_URL").empty() && !env("GITHUB_REPOSITORY").empty() && !env("GITHUB_RUN_ID").empty())
    return fmt::format("{}/{}/actions/runs/{}", env("GITHUB_SERVER_URL"), env("GITHUB_REPOSITORY"), env("GITHUB_RUN_ID"));
  return "index.html";
}

/// The report, junit.xml, summary.md and results.json into the staged folder, which is then
/// swapped in; the baseline rewritten last when asked.
void write_outputs(nlohmann::json& results, const OutputOptions& o, StagedOutput& staged) {
  const std::filesystem::path out = staged.stage();
  try {
    if (o.report) {
      ReportDef def;
      def.snapshots = o.snapshots;
      write_report(results, out, def);
      std::cout << fmt::format("report {:.2f} s ({} snapshots, {} strips, {} plots){}\n", results["report"]["report_s"].get<double>(),
                               results["report"]["snapshots"].size(), results["report"]["strips"].size(),
                               results["report"]["plots"].size(),
                               results["report"]["errors"].empty() ? "" : fmt::format("; {} problems, see index.html", results["report"]["errors"].size()));
    }
    write_file_atomic(out / "junit.xml", junit_xml(results));
    write_file_atomic(out / "summary.md", summary_markdown(results, o.report ? report_link() : ""));
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
}

/// The last line: the verdict counts and where the results are.
void print_summary(const nlohmann::json& results, const OutputOptions& o, const Gates& gates, const StagedOutput& staged) {
  const auto& sum = results["summary"];
  std::cout << fmt::format("{}: {} runs and {} sweep gates, {} unexpected ({} pass, {} known failures, {} unexpected passes, {} fail, "
                           "{} error, {} skip; {} sweep gates failed); {}\n",
                           results.contains("shard") ? fmt::format("shard {}/{}", results["shard"]["index"].get<int>(), results["shard"]["total"].get<int>()) : "validate",
                           sum["total"].get<int>(), gates.total, sum["unexpected"].get<int>(), sum["pass"].get<int>(), sum["known failure"].get<int>(),
                           sum["unexpected pass"].get<int>(), sum["fail"].get<int>(), sum["error"].get<int>(), sum["skip"].get<int>(), gates.failed,
                           o.report ? "report: " + (staged.final_path() / "index.html").string() : "results: " + (staged.final_path() / "results.json").string());
}

}  // namespace

int finish_suite(nlohmann::json& results, const OutputOptions& o, const nlohmann::json& baseline, StagedOutput& staged) {
  bool all_pass = results["summary"]["unexpected"].get<int>() == 0;
  const Gates gates = sweep_gates(results);
  all_pass = all_pass && gates.failed == 0;
  int baseline_problems = 0;
  if (!baseline.is_null()) {
    baseline_problems = compare_with_baseline(results, o.baseline_path, baseline);
    all_pass = all_pass && baseline_problems == 0;
  }
  results["summary"]["baseline_problems"] = baseline_problems;
  results["summary"]["sweep_gates"] = gates.total;
  results["summary"]["sweep_gates_failed"] = gates.failed;
  results["summary"]["unexpected"] = results["summary"]["unexpected"].get<int>() + gates.failed;
  write_outputs(results, o, staged);
  // A report that could not be built counts: the suite is not whole without it.
  int report_problems = 0;
  if (o.report && results.contains("report"))
    for (const auto& e : results["report"]["errors"]) {
      ++report_problems;
      std::cout << "REPORT " << e.get<std::string>() << "\n";
    }
  print_summary(results, o, gates, staged);
  if (report_problems > 0) std::cout << fmt::format("the report has {} problems (listed above and in index.html)\n", report_problems);
  return all_pass && report_problems == 0 ? 0 : 1;
}

int render_again(nlohmann::json& results, const OutputOptions& o, StagedOutput& staged) {
  write_outputs(results, o, staged);
  Gates gates;
  gates.total = results["summary"].value("sweep_gates", 0);
  gates.failed = results["summary"].value("sweep_gates_failed", 0);
  print_summary(results, o, gates, staged);
  return results["summary"].value("unexpected", 0) == 0 && results["summary"].value("baseline_problems", 0) == 0 ? 0 : 1;
}

}  // namespace liftcheck::cli
