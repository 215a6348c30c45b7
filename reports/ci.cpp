#include "reports/ci.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <map>

#include "input/standing.hpp"
#include "reports/escape.hpp"

namespace liftcheck {

namespace {

std::string xml(const std::string& s) { return escape_markup(s); }

/// "expected E, measured M, error X (rel|abs), tolerance T": one metric of a record, as CI shows it.
std::string metric_text(const Metric& m) {
  return fmt::format("expected {:.9g}, measured {:.9g}, {} error {:.3g}, tolerance {:.3g}{}", m.expected, m.measured,
                     m.kind == TolKind::kRelative ? "relative" : "absolute", m.compared_error(), m.tolerance,
                     m.counted() ? "" : " (shown, not counted)");
}

/// "known failure: reason; ..." for the known-failure points of a sweep entry, one reason each.
std::string known_points_text(const SweepEngine& entry) {
  std::vector<std::string> reasons;
  for (const auto& pt : entry.points)
    if (!pt.known_failure.empty() && std::find(reasons.begin(), reasons.end(), pt.known_failure) == reasons.end())
      reasons.push_back(pt.known_failure);
  std::string out;
  for (const auto& r : reasons) out += (out.empty() ? "known failure: " : "; ") + r;
  return out;
}

/// A test case's own metrics, a line each, worst first ("METRIC: figures, N x tolerance").
std::string metrics_out(const RunResult& r) {
  std::string out;
  for (const Metric* m : r.metrics_worst_first())
    out += fmt::format("{}: {}, {:.3g} x tolerance{}\n", m->name, metric_text(*m), m->ratio(), m->pass ? "" : " OUT");
  return out.empty() ? "" : "<system-out>" + xml(out) + "</system-out>";
}

/// The verdict element of a run's test case and the counter it adds to: a true skip and a listed
/// known failure are both <skipped>, told apart by their type ("not-applicable", "known-failure");
/// a run that is as expected is never an <error> or <failure>, so the counts are zero exactly
/// when validate exits 0.
std::string verdict_element(const RunResult& r, int& failures, int& errors, int& skipped) {
  if (r.status == Status::kSkip) {
    ++skipped;
    return fmt::format("<skipped type=\"not-applicable\" message=\"{}\"/>", xml(r.message));
  }
  if (r.as_expected()) {
    if (r.status == Status::kPass) return "";
    ++skipped;
    const std::string why = r.expectation        ? r.expectation->reason
                            : r.negative_control ? "a negative control, which must fail: " + r.message
                                                 : r.message;
    return fmt::format("<skipped type=\"known-failure\" message=\"known failure: {}\"/>", xml(why));
  }
  if (r.status == Status::kError) {
    ++errors;
    return fmt::format("<error message=\"{}\"/>", xml(r.message));
  }
  ++failures;
  return fmt::format("<failure type=\"{}\" message=\"{}\"/>", xml(to_string(r.verdict())), xml(failure_text(r)));
}

/// The test suites of the runs, one per scenario in run order.
std::string run_suites(const SuiteResults& results, int& tests, int& failures, int& errors) {
  std::string suites;
  for (const std::string& sc : results.scenario_order()) {
    int f = 0, e = 0, s = 0, n = 0;
    std::string cases;
    for (const RunResult& r : results.runs) {
      if (r.scenario != sc) continue;
      ++n;
      const std::string verdict = verdict_element(r, f, e, s);
      cases += fmt::format("    <testcase classname=\"{}\" name=\"{}\" time=\"{:.6f}\">{}{}</testcase>\n", xml(sc),
                           xml(r.engine), r.wall_s, verdict, metrics_out(r));
    }
    tests += n, failures += f, errors += e;
    suites += fmt::format(
        "  <testsuite name=\"{}\" tests=\"{}\" failures=\"{}\" errors=\"{}\" skipped=\"{}\">\n{}  </testsuite>\n",
        xml(sc), n, f, e, s, cases);
  }
  return suites;
}

/// The sweeps' gates: a suite per sweep, a case per engine.
std::string sweep_suites(const SuiteResults& results, int& tests, int& failures) {
  std::string suites;
  for (const Sweep& sw : results.sweeps) {
    int f = 0, sk = 0;
    std::string cases;
    for (const SweepEngine& entry : sw.engines) {
      cases +=
          fmt::format("    <testcase classname=\"sweep.{}\" name=\"{}\" time=\"0\">", xml(sw.name), xml(entry.engine));
      if (!entry.gate.pass) {
        cases += fmt::format("<failure message=\"{}\"/>", xml(fmt::format("{}", fmt::join(entry.gate.problems, "; "))));
        ++f;
      } else if (entry.gate.points_known_failure > 0 && entry.gate.points_pass == 0) {
        cases += fmt::format("<skipped type=\"known-failure\" message=\"{}\"/>", xml(known_points_text(entry)));
        ++sk;
      }
      cases += "</testcase>\n";
    }
    tests += static_cast<int>(sw.engines.size()), failures += f;
    suites += fmt::format(
        "  <testsuite name=\"sweep.{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" skipped=\"{}\">\n{}  </testsuite>\n",
        xml(sw.name), sw.engines.size(), f, sk, cases);
  }
  if (results.outcomes) {
    int f = 0;
    std::string cases;
    for (const OutcomeEngine& e : results.outcomes->engines) {
      cases += fmt::format("    <testcase classname=\"sweep.{}\" name=\"{}\" time=\"0\">", xml(results.outcomes->name),
                           xml(e.engine));
      if (!e.gate.pass)
        cases += fmt::format("<failure message=\"{}\"/>", xml(fmt::format("{}", fmt::join(e.gate.problems, "; ")))),
            ++f;
      cases += "</testcase>\n";
    }
    tests += static_cast<int>(results.outcomes->engines.size()), failures += f;
    suites += fmt::format(
        "  <testsuite name=\"sweep.{}\" tests=\"{}\" failures=\"{}\" errors=\"0\" skipped=\"0\">\n{}  </testsuite>\n",
        xml(results.outcomes->name), results.outcomes->engines.size(), f, cases);
  }
  return suites;
}

/// A suite of the configurations' standings: a case each, its counts and worst failure as its message.
std::string standing_suite(const SuiteResults& results, int& tests, int& failures) {
  std::string cases;
  int f = 0;
  for (const Standing& s : standings(results)) {
    const std::string text = s.counts_text() + (s.worst ? "; worst " + s.worst_text() : "");
    cases += fmt::format(
        "    <testcase classname=\"standing\" name=\"{}\" time=\"0\">{}<system-out>{}</system-out></testcase>\n",
        xml(s.engine), s.unexpected > 0 ? fmt::format("<failure message=\"{}\"/>", xml(text)) : "", xml(text));
    f += s.unexpected > 0;
    ++tests;
  }
  failures += f;
  return fmt::format(
      "  <testsuite name=\"standing\" tests=\"{}\" failures=\"{}\" errors=\"0\" skipped=\"0\">\n{}  </testsuite>\n",
      results.context.engines.size(), f, cases);
}

}  // namespace

std::string failure_text(const RunResult& r) {
  std::string msg = std::string(to_string(r.verdict())) + ": " + r.message;
  for (const Metric* m : r.metrics_worst_first())
    if (!m->pass && m->counted()) msg += fmt::format("; {}: {}", m->name, metric_text(*m));
  return msg;
}

std::string junit_xml(const SuiteResults& results) {
  int tests = 0, failures = 0, errors = 0;
  std::string suites = run_suites(results, tests, failures, errors);
  suites += sweep_suites(results, tests, failures);
  suites += standing_suite(results, tests, failures);
  // What else makes validate exit 1: the baseline's regressions and a report that could not be built.
  const Summary sum = summarize(results);
  const std::vector<std::string> none;
  const std::vector<std::string>& report_errors = results.report ? results.report->errors : none;
  const std::string report_msg = fmt::format("{}", fmt::join(report_errors, "; "));
  const int gate_failures = (sum.baseline_problems > 0) + !report_errors.empty();
  suites += fmt::format(
      "  <testsuite name=\"liftcheck\" tests=\"2\" failures=\"{}\" errors=\"0\" skipped=\"0\">\n"
      "    <testcase classname=\"liftcheck\" name=\"baseline\" time=\"0\">{}</testcase>\n"
      "    <testcase classname=\"liftcheck\" name=\"report\" time=\"0\">{}</testcase>\n  </testsuite>\n",
      gate_failures,
      sum.baseline_problems > 0
          ? fmt::format("<failure message=\"{} regressions or metrics worse against the baseline\"/>",
                        sum.baseline_problems)
          : "",
      report_errors.empty() ? "" : fmt::format("<failure message=\"{}\"/>", xml(report_msg)));
  tests += 2, failures += gate_failures;
  // junit-10.xsd (Jenkins' xunit plugin) allows no "skipped" on <testsuites>: it is per suite.
  return fmt::format(
      "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<testsuites name=\"liftcheck\" tests=\"{}\" failures=\"{}\" "
      "errors=\"{}\">\n{}</testsuites>\n",
      tests, failures, errors, suites);
}

namespace {

/// summary.md's table, a row per configuration (it reads in a narrow pull-request comment): its
/// runs passed, known failures, skipped and not as expected, and its worst failure (the standing).
std::string configuration_table(const SuiteResults& results) {
  std::string md =
      "| configuration | ✅ pass | 🟦 known | – skip | ❌ not as expected | worst known failure |\n"
      "|---|--:|--:|--:|--:|---|\n";
  for (const Standing& s : standings(results))
    md += fmt::format("| {} | {} | {} | {} | {} | {} |\n", escape_markdown(s.engine), s.pass, s.known, s.skip,
                      s.unexpected == 0 ? "0" : fmt::format("**{}**", s.unexpected), escape_markdown(s.worst_text()));
  return md +
         "\n✅ pass · 🟦 known failure (listed with its reason in harness/expectations.json, or a negative control "
         "failing as it must) · – skip · ❌ fail, error or unexpected pass\n";
}

/// The baseline's regressions and worsened metrics, then its counts.
std::string baseline_markdown(const BaselineComparison& b) {
  const ResultsDiff& d = b.diff;
  std::string md;
  for (const auto& r : d.regressions)
    md += fmt::format("- REGRESSION **{}** on {}: {} → {} ({})\n", escape_markdown(r.scenario), markdown_code(r.engine),
                      escape_markdown(r.from), escape_markdown(r.to), escape_markdown(r.message));
  const auto metric_lines = [&](const char* kind, const std::vector<DiffFinding>& list, std::size_t most) {
    std::size_t n = 0;
    for (const auto& r : list) {
      if (++n > most) {
        md += fmt::format("- … and {} more {} (the report lists every one)\n", list.size() - most, kind);
        break;
      }
      md += r.metric == "outcome"
                ? fmt::format("- {} {}: {} (was {})\n", kind, markdown_code(r.sweep), r.to, r.from)
                : fmt::format("- {} **{}**: {} {} (was {}), {:.3g} of tolerance (was {:.3g})\n", kind,
                              escape_markdown(finding_name(r)), escape_markdown(r.metric), r.head_measured.dump(),
                              r.base_measured.dump(), r.head_ratio, r.base_ratio);
    }
  };
  metric_lines("worse", d.worse, 1000);
  metric_lines("moved", d.moved, 40);
  return fmt::format(
      "### Against the baseline ({}, worse: an error grown more than {:g}×)\n\n{}{} regressions, {} metrics worse, "
      "{} fixed, {} better, {} moved\n\n",
      escape_markdown(b.file), b.worse_factor, md, d.regressions.size(), d.worse.size(), d.fixed.size(),
      d.better.size(), d.moved.size());
}

}  // namespace

std::string summary_markdown(const SuiteResults& results, const std::string& report_link) {
  const Summary sum = summarize(results);
  // The marker lets CI find and update its own comment on a pull request instead of adding one.
  std::string md = "<!-- liftcheck-summary -->\n## liftcheck validation\n\n";
  md += fmt::format(
      "**{}** — {} runs: {} pass, {} known failures, {} unexpected passes, {} fail, {} error, {} skip; {} sweep gates, "
      "{} failed.{}\n\n",
      sum.unexpected() == 0 ? "all as expected" : fmt::format("{} unexpected", sum.unexpected()), sum.total, sum.pass,
      sum.known, sum.unexpected_pass, sum.fail, sum.error, sum.skip, sum.sweep_gates, sum.sweep_gates_failed,
      report_link.empty()
          ? ""
          : fmt::format(
                " [Report]({}){}", report_link,
                report_link.find("/actions/runs/") != std::string::npos ? " (the run's artifact `report`)" : ""));
  if (results.baseline) md += baseline_markdown(*results.baseline);
  // What is not as expected comes first.
  std::string bad;
  for (const RunResult& r : results.runs)
    if (!r.as_expected())
      bad += fmt::format("- **{}** on {}: {}\n", escape_markdown(r.scenario), markdown_code(r.engine),
                         escape_markdown(failure_text(r)));
  for (const GateRef& g : gates_of(results))
    if (!g.gate->pass)
      bad += fmt::format("- sweep **{}** on {}: {}\n", escape_markdown(g.sweep), markdown_code(g.engine),
                         escape_markdown(fmt::format("{}", fmt::join(g.gate->problems, "; "))));
  if (!bad.empty()) md += "### Not as expected\n\n" + bad + "\n";
  md += configuration_table(results);
  return md;
}

}  // namespace liftcheck
