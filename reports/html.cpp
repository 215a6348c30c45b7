#include "reports/html.hpp"

#include "reports/escape.hpp"

#include <fmt/format.h>
#include <sstream>

namespace liftcheck {

namespace {

using json = nlohmann::json;

std::string esc(const std::string& s) { return escape_markup(s); }

std::string num(const json& v) { return v.is_number() ? fmt::format("{:.6g}", v.get<double>()) : "&ndash;"; }

constexpr const char* kCss =
    "body{font-family:'DejaVu Sans',Arial,sans-serif;margin:0 auto;padding:1em 1.5em;max-width:78em;color:#222;line-height:1.4}"
    "h1{font-size:1.6em;margin:.3em 0}h2{margin-top:1.6em;border-bottom:1px solid #ccc}"
    "table{border-collapse:collapse;margin:.6em 0}td,th{border:1px solid #bbb;padding:.25em .6em;text-align:right;vertical-align:top}"
    "th{background:#eee}td.l,th.l{text-align:left}"
    ".pass{background:#c6efce;color:#0b5a17}.fail{background:#ffc7ce;color:#8a0010}.error{background:#ffe09a;color:#6b4300}"
    ".skip{background:#e4e4e4;color:#555}.xfail{background:#d6e8f7;color:#104a7a}"
    "td.st{font-weight:bold;text-align:center;white-space:nowrap}"
    ".shots{display:flex;flex-wrap:wrap;gap:10px}.shots figure{margin:0;width:380px}.shots img{width:380px;border:1px solid #ccc}"
    "figure.wide img{max-width:100%;border:1px solid #ccc}figcaption{font-size:.85em;color:#555}"
    "img.plot{max-width:100%;border:1px solid #ddd}code{background:#f3f3f3;padding:0 .2em}"
    ".meta{color:#555;font-size:.92em}.note{font-size:.9em;color:#444}";

std::string head(const std::string& title) {
  return fmt::format("<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
                     "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n"
                     "<style>{}</style>\n</head>\n<body>\n",
                     esc(title), kCss);
}

/// CSS class and word for a run's verdict (a reviewed known failure has its own colour; a listed
/// failure that passes is as unexpected as a failure).
std::pair<std::string, std::string> status_of(const json& r) {
  const std::string st = r.value("verdict", r["status"].get<std::string>());
  if (st == "known failure") return {"xfail", "KNOWN FAILURE"};
  if (st == "unexpected pass") return {"fail", "UNEXPECTED PASS"};
  std::string word = st;
  for (auto& c : word) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return {st, word};
}

/// "front_radius ≤ 0.006, slip_rms ≤ 0.002": a known failure's metrics with their ceilings.
std::string ceilings_text(const json& metrics) {
  std::string out;
  for (const auto& [name, c] : metrics.items()) out += fmt::format("{}{} ≤ {:.2g}", out.empty() ? "" : ", ", name, c.get<double>());
  return out;
}

std::vector<std::string> scenario_order(const json& results) {
  std::vector<std::string> v;
  for (const auto& r : results["runs"])
    if (std::find(v.begin(), v.end(), r["scenario"].get<std::string>()) == v.end()) v.push_back(r["scenario"]);
  return v;
}

std::vector<std::string> engine_order(const json& results) {
  std::vector<std::string> v;
  for (const auto& e : results["context"]["engines"]) v.push_back(e["name"]);
  return v;
}

const json* find_run(const json& results, const std::string& sc, const std::string& eng) {
  for (const auto& r : results["runs"])
    if (r["scenario"] == sc && r["engine"] == eng) return &r;
  return nullptr;
}

const json* scenario_info(const json& results, const std::string& sc) {
  if (!results.contains("scenarios")) return nullptr;
  for (const auto& s : results["scenarios"])
    if (s["name"] == sc) return &s;
  return nullptr;
}

std::string inline_md(const std::string& s) {
  std::string o, t = esc(s);
  bool code = false;
  for (char c : t) {
    if (c == '`') {
      o += code ? "</code>" : "<code>";
      code = !code;
    } else {
      o += c;
    }
  }
  if (code) o += "</code>";
  // **bold**
  std::string b;
  bool bold = false;
  for (std::size_t i = 0; i < o.size(); ++i) {
    if (o.compare(i, 2, "**") == 0) {
      b += bold ? "</b>" : "<b>";
      bold = !bold;
      ++i;
    } else {
      b += o[i];
    }
  }
  if (bold) b += "</b>";
  return b;
}

std::vector<std::string> split_row(const std::string& line) {
  std::vector<std::string> cells;
  std::string cur;
  for (std::size_t i = 1; i < line.size(); ++i) {
    if (line[i] == '\\' && i + 1 < line.size() && line[i + 1] == '|') {
      cur += '|';
      ++i;
    } else if (line[i] == '|') {
      cells.push_back(cur);
      cur.clear();
    } else {
      cur += line[i];
    }
  }
  for (auto& c : cells) {
    const auto b = c.find_first_not_of(' '), e = c.find_last_not_of(' ');
    c = b == std::string::npos ? "" : c.substr(b, e - b + 1);
  }
  return cells;
}

std::string metric_table(const json& r) {
  std::string h = "<table><tr><th class=\"l\">metric</th><th>expected</th><th>measured</th><th>abs error</th>"
                  "<th>rel error</th><th>tolerance</th><th>unit</th><th>result</th></tr>\n";
  for (const auto& [name, m] : r["metrics"].items()) {
    const bool ok = m["pass"].get<bool>(), info = m.value("informational", false);
    h += fmt::format("<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{} ({})</td><td>{}</td>"
                     "<td class=\"st {}\">{}</td></tr>\n",
                     esc(name), num(m["expected"]), num(m["measured"]), num(m["abs_error"]), num(m["rel_error"]),
                     num(m["tolerance"]), esc(m["tolerance_kind"]), esc(m["unit"]), info ? "skip" : ok ? "pass" : "fail", info ? "info (not counted)" : ok ? "ok" : "FAIL");
  }
  return h + "</table>\n";
}

}  // namespace

std::string scenario_page(const std::string& scenario) {
  std::string s;
  for (char c : scenario) s += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return "scenario-" + s + ".html";
}

std::string markdown_html(const std::string& md) {
  std::istringstream in(md);
  std::string line, h;
  bool in_table = false, header_done = false;
  std::string para;
  const auto flush = [&] {
    if (!para.empty()) h += "<p class=\"note\">" + inline_md(para) + "</p>\n";
    para.clear();
  };
  while (std::getline(in, line)) {
    if (!line.empty() && line[0] == '|') {
      flush();
      const auto cells = split_row(line);
      if (!cells.empty() && cells[0].find("---") == 0) continue;
      if (!in_table) h += "<table>\n", in_table = true, header_done = false;
      const char* tag = header_done ? "td" : "th";
      h += "<tr>";
      for (const auto& c : cells) h += fmt::format("<{0} class=\"l\">{1}</{0}>", tag, inline_md(c));
      h += "</tr>\n";
      header_done = true;
      continue;
    }
    if (in_table) h += "</table>\n", in_table = false;
    if (line.rfind("## ", 0) == 0) flush(), h += "<h3>" + inline_md(line.substr(3)) + "</h3>\n";
    else if (line.rfind("# ", 0) == 0) flush(), h += "<h3>" + inline_md(line.substr(2)) + "</h3>\n";
    else if (line.empty()) flush();
    else para += (para.empty() ? "" : " ") + line;
  }
  if (in_table) h += "</table>\n";
  flush();
  return h;
}

namespace {

/// The comparison with the baseline, when there is one.
std::string baseline_section(const json& results) {
  std::string h;
  // Against the baseline: regressions and worsened metrics lead, before and after side by side.
  if (results.contains("baseline") && results["baseline"].is_object()) {
    const json& d = results["baseline"]["diff"];
    h += fmt::format("<h2 id=\"baseline\">Against the baseline <code>{}</code></h2>\n<p>{} regressions, {} metrics worse, {} fixed, {} better, "
                     "{} runs added, {} removed.</p>\n",
                     esc(results["baseline"]["file"]), d["regressions"].size(), d["worse"].size(), d["fixed"].size(), d["better"].size(),
                     d["added"].size(), d["removed"].size());
    std::string rows;
    for (const auto& r : d["regressions"])
      rows += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">verdict</td><td>{}</td><td class=\"st fail\">{}</td><td class=\"l\">{}</td></tr>\n",
                          esc(r["scenario"]), esc(r["engine"]), esc(r["from"]), esc(r["to"]), esc(r["message"]));
    for (const char* kind : {"worse", "better"})
      for (const auto& r : d[kind])
        rows += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td><td>{} ({:.3g} of tol.)</td>"
                            "<td class=\"st {}\">{} ({:.3g} of tol.)</td><td class=\"l\">{}</td></tr>\n",
                            esc(r["scenario"]), esc(r["engine"]), esc(r["metric"]), esc(r["base_measured"].dump()), r["base_ratio"].get<double>(),
                            std::string(kind) == "worse" ? "fail" : "pass", esc(r["head_measured"].dump()), r["head_ratio"].get<double>(), kind);
    if (!rows.empty())
      h += "<table><tr><th class=\"l\">scenario</th><th class=\"l\">configuration</th><th class=\"l\">what</th><th>before</th><th>after</th>"
           "<th class=\"l\"></th></tr>\n" + rows + "</table>\n";
  }
  return h;
}

