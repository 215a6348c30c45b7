#include "reports/ci.hpp"

#include "harness/interrupt.hpp"
#include "reports/escape.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>

namespace liftcheck {

namespace {

using json = nlohmann::json;

std::string xml(const std::string& s) { return escape_markup(s); }

bool as_expected(const json& r) {
  if (r.contains("as_expected")) return r["as_expected"].get<bool>();
  return r["status"] == "pass" || r["status"] == "skip";
}

std::map<std::pair<std::string, std::string>, const json*> index_runs(const json& results) {
  std::map<std::pair<std::string, std::string>, const json*> m;
  for (const auto& r : results.at("runs")) m[{r.at("scenario").get<std::string>(), r.at("engine").get<std::string>()}] = &r;
  return m;
}

json merged(json a, const json& b) {
  a.update(b);
  return a;
}

/// A record's verdict ("known failure", ...), or its status in files written before verdicts.
std::string verdict_of(const json& r) { return r.value("verdict", r["status"].get<std::string>()); }

/// A number of a record; null (how a NaN or infinite value is written) or absent reads as infinite.
double number_of(const json& m, const char* key) {
  const auto it = m.find(key);
  return it != m.end() && it->is_number() ? it->get<double>() : INFINITY;
}

/// Error of a metric as a fraction of its tolerance (harness/results_file.cpp checks these fields
/// of a file read back).
double ratio(const json& m) {
  const double err = number_of(m, m.value("tolerance_kind", "abs") == "rel" ? "rel_error" : "abs_error");
  const double tol = number_of(m, "tolerance");
  double r = tol > 0 ? err / tol : (err > 0 ? INFINITY : 0.0);
  if (m.value("floor", 0.0) > 0.0) r = std::min(r, number_of(m, "abs_error") / m["floor"].get<double>());
  return r;
}

/// "expected E, measured M, error X (rel|abs), tolerance T": one metric of a record, as CI shows it.
std::string metric_text(const json& m) {
  const bool rel = m.value("tolerance_kind", "abs") == "rel";
  return fmt::format("expected {:.9g}, measured {:.9g}, {} error {:.3g}, tolerance {:.3g}{}", m["expected"].get<double>(),
                     m["measured"].get<double>(), rel ? "relative" : "absolute", m[rel ? "rel_error" : "abs_error"].get<double>(),
                     m["tolerance"].get<double>(), m.value("informational", false) ? " (shown, not counted)" : "");
}

/// A failure's message: what went wrong and, for each metric out of tolerance, its figures.
std::string failure_text(const json& r) {
  std::string msg = r.value("verdict", r["status"].get<std::string>()) + ": " + r.value("message", "");
  const json metrics = r.value("metrics", json::object());  // items() must not outlive it
  for (const auto& [name, m] : metrics.items())
    if (!m.value("pass", true) && !m.value("informational", false)) msg += fmt::format("; {}: {}", name, metric_text(m));
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
      const json metrics = r->value("metrics", json::object());  // items() must not outlive it
      for (const auto& [name, m] : metrics.items())
        props += fmt::format("    <property name=\"{} {}\" value=\"{}\"/>\n", xml((*r)["engine"]), xml(name), xml(metric_text(m)));
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
      } else if (!as_expected(*r)) {
        cases += fmt::format("<failure type=\"{}\" message=\"{}\"/>", xml(r->value("verdict", "fail")), xml(failure_text(*r)));
        ++f;
      } else if (st == "fail" && r->contains("expectation") && (*r)["expectation"].is_object()) {
        cases += fmt::format("<system-out>known failure: {}</system-out>", xml((*r)["expectation"]["reason"]));
      }
      cases += "</testcase>\n";
    }
    tests += static_cast<int>(by[sc].size()), failures += f, errors += e;
    suites += fmt::format("  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\">\n{}{}  </testsuite>\n",
                          xml(sc), by[sc].size(), f, e, s, props, cases);
  }
  // The sweeps' gates: a suite per sweep, a case per engine.
  for (const auto& sw : results.value("sweeps", json::array())) {
    int f = 0;
    std::string cases;
    for (const auto& entry : sw["engines"]) {
      const json& gate = entry["gate"];
      cases += fmt::format("    <testcase classname=\"sweep.{}\" name=\"{}\" time=\"0\">", xml(sw["name"]), xml(entry["engine"]));
      if (!gate["pass"].get<bool>()) {
        std::string msg;
        for (const auto& p : gate["problems"]) msg += (msg.empty() ? "" : "; ") + p.get<std::string>();
        cases += fmt::format("<failure message=\"{}\"/>", xml(msg));
        ++f;
      }
      cases += "</testcase>\n";
    }
    tests += static_cast<int>(sw["engines"].size()), failures += f;
    suites += fmt::format("  <testsuite name=\"sweep.{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" skipped=\"0\">\n{}  </testsuite>\n",
                          xml(sw["name"]), sw["engines"].size(), f, cases);
  }
  // junit-10.xsd (Jenkins' xunit plugin) allows no "skipped" on <testsuites>: it is per suite.
  return fmt::format("<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"liftcheck\" tests=\"{}\" failures=\"{}\" "
                     "errors=\"{}\">\n{}</testsuites>\n",
                     tests, failures, errors, suites);
}

