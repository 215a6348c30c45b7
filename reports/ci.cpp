#include "reports/ci.hpp"

#include "reports/escape.hpp"

#include "input/record_view.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>

namespace liftcheck {

namespace {

using json = nlohmann::json;

std::string xml(const std::string& s) { return escape_markup(s); }

/// "expected E, measured M, error X (rel|abs), tolerance T": one metric of a record, as CI shows it.
std::string metric_text(const MetricView& m) {
  return fmt::format("expected {:.9g}, measured {:.9g}, {} error {:.3g}, tolerance {:.3g}{}", m.expected(),
                     m.measured(), m.relative() ? "relative" : "absolute", m.compared_error(), m.tolerance(),
                     m.counted() ? "" : " (shown, not counted)");
}

/// "known failure: reason; ..." for the known-failure points of a sweep entry, one reason each.
std::string known_points_text(const json& entry) {
  std::vector<std::string> reasons;
  for (const auto& pt : entry.value("points", json::array()))
    if (pt.contains("known_failure") &&
        std::find(reasons.begin(), reasons.end(), pt["known_failure"].get<std::string>()) == reasons.end())
      reasons.push_back(pt["known_failure"]);
  std::string out;
  for (const auto& r : reasons) out += (out.empty() ? "known failure: " : "; ") + r;
  return out;
}

/// A failure's message: what went wrong and, for each metric out of tolerance, worst first, its figures.
std::string failure_text(const json& r) {
  std::string msg = RecordView(r).verdict() + ": " + r.value("message", "");
  for (const auto& [name, m] : RecordView(r).metrics_worst_first())
    if (!m.pass() && m.counted()) msg += fmt::format("; {}: {}", name, metric_text(m));
  return msg;
}

/// A test case's own metrics, a line each, worst first ("METRIC: figures, N x tolerance").
std::string metrics_out(const json& r) {
  std::string out;
  for (const auto& [name, m] : RecordView(r).metrics_worst_first())
    out += fmt::format("{}: {}, {:.3g} x tolerance{}\n", name, metric_text(m), m.ratio(), m.pass() ? "" : " OUT");
  return out.empty() ? "" : "<system-out>" + xml(out) + "</system-out>";
}

/// The verdict element of a run's test case and the counter it adds to: a true skip and a listed
/// known failure are both <skipped>, told apart by their type ("not-applicable", "known-failure");
/// a run that is as expected is never an <error> or <failure>, so the counts are zero exactly
/// when validate exits 0.
std::string verdict_element(const json& r, int& failures, int& errors, int& skipped) {
  const std::string st = r["status"];
  if (st == "skip") {
    ++skipped;
    return fmt::format("<skipped type=\"not-applicable\" message=\"{}\"/>", xml(r["message"]));
  }
  if (record_as_expected(r)) {
    if (st == "pass") return "";
    ++skipped;
    const json& ex = r.value("expectation", json());
    return fmt::format("<skipped type=\"known-failure\" message=\"known failure: {}\"/>",
                       xml(ex.is_object() ? ex.value("reason", "") : r.value("message", "")));
  }
  if (st == "error") {
    ++errors;
    return fmt::format("<error message=\"{}\"/>", xml(r["message"]));
  }
  ++failures;
  return fmt::format("<failure type=\"{}\" message=\"{}\"/>", xml(r.value("verdict", "fail")), xml(failure_text(r)));
}

/// summary.md's table, a row per configuration (it reads in a narrow pull-request comment): its
/// runs passed, known failures, skipped and not as expected, and its furthest metric from
/// tolerance among the runs that fail, negative controls aside (multiple of tolerance, scenario,
/// metric).
std::string configuration_table(const json& results) {
  struct Row {
    int pass = 0, known = 0, skip = 0, bad = 0;
    double worst = 0.0;
    std::string where;
  };
  std::vector<std::string> engines;
  for (const auto& e : results["context"]["engines"]) engines.push_back(e["name"]);
  // A negative control must fail on every configuration: its figure is no standing.
  std::vector<std::string> controls;
  for (const auto& sc : results.value("scenarios", json::array()))
    if (sc.value("negative_control", false)) controls.push_back(sc.value("name", ""));
  std::map<std::string, Row> rows;
  for (const auto& r : results["runs"]) {
    Row& row = rows[r["engine"].get<std::string>()];
    const std::string st = r["status"], sc = r["scenario"];
    if (!record_as_expected(r))
      ++row.bad;
    else if (st == "pass")
      ++row.pass;
    else if (st == "skip")
      ++row.skip;
    else
      ++row.known;
    if (st == "pass" || st == "skip" || std::find(controls.begin(), controls.end(), sc) != controls.end()) continue;
    for (const auto& [name, m] : RecordView(r).metrics_worst_first()) {
      if (!m.counted()) continue;
      if (row.where.empty() || m.ratio() > row.worst) {
        row.worst = m.ratio();
        // A zero tolerance has no multiple: its measured figure instead.
        const std::string figure = std::isfinite(m.ratio())
                                       ? fmt::format("{:.3g}×", m.ratio())
                                       : fmt::format("{:.3g} against a zero tolerance", m.measured());
        row.where = figure + " in " + escape_markdown(sc) + " " + markdown_code(name);
      }
      break;
    }
  }
  std::string md =
      "| configuration | ✅ pass | 🟦 known | – skip | ❌ not as expected | furthest from tolerance |\n"
      "|---|--:|--:|--:|--:|---|\n";
  for (const auto& e : engines) {
    const Row& row = rows[e];
    md += fmt::format("| {} | {} | {} | {} | {} | {} |\n", escape_markdown(e), row.pass, row.known, row.skip,
                      row.bad == 0 ? "0" : fmt::format("**{}**", row.bad), row.where);
  }
  return md +
         "\n✅ pass · 🟦 known failure (listed with its reason in harness/expectations.json) · – skip · "
         "❌ fail, error or unexpected pass\n";
}

}  // namespace

std::string junit_xml(const json& results) {
  std::map<std::string, std::vector<const json*>> by;
  std::vector<std::string> order;
  for (const auto& r : results["runs"]) {
    const std::string sc = r["scenario"];
    if (!by.count(sc)) order.push_back(sc);
    by[sc].push_back(&r);
  }
  int tests = 0, failures = 0, errors = 0;
  std::string suites;
  for (const auto& sc : order) {
    int f = 0, e = 0, s = 0;
    std::string cases;
    for (const json* r : by[sc]) {
      const std::string verdict = verdict_element(*r, f, e, s);
      cases += fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{:.6f}\">{}{}</testcase>\n", xml(sc),
                           xml((*r)["engine"]), r->value("wall_s", 0.0), verdict, metrics_out(*r));
    }
    tests += static_cast<int>(by[sc].size()), failures += f, errors += e;
    suites += fmt::format(
        "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\">\n{}  </testsuite>\n",
        xml(sc), by[sc].size(), f, e, s, cases);
  }
  // The sweeps' gates: a suite per sweep, a case per engine.
  for (const auto& sw : results.value("sweeps", json::array())) {
    int f = 0, sk = 0;
    std::string cases;
    for (const auto& entry : sw["engines"]) {
      const json& gate = entry["gate"];
      cases += fmt::format("    <testcase classname=\"sweep.{}\" name=\"{}\" time=\"0\">", xml(sw["name"]),
                           xml(entry["engine"]));
      if (!gate["pass"].get<bool>()) {
        std::string msg;
        for (const auto& p : gate["problems"]) msg += (msg.empty() ? "" : "; ") + p.get<std::string>();
        cases += fmt::format("<failure message=\"{}\"/>", xml(msg));
        ++f;
      } else if (entry["gate"].value("points_known_failure", 0) > 0 && entry["gate"].value("points_pass", 0) == 0) {
        cases += fmt::format("<skipped type=\"known-failure\" message=\"{}\"/>", xml(known_points_text(entry)));
        ++sk;
      }
      cases += "</testcase>\n";
    }
    tests += static_cast<int>(sw["engines"].size()), failures += f;
    suites += fmt::format(
        "  <testsuite name=\"sweep.{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" skipped=\"{}\">\n{}  </testsuite>\n",
        xml(sw["name"]), sw["engines"].size(), f, sk, cases);
  }
  // What else makes validate exit 1: the baseline's regressions and a report that could not be built.
  const json& sum = results.value("summary", json::object());
  const int baseline = sum.value("baseline_problems", 0);
  const json report_errors = results.value("report", json::object()).value("errors", json::array());
  std::string report_msg;
  for (const auto& e : report_errors) report_msg += (report_msg.empty() ? "" : "; ") + e.get<std::string>();
  const int gate_failures = (baseline > 0) + !report_errors.empty();
  suites += fmt::format(
      "  <testsuite name=\"liftcheck\" tests=\"2\" failures=\"{}\" errors=\"0\" skipped=\"0\">\n"
      "    <testcase classname=\"liftcheck\" name=\"baseline\" time=\"0\">{}</testcase>\n"
      "    <testcase classname=\"liftcheck\" name=\"report\" time=\"0\">{}</testcase>\n  </testsuite>\n",
      gate_failures,
      baseline > 0
          ? fmt::format("<failure message=\"{} regressions or metrics grown tenfold against the baseline\"/>", baseline)
          : "",
      report_errors.empty() ? "" : fmt::format("<failure message=\"{}\"/>", xml(report_msg)));
  tests += 2, failures += gate_failures;
  // junit-10.xsd (Jenkins' xunit plugin) allows no "skipped" on <testsuites>: it is per suite.
  return fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"liftcheck\" tests=\"{}\" failures=\"{}\" "
      "errors=\"{}\">\n{}</testsuites>\n",
      tests, failures, errors, suites);
}