/// The summary matrix (scenario x configuration) and the known failures of this run.
std::string matrix_section(const json& results) {
  std::string h;
  // Summary matrix.
  const auto engines = engine_order(results);
  h += "<h2 id=\"summary\">Summary</h2>\n<table id=\"matrix\"><tr><th class=\"l\">scenario</th><th class=\"l\">checks</th>";
  for (const auto& e : engines) h += "<th>" + esc(e) + "</th>";
  h += "</tr>\n";
  for (const auto& sc : scenario_order(results)) {
    const json* info = scenario_info(results, sc);
    h += fmt::format("<tr><td class=\"l\"><a href=\"{}\">{}</a></td><td class=\"l\">{}</td>", scenario_page(sc), esc(sc),
                     info ? esc((*info)["equations"]) : "");
    for (const auto& e : engines) {
      const json* r = find_run(results, sc, e);
      if (!r) {
        h += "<td>&ndash;</td>";
        continue;
      }
      const auto [cls, word] = status_of(*r);
      std::string ratio;
      if (cls != "skip") {
        if (r->contains("worst_rel_error") && (*r)["worst_rel_error"].is_number())
          ratio += fmt::format("<br><small>worst rel. error {:.2g}</small>", (*r)["worst_rel_error"].get<double>());
        if ((*r)["worst_ratio"].is_number()) ratio += fmt::format("<br><small>{:.2g} of tolerance</small>", (*r)["worst_ratio"].get<double>());
      }
      if (r->contains("expectation") && (*r)["expectation"].is_object())
        ratio += fmt::format("<br><small>{}</small>", esc((*r)["expectation"]["reason"]));
      h += fmt::format("<td class=\"st {}\" title=\"{}\">{}{}</td>", cls, esc((*r)["message"]), word, ratio);
    }
    h += "</tr>\n";
  }
  h += "</table>\n<p class=\"note\">Each cell: the run's verdict; its worst relative error over the metrics compared "
       "relatively; and its worst error as a fraction of its tolerance (below 1 passes). A known failure is listed, "
       "with its reason and measured figure, in the reviewed expectations (harness/expectations.json): it must fail, and "
       "only in its listed metrics; negative controls are listed there too. "
       "Click a scenario for its metrics, snapshots and plots.</p>\n";
  // The known failures of this run, with their reasons and figures.
  std::string known;
  for (const auto& r : results["runs"])
    if (r.contains("expectation") && r["expectation"].is_object()) {
      const auto [cls, word] = status_of(r);
      known += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"st {}\">{}</td><td class=\"l\">{}</td>"
                           "<td class=\"l\">{}</td><td class=\"l\">{}</td></tr>\n",
                           esc(r["scenario"]), esc(r["engine"]), cls, word,
                           esc(ceilings_text(r["expectation"]["metrics"])),
                           esc(r["expectation"]["reason"]), esc(r["expectation"]["measured"]));
    }
  if (!known.empty())
    h += "<h3 id=\"known\">Known failures</h3>\n<table><tr><th class=\"l\">scenario</th><th class=\"l\">configuration</th><th>verdict</th>"
         "<th class=\"l\">metrics that may fail, error ceilings</th><th class=\"l\">reason</th><th class=\"l\">measured when reviewed</th></tr>\n" +
         known + "</table>\n";
  return h;
}

