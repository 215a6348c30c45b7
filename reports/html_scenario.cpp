// The scenario pages, and the index's sweeps and engines sections.
#include <set>

#include "reports/headline.hpp"
#include "reports/html.hpp"
#include "reports/html_common.hpp"
#include "scenarios/details.hpp"

namespace liftcheck {

using namespace html;

namespace {

/// A run's metrics, the headline's first, then the rest from the worst ratio down; the ratio to
/// the tolerance in a column of its own.
std::string metric_table(const json& r, const json& def) {
  std::vector<std::string> first;
  for (const auto& n : def.is_object() ? def.value("metrics", json::array()) : json::array()) first.push_back(n);
  std::vector<std::pair<double, std::string>> order;
  for (const auto& [name, m] : r["metrics"].items()) {
    const auto it = std::find(first.begin(), first.end(), name);
    const auto f = headline_figure(json{{"metrics", {{name, m}}}, {"params", r["params"]}}, json{{"metrics", {name}}});
    const double key = it != first.end() ? 1e300 - static_cast<double>(it - first.begin()) : f ? f->ratio : 0.0;
    order.emplace_back(std::isfinite(key) ? key : 1e299, name);
  }
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string h =
      "<table><tr><th class=\"l\">metric</th><th>expected</th><th>measured</th><th>abs error</th>"
      "<th>rel error</th><th>tolerance</th><th>error / tolerance</th><th class=\"l\">unit</th><th>result</th></tr>\n";
  for (const auto& [key, name] : order) {
    const MetricView m = RecordView(r).metric(name);
    const bool ok = m.pass(), info = !m.counted(), rel = m.relative();
    const bool head = std::find(first.begin(), first.end(), name) != first.end();
    const double err = m.compared_error(), tol = m.tolerance();
    h += fmt::format(
        "<tr><td class=\"l\">{}{}{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{} ({})</td><td>{}</td><td "
        "class=\"l\">{}</td>"
        "<td class=\"st {}\">{}</td></tr>\n",
        head ? "<b>" : "", esc(name), head ? "</b> (headline)" : "", num(m.expected()), num(m.measured()),
        num(m.abs_error()), rel ? num(m.rel_error()) : "&ndash;", num(m.tolerance()), esc(m.tolerance_kind()),
        tol > 0 ? short_number(err / tol) : "&ndash;", esc(m.unit()),
        info ? "skip"
        : ok ? "pass"
             : "fail",
        info ? "info (not counted)"
        : ok ? "ok"
             : "FAIL");
  }
  return h + "</table>\n";
}

/// The run's parameters with their units and meanings.
std::string params_table(const json& r, const json* info) {
  std::string h =
      "<h2 id=\"parameters\">Parameters of this run</h2>\n<table><tr><th class=\"l\">parameter</th><th>value</th><th "
      "class=\"l\">unit</th>"
      "<th class=\"l\">meaning</th></tr>\n";
  for (const auto& [k, v] : r["params"].items()) {
    std::string unit, help;
    if (info)
      for (const auto& p : (*info)["params"])
        if (p["key"] == k) unit = p.value("unit", ""), help = p.value("help", "");
    const std::string val = v.is_string() ? v.get<std::string>() : v.dump();
    h += fmt::format("<tr><td class=\"l\">{}</td><td>{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td></tr>\n",
                     esc(k), esc(val), esc(unit), esc(help));
  }
  return h + "</table>\n";
}

/// Every configuration on this scenario: verdict, headline, failing metrics, settings, reason.
std::string cross_engine_table(const json& results, const std::string& sc, const json& def) {
  std::string h = fmt::format(
      "<h2 id=\"engines\">Every configuration</h2>\n<table><tr><th class=\"l\">configuration</th><th>verdict</th>"
      "<th>{}{}</th><th>error / tolerance</th><th class=\"l\">failing metrics (error / tolerance)</th><th "
      "class=\"l\">settings applied</th>"
      "<th class=\"l\">known failure: reason</th></tr>\n",
      esc(def.is_object() ? def.value("label", "headline") : "headline"),
      def.is_object() && !def.value("unit", "").empty() ? ", " + esc(def["unit"]) : "");
  for (const auto& e : engine_order(results)) {
    const json* r = find_run(results, sc, e);
    if (!r) continue;
    const auto [cls, word] = status_of(*r);
    const auto fig = headline_figure(*r, def);
    std::string failing;
    for (const auto& [name, m] : (*r)["metrics"].items())
      if (!m.value("pass", true) && !m.value("informational", false))
        if (const auto w = worst_failing(json{{"metrics", {{name, m}}}}))
          failing +=
              fmt::format("{}{} {} ({:.2g}&times;)", failing.empty() ? "" : "; ", esc(name), esc(w->text()), w->ratio);
    const std::string applied = settings_text(r->value("settings", json::object()));
    h += fmt::format(
        "<tr><td class=\"l\"><a href=\"#{0}\">{0}</a></td><td class=\"st {1}\">{2}</td><td>{3}</td><td>{4}</td><td "
        "class=\"l\">{5}</td>"
        "<td class=\"l\">{6}</td><td class=\"l\">{7}</td></tr>\n",
        esc(e), cls, word, fig ? short_number(fig->value) : "&ndash;", fig ? short_number(fig->ratio) : "&ndash;",
        failing, applied.empty() ? "" : "<code>" + esc(applied) + "</code>",
        has_expectation(*r)        ? esc((*r)["expectation"].value("reason", ""))
        : (*r)["status"] == "skip" ? esc((*r)["message"])
                                   : "");
  }
  return h + "</table>\n";
}

/// One configuration's section: verdict, reason, metrics, errors split, snapshots.
std::string engine_section(const json& results, const json& r, const json& def) {
  const json& rep = results.value("report", json::object());
  const std::string e = r["engine"], sc = r["scenario"];
  const auto [cls, word] = status_of(r);
  std::string h =
      fmt::format("<h2 id=\"{0}\">{0}: <span class=\"st {1}\">&nbsp;{2}&nbsp;</span></h2>\n", esc(e), cls, word);
  if (!r["message"].get<std::string>().empty()) h += "<p>" + esc(r["message"]) + "</p>\n";
  if (has_expectation(r))
    h += fmt::format("<p class=\"note\"><b>Known failure</b>: {}<br><i>Measured when reviewed:</i> {}</p>\n",
                     esc(r["expectation"].value("reason", "")), esc(r["expectation"].value("measured", "")));
  if (const std::string s = settings_text(r.value("settings", json::object())); !s.empty())
    h += "<p class=\"meta\">Settings applied: <code>" + esc(s) + "</code></p>\n";
  if (!r["metrics"].empty()) h += metric_table(r, def);
  const auto& d = r["details"];
  if (d.is_object() && d.contains("ground_load") && d["ground_load"].contains("not_measured"))
    h += "<p class=\"note\">Not measured here: the ground's load (<code>load_at_rest</code>, "
         "<code>load_over_drive</code>): " +
         esc(d["ground_load"]["not_measured"].get<std::string>()) + ".</p>\n";
  if (d.is_object() && d.contains(detail_key::kErrors)) {
    const auto& er = d[detail_key::kErrors];
    h += fmt::format(
        "<p class=\"note\">Actuation error (lift of the realized (alpha, beta) against the commanded lift): {:.3g} m; "
        "contact error (engine pose against the lift of its realized path): {:.3g} m.</p>\n",
        er[detail_key::kActuationError].get<double>(), er[detail_key::kContactError].get<double>());
  }
  h += "<div class=\"shots\">\n";
  for (const auto& s : rep.value("snapshots", json::array()))
    if (s["scenario"] == sc && s["engine"] == e && s.value("tag", "") != "start")
      h += fmt::format(
          "<figure><a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a><figcaption>{1}</figcaption></figure>\n",
          esc(s["file"]), esc(s["caption"]));
  h += "</div>\n";
  for (const auto& s : rep.value("strips", json::array()))
    if (s["scenario"] == sc && s["engine"] == e)
      h += fmt::format(
          "<figure class=\"wide\"><img src=\"{0}\" alt=\"frame strip\"><figcaption>{1}</figcaption></figure>\n",
          esc(s["file"]), esc(s["caption"]));
  return h;
}

/// A sweep entry's gate: pass, known failure (it passes only through listed failures) or fail.
std::pair<std::string, std::string> gate_status(const json& g) {
  if (!g["pass"].get<bool>()) return {"fail", "FAIL"};
  if (g.value("points_known_failure", 0) > 0)
    return {"xfail", g.value("points_pass", 0) == 0
                         ? "KNOWN FAILURE"
                         : fmt::format("pass, {} known", g.value("points_known_failure", 0))};
  return {"pass", "pass"};
}

/// A sweep entry's points in one line: x and a mark each; its reasons once each.
std::string sweep_points(const json& sw, const json& e) {
  std::string pts;
  std::vector<std::string> reasons;
  for (const auto& pt : e.value("points", json::array())) {
    const std::string st = pt.value("status", "");
    const bool known = pt.contains("known_failure");
    const char* cls = known ? "xfail" : st == "pass" ? "pass" : st == "error" ? "error" : "fail";
    const char* mark = known ? "&#10007;" : st == "pass" ? "&#10003;" : st == "error" ? "!" : "FAIL";
    pts += fmt::format("<span class=\"{}\" title=\"{} = {}: {}\">&nbsp;{}&nbsp;{}&nbsp;</span> ", cls, esc(sw["param"]),
                       esc(pt["x"].dump()), esc(pt.value("message", st)), esc(pt["x"].dump()), mark);
    if (known && std::find(reasons.begin(), reasons.end(), pt["known_failure"].get<std::string>()) == reasons.end())
      reasons.push_back(pt["known_failure"]);
  }
  std::string why;
  for (const auto& p : e["gate"]["problems"]) why += "<li>" + esc(p) + "</li>";
  for (const auto& r : reasons) why += "<li class=\"xfail\">known failure: " + esc(r) + "</li>";
  return fmt::format("<td class=\"l\">{}</td><td class=\"l\">{}</td>", pts,
                     why.empty()
                         ? ""
                         : "<details><summary>" + std::to_string(reasons.size() + e["gate"]["problems"].size()) +
                               " notes</summary><ul>" + why + "</ul></details>");
}

std::string outcomes_table(const json& sw) {
  std::string h =
      "<h3>Collision outcomes against the reference</h3>\n<table><tr><th class=\"l\">configuration</th><th>both "
      "collide</th>"
      "<th>neither</th><th>engine only</th><th>reference only</th><th>near boundary</th><th>unexplained</th><th>worst "
      "|t| error [steps]</th></tr>\n";
  for (const auto& e : sw["engines"]) {
    const auto& c = e["confusion"];
    h += fmt::format(
        "<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"st "
        "{}\">{}</td><td>{:.3f}</td></tr>\n",
        esc(e["engine"]), c["both_collide"].get<int>(), c["neither"].get<int>(), c["engine_only"].get<int>(),
        c["reference_only"].get<int>(), e["near_boundary_cases"].get<int>(),
        e["unexplained_disagreements"].get<int>() == 0 ? "pass" : "fail", e["unexplained_disagreements"].get<int>(),
        e["worst_t_error_steps"].get<double>());
  }
  return h +
         fmt::format(
             "</table>\n<p class=\"note\">{} over the grid a &isin; {}, b &isin; {} and N's paths {}; near boundary: "
             "the reference closest approach is within {} m of contact.</p>\n",
             esc(sw["scenario"]), esc(sw["grid"]["a"].dump()), esc(sw["grid"]["b"].dump()),
             esc(sw["grid"]["path"].dump()), sw["near_boundary_m"].get<double>());
}

}  // namespace

/// The sweeps: their plots, a row per sweep x configuration with its points, the outcome sweep.
std::string sweeps_section(const json& results) {
  std::string h = "<h2 id=\"sweeps\">Sweeps</h2>\n<details class=\"fold\"><summary>the sweeps' plots</summary>\n";
  for (const auto& p : results.value("report", json::object()).value("plots", json::array()))
    if (p["group"] == "sweeps" && p["file"].get<std::string>().rfind("plots/map-", 0) != 0)
      h += fmt::format(
          "<figure class=\"wide\"><img class=\"plot\" src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
          esc(p["file"]), esc(p["caption"]), esc(p["caption"]));
  h += "</details>\n<h3>Sweep gates</h3>\n<details class=\"fold\"><summary>each sweep's gate per configuration, "
       "its points</summary>\n<table><tr><th class=\"l\">sweep</th><th class=\"l\">configuration</th><th>gate</th><th "
       "class=\"l\">points "
       "(&#10003; pass, &#10007; known failure)</th><th class=\"l\">problems, known-failure reasons</th></tr>\n";
  for (const auto& sw : results.value("sweeps", json::array())) {
    if (sw.value("kind", "") == "outcomes" || !sw.contains("engines")) continue;
    bool first = true;
    for (const auto& e : sw["engines"]) {
      const auto [cls, word] = gate_status(e["gate"]);
      std::string fit;
      if (e.contains("fit") && e["fit"]["slope"].is_number())
        fit = fmt::format("<br><small>slope {:.3f}</small>", e["fit"]["slope"].get<double>());
      h += fmt::format("<tr{}><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"st {}\">{}{}</td>{}</tr>\n",
                       first ? " id=\"sweep-" + esc(sw["name"]) + "\"" : "", esc(sw["name"]), esc(e["engine"]), cls,
                       word, fit, sweep_points(sw, e));
      first = false;
    }
  }
  h += "</table></details>\n";
  for (const auto& sw : results.value("sweeps", json::array()))
    if (sw.value("kind", "") == "outcomes")
      h += "<details class=\"fold\"><summary>the outcome sweep</summary>\n" + outcomes_table(sw) + "</details>\n";
  return h;
}

/// The configurations with their settings, the machine and the report's own problems.
std::string engines_section(const json& results) {
  const auto& ctx = results["context"];
  const json& rep = results.value("report", json::object());
  std::string h =
      "<h2 id=\"engines\">Engines and settings</h2>\n<details class=\"fold\"><summary>every configuration's "
      "description and settings</summary>\n<table><tr><th class=\"l\">engine</th><th "
      "class=\"l\">version</th><th class=\"l\">settings</th></tr>\n";
  for (const auto& e : ctx["engines"]) {
    std::string settings = esc(e["description"]) + "<ul>";
    const json engine_settings = e.value("settings", json::object());
    for (const auto& [k, v] : engine_settings.items())
      settings += fmt::format("<li><b>{}</b>: {}</li>", esc(k), esc(v));
    settings += "</ul>";
    h += fmt::format(
        "<tr id=\"engine-{0}\"><td class=\"l\">{0}</td><td class=\"l\">{1}</td><td class=\"l\">{2}</td></tr>\n",
        esc(e["name"]), esc(e["version"]), settings);
  }
  h += "</table></details>\n";
  h += fmt::format("<p class=\"meta\">Machine: {} ({}), {} CPUs; renderer: {}.</p>\n", esc(ctx["machine"]["host"]),
                   esc(ctx["machine"]["os"]), ctx["machine"]["cpus"].get<int>(), esc(rep.value("gl_version", "none")));
  for (const auto& err : rep.value("errors", json::array()))
    h += "<p class=\"st error\">report: " + esc(err) + "</p>\n";
  return h;
}

namespace {

/// The scenario's start, drawn once: every configuration starts from the same pose.
std::string start_figure(const json& results, const std::string& sc) {
  for (const auto& s : results.value("report", json::object()).value("snapshots", json::array()))
    if (s["scenario"] == sc && s.value("tag", "") == "start")
      return fmt::format(
          "<div class=\"shots\"><figure><a href=\"{0}\"><img src=\"{0}\" alt=\"start\"></a><figcaption>the start, "
          "as every configuration starts (drawn from {1}'s record; a car settling on its wheels moves a few "
          "mm)</figcaption></figure></div>\n",
          esc(s["file"]), esc(s["engine"]));
  return "";
}

/// A list of names as prose: "a", "a and b", "a, b and c".
std::string names_text(const json& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i].get<std::string>();
  return out;
}

}  // namespace