std::string summary_markdown(const json& results, const std::string& report_link) {
  const json& sum = results["summary"];
  // The marker lets CI find and update its own comment on a pull request instead of adding one.
  std::string md = "<!-- liftcheck-summary -->\n## liftcheck validation\n\n";
  const int unexpected = sum.value("unexpected", 0);
  md += fmt::format(
      "**{}** — {} runs: {} pass, {} known failures, {} unexpected passes, {} fail, {} error, {} skip; {} sweep gates, "
      "{} failed.{}\n\n",
      unexpected == 0 ? "all as expected" : fmt::format("{} unexpected", unexpected), sum.value("total", 0),
      sum.value("pass", 0), sum.value("known failure", 0), sum.value("unexpected pass", 0), sum.value("fail", 0),
      sum.value("error", 0), sum.value("skip", 0), sum.value("sweep_gates", 0), sum.value("sweep_gates_failed", 0),
      report_link.empty()
          ? ""
          : fmt::format(
                " [Report]({}){}", report_link,
                report_link.find("/actions/runs/") != std::string::npos ? " (the run's artifact `report`)" : ""));
  // Against the baseline, regressions and worsened metrics first.
  if (results.contains("baseline") && results["baseline"].is_object()) {
    const json& d = results["baseline"]["diff"];
    std::string b;
    for (const auto& r : d["regressions"])
      b += fmt::format("- REGRESSION **{}** on {}: {} → {} ({})\n", r["scenario"].get<std::string>(),
                       markdown_code(r["engine"].get<std::string>()), r["from"].get<std::string>(),
                       r["to"].get<std::string>(), escape_markdown(r["message"].get<std::string>()));
    for (const auto& r : d["worse"])
      b += fmt::format("- worse **{}** on {}: {} measured {} (was {}), {:.3g} of tolerance (was {:.3g})\n",
                       r["scenario"].get<std::string>(), markdown_code(r["engine"].get<std::string>()),
                       r["metric"].get<std::string>(), r["head_measured"].dump(), r["base_measured"].dump(),
                       r["head_ratio"].get<double>(), r["base_ratio"].get<double>());
    md += fmt::format("### Against the baseline ({})\n\n{}{} regressions, {} metrics worse, {} fixed, {} better\n\n",
                      escape_markdown(results["baseline"]["file"].get<std::string>()), b, d["regressions"].size(),
                      d["worse"].size(), d["fixed"].size(), d["better"].size());
  }
  // What is not as expected comes first.
  std::string bad;
  for (const auto& r : results["runs"])
    if (!record_as_expected(r))
      bad += fmt::format("- **{}** on {}: {}\n", r["scenario"].get<std::string>(),
                         markdown_code(r["engine"].get<std::string>()), escape_markdown(failure_text(r)));
  for (const auto& sw : results.value("sweeps", json::array()))
    for (const auto& e : sw["engines"])
      if (!e["gate"]["pass"].get<bool>()) {
        std::string problems;
        for (const auto& p : e["gate"]["problems"]) problems += (problems.empty() ? "" : "; ") + p.get<std::string>();
        bad += fmt::format("- sweep **{}** on {}: {}\n", sw["name"].get<std::string>(),
                           markdown_code(e["engine"].get<std::string>()), escape_markdown(problems));
      }
  if (!bad.empty()) md += "### Not as expected\n\n" + bad + "\n";
  md += configuration_table(results);
  return md;
}

}  // namespace liftcheck