/// The sweeps' plots, their gates, the collision outcomes and the fitted slopes.
std::string sweeps_section(const json& results) {
  std::string h;
  const json& rep = results.value("report", json::object());
  // Sweeps.
  h += "<h2 id=\"sweeps\">Sweeps</h2>\n";
  for (const auto& p : rep.value("plots", json::array()))
    if (p["group"] == "sweeps")
      h += fmt::format("<figure class=\"wide\"><img class=\"plot\" src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
                       esc(p["file"]), esc(p["caption"]), esc(p["caption"]));
  // The sweeps' gates: each engine's points pass, fail as listed known failures (with the reason
  // from the reviewed expectations), or are unexpected; fitted slopes lie in their bands.
  h += "<h3>Sweep gates</h3>\n<table><tr><th class=\"l\">sweep</th><th class=\"l\">engine</th><th>gate</th><th>points passing</th>"
       "<th>known failures</th><th>unexpected</th><th>errors</th><th class=\"l\">problems and known failures</th></tr>\n";
  for (const auto& sw : results.value("sweeps", json::array()))
    for (const auto& e : sw["engines"]) {
      const json& g = e["gate"];
      std::string notes;
      for (const auto& p : g["problems"]) notes += "<li>" + esc(p) + "</li>";
      for (const auto& pt : e.value("points", json::array()))
        if (pt.contains("known_failure"))
          notes += fmt::format("<li class=\"xfail\">{} = {}: known failure: {}</li>", esc(sw["param"]), pt["x"].dump(), esc(pt["known_failure"]));
      const bool pass = g["pass"].get<bool>();
      h += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"st {}\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td>"
                       "<td class=\"l\"><ul>{}</ul></td></tr>\n",
                       esc(sw["name"]), esc(e["engine"]), pass ? "pass" : "fail", pass ? "pass" : "FAIL", g.value("points_pass", 0),
                       g.value("points_known_failure", 0), g.value("points_unexpected", 0), g.value("points_error", e.value("errors", 0)), notes);
    }
  h += "</table>\n";
  for (const auto& sw : results.value("sweeps", json::array())) {
    if (sw.value("kind", "") == "outcomes") {
      h += "<h3>Collision outcomes against the reference</h3>\n<table><tr><th class=\"l\">configuration</th><th>both collide</th>"
           "<th>neither</th><th>engine only</th><th>reference only</th><th>near boundary</th><th>unexplained</th><th>worst |t| error [steps]</th></tr>\n";
      for (const auto& e : sw["engines"]) {
        const auto& c = e["confusion"];
        h += fmt::format("<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"st {}\">{}</td><td>{:.3f}</td></tr>\n",
                         esc(e["engine"]), c["both_collide"].get<int>(), c["neither"].get<int>(), c["engine_only"].get<int>(),
                         c["reference_only"].get<int>(), e["near_boundary_cases"].get<int>(),
                         e["unexplained_disagreements"].get<int>() == 0 ? "pass" : "fail", e["unexplained_disagreements"].get<int>(),
                         e["worst_t_error_steps"].get<double>());
      }
      h += fmt::format("</table>\n<p class=\"note\">{} over the grid a &isin; {}, b &isin; {} and N's paths {}; near boundary: "
                       "the reference closest approach is within {} m of contact.</p>\n",
                       esc(sw["scenario"]), esc(sw["grid"]["a"].dump()), esc(sw["grid"]["b"].dump()), esc(sw["grid"]["path"].dump()),
                       sw["near_boundary_m"].get<double>());
    } else if (sw.contains("engines")) {
      for (const auto& e : sw["engines"])
        if (e.contains("fit") && e["fit"]["slope"].is_number())
          h += fmt::format("<p class=\"note\">{}: {} fitted log-log slope {:.3f} over {} points above its noise floor.</p>\n",
                           esc(sw["name"]), esc(e["engine"]), e["fit"]["slope"].get<double>(), e["fit"]["points"].get<int>());
    }
  }
  return h;
}

