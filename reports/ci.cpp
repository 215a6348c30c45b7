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

/// A failure's message: what went wrong and, for each metric out of tolerance, its figures.
std::string failure_text(const json& r) {
  std::string msg = RecordView(r).verdict() + ": " + r.value("message", "");
  RecordView(r).each_metric([&](const std::string& name, const MetricView& m) {
    if (!m.pass() && m.counted()) msg += fmt::format("; {}: {}", name, metric_text(m));
  });
  return msg;
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
    // Every run's metrics as the suite's properties (the schema allows properties on suites, not
    // on cases): "CONFIGURATION METRIC" = expected, measured, error, tolerance.
    std::string props;
    for (const json* r : by[sc]) {
      RecordView(*r).each_metric([&](const std::string& name, const MetricView& m) {
        props += fmt::format("    <property name=\"{} {}\" value=\"{}\"/>\n", xml((*r)["engine"]), xml(name),
                             xml(metric_text(m)));
      });
    }
    if (!props.empty()) props = "    <properties>\n" + props + "    </properties>\n";
    for (const json* r : by[sc]) {
      const std::string st = (*r)["status"];
      cases += fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{:.6f}\">", xml(sc), xml((*r)["engine"]),
                           r->value("wall_s", 0.0));
      if (st == "skip") {
        cases += fmt::format("<skipped message=\"{}\"/>", xml((*r)["message"]));
        ++s;
      } else if (st == "error") {
        cases += fmt::format("<error message=\"{}\"/>", xml((*r)["message"]));
        ++e;
      } else if (!record_as_expected(*r)) {
        cases += fmt::format("<failure type=\"{}\" message=\"{}\"/>", xml(r->value("verdict", "fail")),
                             xml(failure_text(*r)));
        ++f;
      } else if (st == "fail" && r->contains("expectation") && (*r)["expectation"].is_object()) {
        // An expected failure is the skip convention's: a CI page shows it apart from the passes.
        cases += fmt::format("<skipped message=\"known failure: {}\"/>", xml((*r)["expectation"]["reason"]));
        ++s;
      }
      cases += "</testcase>\n";
    }
    tests += static_cast<int>(by[sc].size()), failures += f, errors += e;
    suites += fmt::format(
        "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\">\n{}{}  </testsuite>\n",
        xml(sc), by[sc].size(), f, e, s, props, cases);
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
        cases += fmt::format("<skipped message=\"{}\"/>", xml(known_points_text(entry)));
        ++sk;
      }
      cases += "</testcase>\n";
    }
    tests += static_cast<int>(sw["engines"].size()), failures += f;
    suites += fmt::format(
        "  <testsuite name=\"sweep.{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" skipped=\"{}\">\n{}  </testsuite>\n",
        xml(sw["name"]), sw["engines"].size(), f, sk, cases);
  }
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
  // The matrix.
  std::vector<std::string> engines, scenarios;
  for (const auto& e : results["context"]["engines"]) engines.push_back(e["name"]);
  std::map<std::pair<std::string, std::string>, const json*> runs;
  for (const auto& r : results["runs"]) {
    if (std::find(scenarios.begin(), scenarios.end(), r["scenario"].get<std::string>()) == scenarios.end())
      scenarios.push_back(r["scenario"]);
    runs[{r["scenario"].get<std::string>(), r["engine"].get<std::string>()}] = &r;
  }
  md += "| scenario |";
  for (const auto& e : engines) md += " " + escape_markdown(e) + " |";
  md += "\n|---|";
  for (std::size_t i = 0; i < engines.size(); ++i) md += ":-:|";
  md += "\n";
  for (const auto& sc : scenarios) {
    md += "| " + sc + " |";
    for (const auto& e : engines) {
      const auto it = runs.find({sc, e});
      std::string cell = " ";
      if (it != runs.end()) {
        const std::string v = it->second->value("verdict", (*it->second)["status"].get<std::string>());
        cell = v == "pass" ? "✅" : v == "known failure" ? "🟦" : v == "skip" ? "–" : v == "error" ? "💥" : "❌";
      }
      md += " " + cell + " |";
    }
    md += "\n";
  }
  md += "\n✅ pass · 🟦 known failure (listed with its reason in harness/expectations.json)";
  md += " · ❌ fail or unexpected pass · 💥 error · – skip\n";
  return md;
}

}  // namespace liftcheck
