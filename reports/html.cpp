// index.html (sections in reading order) and the errata's Markdown; the scenario pages are
// reports/html_scenario.cpp.
#include "reports/html.hpp"

#include <md4c-html.h>

#include "reports/headline.hpp"
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
std::string baseline_section(const json& results) {
  if (!results.contains("baseline") || !results["baseline"].is_object()) return "";
  const json& d = results["baseline"]["diff"];
  std::string h = fmt::format(
      "<h2 id=\"baseline\">Against the baseline <code>{}</code></h2>\n<p>{} regressions, {} metrics worse, {} fixed, "
      "{} better, "
      "{} runs added, {} removed.</p>\n",
      esc(results["baseline"]["file"]), d["regressions"].size(), d["worse"].size(), d["fixed"].size(),
      d["better"].size(), d["added"].size(), d["removed"].size());
  std::string rows;
  for (const auto& r : d["regressions"])
    rows += fmt::format(
        "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">verdict</td><td>{}</td><td class=\"st "
        "fail\">{}</td><td class=\"l\">{}</td></tr>\n",
        esc(r["scenario"]), esc(r["engine"]), esc(r["from"]), esc(r["to"]), esc(r["message"]));
  for (const char* kind : {"worse", "better"})
    for (const auto& r : d[kind])
      rows += fmt::format(
          "<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{} ({:.3g} of tol.)</td>"
          "<td class=\"st {}\">{} ({:.3g} of tol.)</td><td class=\"l\">{}</td></tr>\n",
          esc(r["scenario"]), esc(r["engine"]), esc(r["metric"]), esc(r["base_measured"].dump()),
          r["base_ratio"].get<double>(), std::string(kind) == "worse" ? "fail" : "pass", esc(r["head_measured"].dump()),
          r["head_ratio"].get<double>(), kind);
  if (!rows.empty())
    h += "<table><tr><th class=\"l\">scenario</th><th class=\"l\">configuration</th><th "
         "class=\"l\">what</th><th>before</th><th>after</th>"
         "<th class=\"l\"></th></tr>\n" +
         rows + "</table>\n";
  return h;
}

/// The counts at the top: runs by verdict, sweep gates, the settings of the run.
std::string counts_line(const json& results) {
  const auto& sum = results["summary"];
  const int unexpected = sum.value("unexpected", 0);
  std::string set = settings_text(results["context"].value("set", json::object()));
  return fmt::format(
      "<p id=\"counts\" class=\"counts\">{} <b>{} runs</b>: {} pass, <span class=\"xfail\">&nbsp;{} known "
      "failures&nbsp;</span>, "
      "{} fail, {} unexpected passes, {} error, {} skip &middot; <b>{} sweep gates</b>, {} failed{}</p>\n",
      unexpected == 0
          ? "<span class=\"st pass\">&nbsp;ALL AS EXPECTED&nbsp;</span>"
          : fmt::format("<a class=\"st fail\" href=\"#unexpected\">&nbsp;{} NOT AS EXPECTED&nbsp;</a>", unexpected),
      sum.value("total", 0), sum.value("pass", 0), sum.value("known failure", 0), sum.value("fail", 0),
      sum.value("unexpected pass", 0), sum.value("error", 0), sum.value("skip", 0), sum.value("sweep_gates", 0),
      sum.value("sweep_gates_failed", 0),
      set.empty() ? "" : " &middot; settings of this run: <code>" + esc(set) + "</code>");
}