/// The configurations with their settings, the machine and the report's own problems.
std::string engines_section(const json& results) {
  std::string h;
  const auto& ctx = results["context"];
  const json& rep = results.value("report", json::object());
  // Engines and machine.
  h += "<h2 id=\"engines\">Engines and settings</h2>\n<table><tr><th class=\"l\">engine</th><th class=\"l\">version</th><th class=\"l\">settings</th></tr>\n";
  for (const auto& e : ctx["engines"]) {
    std::string settings = esc(e["description"]) + "<ul>";
    const json engine_settings = e.value("settings", json::object());
    for (const auto& [k, v] : engine_settings.items()) settings += fmt::format("<li><b>{}</b>: {}</li>", esc(k), esc(v));
    settings += "</ul>";
    h += fmt::format("<tr><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td></tr>\n", esc(e["name"]),
                     esc(e["version"]), settings);
  }
  h += "</table>\n";
  h += fmt::format("<p class=\"meta\">Machine: {} ({}), {} CPUs; renderer: {}.</p>\n", esc(ctx["machine"]["host"]),
                   esc(ctx["machine"]["os"]), ctx["machine"]["cpus"].get<int>(), esc(rep.value("gl_version", "none")));
  for (const auto& err : rep.value("errors", json::array())) h += "<p class=\"st error\">report: " + esc(err) + "</p>\n";
  return h;
}

}  // namespace

