// index.html (sections in reading order) and the errata's Markdown; the scenario pages are
// reports/html_scenario.cpp.
#include "reports/html.hpp"

#include <md4c-html.h>

#include "reports/html_common.hpp"

namespace liftcheck {

using namespace html;

std::string scenario_page(const std::string& scenario) {
  std::string s;
  for (char c : scenario) s += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return "scenario-" + s + ".html";
}

std::string markdown_html(const std::string& md) {
  std::string out;
  const auto sink = [](const MD_CHAR* text, MD_SIZE size, void* user) {
    static_cast<std::string*>(user)->append(text, size);
  };
  if (md_html(md.data(), static_cast<MD_SIZE>(md.size()), sink, &out, MD_DIALECT_GITHUB, 0) != 0)
    return "<pre>" + esc(md) + "</pre>\n";
  return out;
}

namespace {

/// The comparison with the baseline, when there is one.
std::string baseline_section(const SuiteResults& results) {
  if (!results.baseline) return "";
  const ResultsDiff& d = results.baseline->diff;
  std::string h = fmt::format(
      "<h2 id=\"baseline\">Against the baseline <code>{}</code></h2>\n<p>{} regressions, {} metrics worse (an error "
      "grown more than {:g}&times;), {} fixed, {} better, {} moved, {} runs added, {} removed.</p>\n",
      esc(results.baseline->file), d.regressions.size(), d.worse.size(), results.baseline->worse_factor, d.fixed.size(),
      d.better.size(), d.moved.size(), d.added.size(), d.removed.size());
  std::string rows;
  for (const auto& r : d.regressions)
    rows += fmt::format(
        "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">verdict</td><td>{}</td><td class=\"st "
        "fail\">{}</td><td class=\"l\">{}</td></tr>\n",
        esc(r.scenario), esc(r.engine), esc(r.from), esc(r.to), esc(r.message));
  const auto metric_rows = [&](const char* kind, const std::vector<DiffFinding>& list) {
    for (const auto& r : list)
      rows += fmt::format(
          "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{} ({:.3g} of tol.)</td>"
          "<td class=\"st {}\">{} ({:.3g} of tol.)</td><td class=\"l\">{}</td></tr>\n",
          esc(r.sweep.empty() ? r.scenario : r.sweep), esc(r.engine), esc(r.metric),
          esc(r.metric == "outcome" ? r.from : r.base_measured.dump()), r.base_ratio,
          std::string(kind) == "worse"    ? "fail"
          : std::string(kind) == "better" ? "pass"
                                          : "moved",
          esc(r.metric == "outcome" ? r.to : r.head_measured.dump()), r.head_ratio, kind);
  };
  metric_rows("worse", d.worse);
  metric_rows("better", d.better);
  metric_rows("moved", d.moved);
  if (!rows.empty())
    h += "<table><tr><th class=\"l\">scenario</th><th class=\"l\">configuration</th><th "
         "class=\"l\">what</th><th>before</th><th>after</th>"
         "<th class=\"l\"></th></tr>\n" +
         rows + "</table>\n";
  return h;
}

/// The counts at the top: runs by verdict, sweep gates, the settings of the run.
std::string counts_line(const SuiteResults& results) {
  const Summary sum = summarize(results);
  const int unexpected = sum.unexpected();
  const std::string set = settings_text(results.context.set);
  return fmt::format(
      "<p id=\"counts\" class=\"counts\">{} <b>{} runs</b>: {} pass, <span class=\"xfail\">&nbsp;{} known "
      "failures&nbsp;</span>, "
      "{} fail, {} unexpected passes, {} error, {} skip &middot; <b>{} sweep gates</b>, {} failed{}</p>\n",
      unexpected == 0
          ? "<span class=\"st pass\">&nbsp;ALL AS EXPECTED&nbsp;</span>"
          : fmt::format("<a class=\"st fail\" href=\"#unexpected\">&nbsp;{} NOT AS EXPECTED&nbsp;</a>", unexpected),
      sum.total, sum.pass, sum.known, sum.fail, sum.unexpected_pass, sum.error, sum.skip, sum.sweep_gates,
      sum.sweep_gates_failed, set.empty() ? "" : " &middot; settings of this run: <code>" + esc(set) + "</code>");
}

/// A run not as expected: its failing metrics worst first with their figures, then its message.
std::string unexpected_row(const RunResult& r) {
  const auto [cls, word] = status_of(r);
  std::string why;
  for (const Metric* m : r.metrics_worst_first())
    if (!m->pass && m->counted()) why += "<li>" + metric_figures(*m) + "</li>";
  if (!r.message.empty()) why += "<li>" + esc(r.message) + "</li>";
  const std::string applied = settings_text(r.settings);
  return fmt::format(
      "<tr><td class=\"l\"><a href=\"{}#{}\">{}</a></td><td class=\"l\">{}</td><td class=\"st {}\">{}</td><td "
      "class=\"l\"><ul>{}</ul></td>"
      "<td class=\"l\">{}</td></tr>\n",
      scenario_page(r.scenario), esc(r.engine), esc(r.scenario), esc(r.engine), cls, word, why,
      applied.empty() ? "defaults" : "<code>" + esc(applied) + "</code>");
}

/// What is not as expected, each with its failing metrics and their figures.
std::string unexpected_section(const SuiteResults& results) {
  std::string rows;
  const std::string set = settings_text(results.context.set);
  for (const RunResult& r : results.runs)
    if (!r.as_expected()) rows += unexpected_row(r);
  for (const GateRef& g : gates_of(results))
    if (!g.gate->pass) {
      std::string why;
      for (const auto& p : g.gate->problems) why += "<li>" + esc(p) + "</li>";
      rows += fmt::format(
          "<tr><td class=\"l\"><a href=\"#sweep-{}\">sweep {}</a></td><td class=\"l\">{}</td><td class=\"st "
          "fail\">FAIL</td>"
          "<td class=\"l\"><ul>{}</ul></td><td class=\"l\"></td></tr>\n",
          esc(g.sweep), esc(g.sweep), esc(g.engine), why);
    }
  std::string h = "<h2 id=\"unexpected\">Not as expected</h2>\n";
  if (rows.empty()) return h + "<p>Nothing: every run and every sweep gate is as expected.</p>\n";
  return h +
         (set.empty() ? ""
                      : "<p>Settings of this run: <code>" + esc(set) +
                            "</code> (a run with a changed setting is judged on its own, "
                            "without the known failures listed for the defaults).</p>\n") +
         "<table><tr><th class=\"l\">scenario</th><th class=\"l\">configuration</th><th>verdict</th><th "
         "class=\"l\">failing metrics, worst first</th>"
         "<th class=\"l\">settings applied</th></tr>\n" +
         rows + "</table>\n";
}

/// A plot as a figure of the page.
std::string plot_figure(const ReportFile& p) {
  return fmt::format(
      "<figure class=\"wide\"><img class=\"plot\" src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
      esc(p.file), esc(p.alt), esc(p.caption));
}

/// The speed-accuracy map, the one picture worth seeing first.
std::string map_section(const SuiteResults& results) {
  std::string h;
  if (results.report)
    for (const auto& p : results.report->plots)
      if (p.file.rfind("plots/map-", 0) == 0) h += plot_figure(p);
  return h.empty() ? "" : "<h2 id=\"map\">Speed and accuracy</h2>\n" + h;
}

std::string contents_section(const SuiteResults& results) {
  std::string h = "<h2 id=\"contents\">Contents</h2>\n<ul class=\"toc\">";
  if (results.baseline) h += "<li><a href=\"#baseline\">Against the baseline</a></li>";
  h += "<li><a href=\"#known\">Known failures</a></li><li><a href=\"#sweeps\">Sweeps and their gates</a></li>"
       "<li><a href=\"#engines\">Engines and settings</a></li>";
  if (!results.context.tune_table.empty()) h += "<li><a href=\"#tune\">What it takes to pass</a></li>";
  h += "<li><a href=\"#errata\">Errata found in the papers</a></li>";
  for (const auto& sc : results.scenario_order())
    h += fmt::format("<li><a href=\"{}\">{}</a></li>", scenario_page(sc), esc(sc));
  return h + "</ul>\n";
}

/// A listing's ceilings as text: "drive_lag &le; 9.1, slip_rms &le; 0.0024" (a listed error: its start).
std::string ceilings_text(const Expectation& e) {
  if (!e.error.empty()) return "an error starting &ldquo;" + esc(e.error) + "&rdquo;";
  std::string metrics;
  for (const auto& [name, c] : e.ceilings)
    metrics += fmt::format("{}{} &le; {:.2g}", metrics.empty() ? "" : ", ", esc(name), c);
  return metrics;
}

/// The known failures of this run: one row each, the reason folded.
std::string known_section(const SuiteResults& results) {
  std::string rows;
  for (const RunResult& r : results.runs) {
    if (!r.expectation) continue;
    const auto [cls, word] = status_of(r);
    const std::string& reason = r.expectation->reason;
    const bool fold = reason.size() > 90;
    rows += fmt::format(
        "<tr><td class=\"l\"><a href=\"{}#{}\">{}</a></td><td class=\"l\">{}</td><td class=\"st {}\">{}</td><td "
        "class=\"l\">{}</td>"
        "<td class=\"l\"><details><summary>{}</summary>{}<br><i>measured when reviewed:</i> {}</details></td></tr>\n",
        scenario_page(r.scenario), esc(r.engine), esc(r.scenario), esc(r.engine), cls, word,
        ceilings_text(*r.expectation), fold ? esc(reason.substr(0, reason.rfind(' ', 90))) + " &hellip;" : esc(reason),
        fold ? esc(reason) : "", esc(r.expectation->measured));
  }
  if (rows.empty()) return "<h2 id=\"known\">Known failures</h2>\n<p>None in this run.</p>\n";
  const auto n = static_cast<std::size_t>(std::count(rows.begin(), rows.end(), '\n'));
  return "<h2 id=\"known\">Known failures</h2>\n<p class=\"note\">Reviewed in harness/expectations.json: each must "
         "fail, only in its listed "
         "metrics and below their ceilings. Click a reason for the whole of it.</p>\n" +
         fmt::format("<details class=\"fold\"><summary>{} known failures: the table</summary>\n", n) +
         "<table><tr><th "
         "class=\"l\">scenario</th><th class=\"l\">configuration</th>"
         "<th>verdict</th><th class=\"l\">metrics that may fail, error ceilings</th><th "
         "class=\"l\">reason</th></tr>\n" +
         rows + "</table></details>\n";
}

/// One configuration's committed tune answer for one scenario, as a cell.
std::string tune_cell(const TuneEntry& e) {
  std::string change;
  for (const auto& [k, v] : e.change) change += (change.empty() ? "" : ", ") + k + "=" + v;
  if (change.empty()) change = "defaults";
  const std::string tip =
      fmt::format("{} of {} runs; default {}", e.runs, e.budget, e.default_passes ? "passes" : "fails");
  // A search its budget cut short says so in the cell: a cheaper pass, or any pass, may lie there.
  const std::string cut = e.unmade > 0 ? fmt::format(" [{} run{} unmade]", e.unmade, e.unmade == 1 ? "" : "s") : "";
  if (e.passes)
    return fmt::format("<td class=\"l pass\" title=\"{}\">{} ({:.2g}&times; cost){}</td>", esc(tip), esc(change),
                       e.cost_ratio, cut);
  return fmt::format(
      "<td class=\"l xfail\" title=\"{}\">none; closest {}: {:.2g}&times; tol. ({:.2g}&times; cost){}</td>", esc(tip),
      esc(change), e.worst_ratio, e.cost_ratio, cut);
}

/// liftcheck tune's committed answers (context.tune_table): per configuration and headline
/// scenario, the cheapest settings found that pass, or the closest approach, with its cost against
/// the default's.
std::string tune_section(const SuiteResults& results) {
  const auto& table = results.context.tune_table;
  if (table.empty()) return "";
  std::vector<std::string> scenarios;
  for (const auto& [pair, e] : table)
    if (const std::string sc = pair.substr(0, pair.find(' '));
        std::find(scenarios.begin(), scenarios.end(), sc) == scenarios.end())
      scenarios.push_back(sc);
  std::string h =
      "<h2 id=\"tune\">What it takes to pass</h2>\n<p class=\"note\">From <code>liftcheck tune</code> (the "
      "committed table, <code>make tune-table</code>; each configuration at its defaults but for the settings named): "
      "the cheapest settings found that pass each scenario, judged against the default run's tolerances, with the "
      "engine's measured cost against its defaults', or, where nothing tried passed, the closest run (its worst error "
      "over its tolerance). Each search is bounded (the runs it took of its budget in the "
      "tooltip).</p>\n<details class=\"fold\"><summary>each configuration's cheapest passing settings or closest "
      "run, per headline scenario</summary>\n<table class=\"tune\"><tr><th "
      "class=\"l\">configuration</th>";
  for (const auto& sc : scenarios) h += "<th class=\"l\">" + esc(sc) + "</th>";
  h += "</tr>\n";
  for (const auto& eng : engine_order(results)) {
    std::string row;
    bool any = false;
    for (const auto& sc : scenarios) {
      const auto it = table.find(sc + " " + eng);
      any = any || it != table.end();
      row += it == table.end() ? "<td></td>" : tune_cell(it->second);
    }
    if (any) h += "<tr><td class=\"l\">" + esc(eng) + "</td>" + row + "</tr>\n";
  }
  return h + "</table></details>\n";
}

}  // namespace

std::string sweeps_section(const SuiteResults& results);
std::string matrix_section(const SuiteResults& results);
std::string engines_section(const SuiteResults& results);

std::string index_html(const SuiteResults& results) {
  const SuiteContext& ctx = results.context;
  std::string h = head("liftcheck validation report");
  h += "<h1>liftcheck: is each engine right, and where not?</h1>\n";
  h += counts_line(results);
  h += matrix_section(results);
  h += fmt::format(
      "<p class=\"meta\">liftcheck {} (commit <code>{}</code>) &middot; {} &middot; {} &middot; {} CPUs &middot; {} "
      "&middot; "
      "{:.1f} s wall on {} threads (engine time: runs {:.1f} s, sweep and map points {:.1f} s), report {:.1f} s</p>\n",
      esc(ctx.version), esc(ctx.commit), esc(ctx.date), esc(ctx.machine.os), ctx.machine.cpus,
      esc(ctx.machine.compiler), ctx.wall_s, ctx.jobs, ctx.runs_s, ctx.points_s,
      results.report ? results.report->report_s : 0.0);
  h += unexpected_section(results);
  h += map_section(results);
  h += contents_section(results);
  h += baseline_section(results);
  h += known_section(results);
  h += sweeps_section(results);
  h += engines_section(results);
  h += tune_section(results);
  h += "<h2 id=\"errata\">Errata found in the papers</h2>\n<details class=\"fold\"><summary>where the printed "
       "formulas and an independent check differ, and what the code follows</summary>\n";
  h += markdown_html(ctx.errata) + "</details>\n";
  h += "</body>\n</html>\n";
  return h;
}

}  // namespace liftcheck