/// What is not as expected, each with its failing metrics and their figures.
std::string unexpected_section(const json& results) {
  std::string rows;
  const std::string set = settings_text(results["context"].value("set", json::object()));
  for (const auto& r : results["runs"]) {
    if (r.value("as_expected", true)) continue;
    const auto [cls, word] = status_of(r);
    std::string why;
    std::vector<std::pair<double, std::string>> failing;
    for (const auto& [name, m] : r["metrics"].items())
      if (!m.value("pass", true) && !m.value("informational", false)) {
        const auto w = worst_failing(json{{"metrics", {{name, m}}}});
        failing.emplace_back(w ? w->ratio : 0.0, "<li>" + metric_figures(name, m) + "</li>");
      }
    std::sort(failing.begin(), failing.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
    for (const auto& f : failing) why += f.second;
    if (!r.value("message", "").empty()) why += "<li>" + esc(r["message"]) + "</li>";
    const std::string applied = settings_text(r.value("settings", json::object()));
    rows += fmt::format(
        "<tr><td class=\"l\"><a href=\"{}#{}\">{}</a></td><td class=\"l\">{}</td><td class=\"st {}\">{}</td><td "
        "class=\"l\"><ul>{}</ul></td>"
        "<td class=\"l\">{}</td></tr>\n",
        scenario_page(r["scenario"]), esc(r["engine"]), esc(r["scenario"]), esc(r["engine"]), cls, word, why,
        applied.empty() ? "defaults" : "<code>" + esc(applied) + "</code>");
  }
  for (const auto& sw : results.value("sweeps", json::array()))
    for (const auto& e : sw["engines"])
      if (!e["gate"]["pass"].get<bool>()) {
        std::string why;
        for (const auto& p : e["gate"]["problems"]) why += "<li>" + esc(p) + "</li>";
        rows += fmt::format(
            "<tr><td class=\"l\"><a href=\"#sweep-{}\">sweep {}</a></td><td class=\"l\">{}</td><td class=\"st "
            "fail\">FAIL</td>"
            "<td class=\"l\"><ul>{}</ul></td><td class=\"l\"></td></tr>\n",
            esc(sw["name"]), esc(sw["name"]), esc(e["engine"]), why);
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

/// The speed-accuracy map, the one picture worth seeing first.
std::string map_section(const json& results) {
  std::string h;
  for (const auto& p : results.value("report", json::object()).value("plots", json::array()))
    if (p["file"].get<std::string>().rfind("plots/map-", 0) == 0)
      h += fmt::format(
          "<figure class=\"wide\"><img class=\"plot\" src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
          esc(p["file"]), esc(p["caption"]), esc(p["caption"]));
  return h.empty() ? "" : "<h2 id=\"map\">Speed and accuracy</h2>\n" + h;
}

std::string contents_section(const json& results) {
  std::string h = "<h2 id=\"contents\">Contents</h2>\n<ul class=\"toc\">";
  if (results.contains("baseline") && results["baseline"].is_object())
    h += "<li><a href=\"#baseline\">Against the baseline</a></li>";
  h += "<li><a href=\"#known\">Known failures</a></li><li><a href=\"#sweeps\">Sweeps and their gates</a></li>"
       "<li><a href=\"#engines\">Engines and settings</a></li>";
  const json tune = results["context"].value("tune_table", json::object());
  if (tune.is_object() && !tune.empty()) h += "<li><a href=\"#tune\">What it takes to pass</a></li>";
  h += "<li><a href=\"#errata\">Errata found in the papers</a></li>";
  for (const auto& sc : scenario_order(results))
    h += fmt::format("<li><a href=\"{}\">{}</a></li>", scenario_page(sc), esc(sc));
  return h + "</ul>\n";
}

/// The known failures of this run: one row each, the reason folded.
std::string known_section(const json& results) {
  std::string rows;
  for (const auto& r : results["runs"]) {
    if (!has_expectation(r)) continue;
    const auto [cls, word] = status_of(r);
    std::string metrics;
    for (const auto& [name, c] : r["expectation"]["metrics"].items())
      metrics += fmt::format("{}{} &le; {:.2g}", metrics.empty() ? "" : ", ", esc(name), c.get<double>());
    const std::string reason = r["expectation"].value("reason", "");
    const bool fold = reason.size() > 90;
    rows += fmt::format(
        "<tr><td class=\"l\"><a href=\"{}#{}\">{}</a></td><td class=\"l\">{}</td><td class=\"st {}\">{}</td><td "
        "class=\"l\">{}</td>"
        "<td class=\"l\"><details><summary>{}</summary>{}<br><i>measured when reviewed:</i> {}</details></td></tr>\n",
        scenario_page(r["scenario"]), esc(r["engine"]), esc(r["scenario"]), esc(r["engine"]), cls, word, metrics,
        fold ? esc(reason.substr(0, reason.rfind(' ', 90))) + " &hellip;" : esc(reason), fold ? esc(reason) : "",
        esc(r["expectation"].value("measured", "")));
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

/// liftcheck tune's committed answers (context.tune_table): per configuration and headline
/// scenario, the cheapest settings found that pass, or the closest approach, with its cost against
/// the default's.
std::string tune_section(const json& results) {
  const json table = results["context"].value("tune_table", json::object());
  if (!table.is_object() || table.empty()) return "";
  std::vector<std::string> scenarios;
  for (const auto& [pair, e] : table.items())
    if (const std::string sc = pair.substr(0, pair.find(' '));
        std::find(scenarios.begin(), scenarios.end(), sc) == scenarios.end())
      scenarios.push_back(sc);
  const auto number = [](const json& e, const char* key) {
    const json v = e.value(key, json());
    return v.is_number() ? v.get<double>() : NAN;
  };
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
      const std::string key = sc + " " + eng;
      if (!table.contains(key) || !table[key].is_object()) {
        row += "<td></td>";
        continue;
      }
      any = true;
      const json& e = table[key];
      std::string change;
      const json changes = e.value("change", json::object());
      for (const auto& [k, v] : changes.items())
        change += (change.empty() ? "" : ", ") + k + "=" + (v.is_string() ? v.get<std::string>() : v.dump());
      if (change.empty()) change = "defaults";
      const std::string tip = fmt::format("{} of {} runs; default {}", e.value("runs", 0), e.value("budget", 0),
                                          e.value("default_passes", false) ? "passes" : "fails");
      // A search its budget cut short says so in the cell: a cheaper pass, or any pass, may lie there.
      const int unmade = e.value("unmade", 0);
      const std::string cut = unmade > 0 ? fmt::format(" [{} run{} unmade]", unmade, unmade == 1 ? "" : "s") : "";
      row += e.value("passes", false)
                 ? fmt::format("<td class=\"l pass\" title=\"{}\">{} ({:.2g}&times; cost){}</td>", esc(tip),
                               esc(change), number(e, "cost_ratio"), cut)
                 : fmt::format(
                       "<td class=\"l xfail\" title=\"{}\">none; closest {}: {:.2g}&times; tol. ({:.2g}&times; "
                       "cost){}</td>",
                       esc(tip), esc(change), number(e, "worst_ratio"), number(e, "cost_ratio"), cut);
    }
    if (any) h += "<tr><td class=\"l\">" + esc(eng) + "</td>" + row + "</tr>\n";
  }
  return h + "</table></details>\n";
}

}  // namespace

std::string sweeps_section(const json& results);
std::string matrix_section(const json& results);
std::string engines_section(const json& results);

std::string index_html(const json& results) {
  const auto& ctx = results["context"];
  std::string h = head("liftcheck validation report");
  h += "<h1>liftcheck: is each engine right, and where not?</h1>\n";
  h += counts_line(results);
  h += matrix_section(results);
  h += fmt::format(
      "<p class=\"meta\">liftcheck {} (commit <code>{}</code>) &middot; {} &middot; {} &middot; {} CPUs &middot; {} "
      "&middot; "
      "{:.1f} s wall on {} threads (engine time: runs {:.1f} s, sweep and map points {:.1f} s), report {:.1f} s</p>\n",
      esc(ctx["liftcheck"]["version"]), esc(ctx["liftcheck"]["commit"]), esc(ctx["date"]), esc(ctx["machine"]["os"]),
      ctx["machine"]["cpus"].get<int>(), esc(ctx["machine"]["compiler"]), ctx.value("wall_s", 0.0),
      ctx.value("jobs", 1), ctx.value("runs_s", 0.0), ctx.value("points_s", 0.0),
      results.value("report", json::object()).value("report_s", 0.0));
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
  h += markdown_html(ctx.value("errata", std::string())) + "</details>\n";
  h += "</body>\n</html>\n";
  return h;
}

}  // namespace liftcheck