std::string index_html(const json& results) {
  const auto& ctx = results["context"];
  const auto& sum = results["summary"];
  std::string h = head("liftcheck validation report");
  h += "<h1>liftcheck validation report</h1>\n";
  h += fmt::format("<p class=\"meta\">liftcheck {} (commit <code>{}</code>) &middot; {} &middot; {} &middot; {} CPUs &middot; {}<br>"
                   "{:.1f} s wall on {} threads (engine time: runs {:.1f} s, sweep and map points {:.1f} s), report {:.1f} s</p>\n",
                   esc(ctx["liftcheck"]["version"]), esc(ctx["liftcheck"]["commit"]), esc(ctx["date"]), esc(ctx["machine"]["os"]),
                   ctx["machine"]["cpus"].get<int>(), esc(ctx["machine"]["compiler"]), ctx.value("wall_s", 0.0), ctx.value("jobs", 1), ctx.value("runs_s", 0.0),
                   ctx.value("points_s", 0.0), results.value("report", json::object()).value("report_s", 0.0));
  h += fmt::format("<p><b>{} runs</b>: {} pass, <span class=\"st xfail\">&nbsp;{} known failures&nbsp;</span> (reviewed, "
                   "<a href=\"#known\">listed below</a> with their reasons), {} unexpected passes, {} fail, {} error, {} skip; "
                   "<b>{} <a href=\"#sweeps\">sweep gates</a></b>, {} failed. {}</p>\n",
                   sum["total"].get<int>(), sum.value("pass", 0), sum.value("known failure", 0), sum.value("unexpected pass", 0),
                   sum.value("fail", 0), sum.value("error", 0), sum.value("skip", 0), sum.value("sweep_gates", 0), sum.value("sweep_gates_failed", 0),
                   sum["unexpected"].get<int>() == 0 ? "<span class=\"st pass\">&nbsp;ALL AS EXPECTED&nbsp;</span>"
                                                     : fmt::format("<span class=\"st fail\">&nbsp;{} UNEXPECTED&nbsp;</span>", sum["unexpected"].get<int>()));

  h += baseline_section(results);
  h += matrix_section(results);
  h += sweeps_section(results);
  h += engines_section(results);

  // Errata.
  h += "<h2 id=\"errata\">Errata found in the papers</h2>\n";
  h += markdown_html(ctx.value("errata", std::string()));
  h += "</body>\n</html>\n";
  return h;
}