json baseline_json(const json& results) {
  json runs = json::array();
  for (const auto& r : results["runs"]) {
    json metrics = json::object();
    for (const auto& [name, m] : r["metrics"].items()) {
      json kept = json::object();
      for (const char* k : {"expected", "measured", "abs_error", "rel_error", "tolerance", "tolerance_kind", "floor", "pass", "informational"})
        if (m.contains(k)) kept[k] = m[k];
      metrics[name] = kept;
    }
    runs.push_back({{"scenario", r["scenario"]}, {"engine", r["engine"]}, {"params", r["params"]}, {"settings", r["settings"]},
                    {"status", r["status"]}, {"verdict", r.value("verdict", r["status"].get<std::string>())},
                    {"as_expected", as_expected(r)}, {"message", r["message"]}, {"metrics", metrics}});
  }
  return {{"liftcheck_baseline", 1}, {"context", {{"liftcheck", results["context"]["liftcheck"]}}}, {"runs", runs}};
}

std::string summary_markdown(const json& results, const std::string& report_link) {
  const json& sum = results["summary"];
  std::string md = "## liftcheck validation\n\n";
  const int unexpected = sum.value("unexpected", 0);
  md += fmt::format("**{}** — {} runs: {} pass, {} known failures, {} unexpected passes, {} fail, {} error, {} skip; {} sweep gates, {} failed.{}\n\n",
                    unexpected == 0 ? "all as expected" : fmt::format("{} unexpected", unexpected), sum.value("total", 0), sum.value("pass", 0),
                    sum.value("known failure", 0), sum.value("unexpected pass", 0), sum.value("fail", 0), sum.value("error", 0),
                    sum.value("skip", 0), sum.value("sweep_gates", 0), sum.value("sweep_gates_failed", 0),
                    report_link.empty() ? "" : fmt::format(" [Report]({})", report_link));
  // Against the baseline, regressions and worsened metrics first.
  if (results.contains("baseline") && results["baseline"].is_object()) {
    const json& d = results["baseline"]["diff"];
    std::string b;
    for (const auto& r : d["regressions"])
      b += fmt::format("- REGRESSION **{}** on {}: {} → {} ({})\n", r["scenario"].get<std::string>(), markdown_code(r["engine"].get<std::string>()),
                       r["from"].get<std::string>(), r["to"].get<std::string>(), r["message"].get<std::string>());
    for (const auto& r : d["worse"])
      b += fmt::format("- worse **{}** on {}: {} measured {} (was {}), {:.3g} of tolerance (was {:.3g})\n", r["scenario"].get<std::string>(),
                       markdown_code(r["engine"].get<std::string>()), r["metric"].get<std::string>(), r["head_measured"].dump(), r["base_measured"].dump(),
                       r["head_ratio"].get<double>(), r["base_ratio"].get<double>());
    md += fmt::format("### Against the baseline ({})\n\n{}{} regressions, {} metrics worse, {} fixed, {} better\n\n",
                      escape_markdown(results["baseline"]["file"].get<std::string>()), b, d["regressions"].size(), d["worse"].size(), d["fixed"].size(),
                      d["better"].size());
  }
  // What is not as expected comes first.
  std::string bad;
  for (const auto& r : results["runs"])
    if (!as_expected(r))
      bad += fmt::format("- **{}** on {}: {}\n", r["scenario"].get<std::string>(), markdown_code(r["engine"].get<std::string>()), failure_text(r));
  for (const auto& sw : results.value("sweeps", json::array()))
    for (const auto& e : sw["engines"])
      if (!e["gate"]["pass"].get<bool>()) {
        std::string problems;
        for (const auto& p : e["gate"]["problems"]) problems += (problems.empty() ? "" : "; ") + p.get<std::string>();
        bad += fmt::format("- sweep **{}** on {}: {}\n", sw["name"].get<std::string>(), markdown_code(e["engine"].get<std::string>()), problems);
      }
  if (!bad.empty()) md += "### Not as expected\n\n" + bad + "\n";
  // The matrix.
  std::vector<std::string> engines, scenarios;
  for (const auto& e : results["context"]["engines"]) engines.push_back(e["name"]);
  std::map<std::pair<std::string, std::string>, const json*> runs;
  for (const auto& r : results["runs"]) {
    if (std::find(scenarios.begin(), scenarios.end(), r["scenario"].get<std::string>()) == scenarios.end()) scenarios.push_back(r["scenario"]);
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
  md += "\n✅ pass · 🟦 known failure (listed with its reason in harness/expectations.json) · ❌ fail or unexpected pass · 💥 error · – skip\n";
  return md;
}

json diff_results(const json& base, const json& head, const DiffDef& def) {
  json d{{"regressions", json::array()}, {"fixed", json::array()}, {"worse", json::array()},
         {"better", json::array()}, {"added", json::array()}, {"removed", json::array()}};
  const auto b = index_runs(base), h = index_runs(head);
  std::size_t compared = 0;
  for (const auto& [key, hr] : h) {
    if ((++compared & 0xFFFF) == 0) throw_if_interrupted("while comparing the results");
    const auto it = b.find(key);
    const json id{{"scenario", key.first}, {"engine", key.second}};
    if (it == b.end()) {
      d["added"].push_back(id);
      continue;
    }
    const json& br = *it->second;
    if (as_expected(br) && !as_expected(*hr))
      d["regressions"].push_back(merged(id, {{"from", verdict_of(br)}, {"to", verdict_of(*hr)}, {"message", hr->value("message", "")}}));
    else if (!as_expected(br) && as_expected(*hr))
      d["fixed"].push_back(merged(id, {{"from", verdict_of(br)}, {"to", verdict_of(*hr)}}));
    if (!br.contains("metrics") || !hr->contains("metrics") || !br["metrics"].is_object() || !(*hr)["metrics"].is_object()) continue;
    for (const auto& [name, hm] : (*hr)["metrics"].items()) {
      if (!br["metrics"].contains(name) || hm.value("informational", false)) continue;
      const json& bm = br["metrics"][name];
      const double rb = ratio(bm), rh = ratio(hm);
      const json entry = merged(id, {{"metric", name}, {"base_ratio", rb}, {"head_ratio", rh},
                                     {"base_measured", bm.value("measured", json())}, {"head_measured", hm.value("measured", json())}});
      if (rh > def.floor && rh > def.growth * rb) d["worse"].push_back(entry);
      else if (rb > def.floor && rb > def.growth * rh) d["better"].push_back(entry);
    }
  }
  for (const auto& [key, br] : b)
    if (!h.count(key)) d["removed"].push_back({{"scenario", key.first}, {"engine", key.second}});
  return d;
}

std::string diff_text(const json& d) {
  std::string t;
  for (const auto& r : d["regressions"])
    t += fmt::format("REGRESSION {} on {}: {} -> {} ({})\n", r["scenario"].get<std::string>(), r["engine"].get<std::string>(),
                     r["from"].get<std::string>(), r["to"].get<std::string>(), r["message"].get<std::string>());
  for (const auto& r : d["fixed"])
    t += fmt::format("fixed      {} on {}: {} -> {}\n", r["scenario"].get<std::string>(), r["engine"].get<std::string>(),
                     r["from"].get<std::string>(), r["to"].get<std::string>());
  for (const char* kind : {"worse", "better"})
    for (const auto& r : d[kind])
      t += fmt::format("{:<10} {} on {}: {} measured {} (was {}), {:.3g} of tolerance (was {:.3g})\n", kind, r["scenario"].get<std::string>(),
                       r["engine"].get<std::string>(), r["metric"].get<std::string>(), r["head_measured"].dump(), r["base_measured"].dump(),
                       r["head_ratio"].get<double>(), r["base_ratio"].get<double>());
  for (const char* kind : {"added", "removed"})
    for (const auto& r : d[kind])
      t += fmt::format("{:<10} {} on {}\n", kind, r["scenario"].get<std::string>(), r["engine"].get<std::string>());
  t += fmt::format("{} regressions, {} fixed, {} metrics worse, {} better, {} runs added, {} removed\n", d["regressions"].size(),
                   d["fixed"].size(), d["worse"].size(), d["better"].size(), d["added"].size(), d["removed"].size());
  return t;
}

}  // namespace liftcheck