std::string scenario_html(const json& results, const std::string& sc) {
  const json* info = scenario_info(results, sc);
  const json def = headline_def(results, sc);
  std::string h = head("liftcheck: " + sc);
  h += "<p><a href=\"index.html\">&larr; summary</a></p>\n";
  h += fmt::format("<h1>{}</h1>\n", esc(sc));
  if (info) {
    h += fmt::format("<p>{}</p>\n<p class=\"meta\">Equations: {}</p>\n", esc((*info)["summary"]),
                     esc((*info)["equations"]));
    if ((*info).value("negative_control", false))
      h += "<p class=\"note\"><b>Negative control</b>: meant to fail on every configuration with contact dynamics "
           "(listed as such in the expectations).</p>\n";
  }
  if (def.is_object())
    h += fmt::format("<p class=\"meta\">Headline: {} (the largest of {}).</p>\n", esc(def.value("label", "")),
                     esc(names_text(def["metrics"])));
  if (const std::string set = settings_text(results["context"].value("set", json::object())); !set.empty())
    h += "<p>Settings of this run (<code>--set</code>): <code>" + esc(set) + "</code>.</p>\n";
  h += cross_engine_table(results, sc, def);
  for (const auto& p : results.value("report", json::object()).value("plots", json::array()))
    if (p["group"] == sc)
      h += fmt::format(
          "<figure class=\"wide\"><img class=\"plot\" src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
          esc(p["file"]), esc(p["caption"]), esc(p["caption"]));
  h += start_figure(results, sc);
  bool params_done = false;
  for (const auto& e : engine_order(results)) {
    const json* r = find_run(results, sc, e);
    if (!r) continue;
    if (!params_done && (*r)["params"].is_object()) h += params_table(*r, info), params_done = true;
    h += engine_section(results, *r, def);
  }
  h += "</body>\n</html>\n";
  return h;
}

}  // namespace liftcheck