std::string scenario_html(const json& results, const std::string& sc) {
  const json* info = scenario_info(results, sc);
  std::string h = head("liftcheck: " + sc);
  h += "<p><a href=\"index.html\">&larr; summary</a></p>\n";
  h += fmt::format("<h1>{}</h1>\n", esc(sc));
  if (info) {
    h += fmt::format("<p>{}</p>\n<p class=\"meta\">Equations: {}</p>\n", esc((*info)["summary"]), esc((*info)["equations"]));
    if ((*info).value("negative_control", false))
      h += "<p class=\"note\"><b>Negative control</b>: meant to fail on every configuration with contact dynamics "
           "(listed as such in the expectations).</p>\n";
  }
  const json& rep = results.value("report", json::object());
  for (const auto& p : rep.value("plots", json::array()))
    if (p["group"] == sc)
      h += fmt::format("<figure class=\"wide\"><img class=\"plot\" src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
                       esc(p["file"]), esc(p["caption"]), esc(p["caption"]));
  bool params_done = false;
  for (const auto& e : engine_order(results)) {
    const json* r = find_run(results, sc, e);
    if (!r) continue;
    if (!params_done && (*r)["params"].is_object()) {
      h += "<h2>Parameters</h2>\n<table><tr><th class=\"l\">parameter</th><th>value</th><th class=\"l\">unit</th><th class=\"l\">meaning</th></tr>\n";
      for (const auto& [k, v] : (*r)["params"].items()) {
        std::string unit, help;
        if (info)
          for (const auto& p : (*info)["params"])
            if (p["key"] == k) unit = p["unit"], help = p["help"];
        h += fmt::format("<tr><td class=\"l\">{}</td><td>{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td></tr>\n", esc(k),
                         esc(v.is_string() ? v.get<std::string>() : v.dump()), esc(unit), esc(help));
      }
      h += "</table>\n";
      params_done = true;
    }
    const auto [cls, word] = status_of(*r);
    h += fmt::format("<h2 id=\"{0}\">{0}: <span class=\"st {1}\">&nbsp;{2}&nbsp;</span></h2>\n", esc(e), cls, word);
    if (!(*r)["message"].get<std::string>().empty()) h += "<p>" + esc((*r)["message"]) + "</p>\n";
    if (!(*r)["metrics"].empty()) h += metric_table(*r);
    const auto& d = (*r)["details"];
    if (d.is_object() && d.contains("errors")) {
      const auto& er = d["errors"];
      h += fmt::format("<p class=\"note\">Actuation error (lift of the realized (alpha, beta) against the commanded lift): {:.3g} m; "
                       "contact error (engine pose against the lift of its realized path): {:.3g} m.</p>\n",
                       er["actuation_error_m"].get<double>(), er["contact_error_m"].get<double>());
    }
    h += "<div class=\"shots\">\n";
    for (const auto& s : rep.value("snapshots", json::array()))
      if (s["scenario"] == sc && s["engine"] == e)
        h += fmt::format("<figure><a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a><figcaption>{1}</figcaption></figure>\n",
                         esc(s["file"]), esc(s["caption"]));
    h += "</div>\n";
    for (const auto& s : rep.value("strips", json::array()))
      if (s["scenario"] == sc && s["engine"] == e)
        h += fmt::format("<figure class=\"wide\"><img src=\"{0}\" alt=\"frame strip\"><figcaption>{1}</figcaption></figure>\n",
                         esc(s["file"]), esc(s["caption"]));
  }
  h += "</body>\n</html>\n";
  return h;
}

}  // namespace liftcheck
