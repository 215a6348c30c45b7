// The scenario pages, and the index's sweeps and engines sections.
#include <set>

#include "reports/html.hpp"
#include "reports/html_common.hpp"
#include "input/json_in.hpp"  // scalar_text
#include "scenarios/details.hpp"

namespace liftcheck {

using namespace html;

namespace {

/// A run's metrics, the headline's first, then the rest from the worst ratio down; the ratio to
/// the tolerance in a column of its own.
std::string metric_table(const RunResult& r, const ScenarioInfo* info) {
  const std::vector<std::string> first = info ? info->headline_metrics : std::vector<std::string>{};
  std::vector<std::pair<double, const Metric*>> order;
  for (const Metric& m : r.metrics) {
    const auto it = std::find(first.begin(), first.end(), m.name);
    const double key = it != first.end() ? 1e300 - static_cast<double>(it - first.begin()) : m.ratio();
    order.emplace_back(std::isfinite(key) ? key : 1e299, &m);
  }
  std::stable_sort(order.begin(), order.end(), [](const auto& a, const auto& b) { return a.first > b.first; });
  std::string h =
      "<table><tr><th class=\"l\">metric</th><th>expected</th><th>measured</th><th>abs error</th>"
      "<th>rel error</th><th>tolerance</th><th>error / tolerance</th><th class=\"l\">unit</th><th>result</th></tr>\n";
  for (const auto& [key, mp] : order) {
    const Metric& m = *mp;
    const bool info_only = !m.counted(), rel = m.kind == TolKind::kRelative;
    const bool headline = std::find(first.begin(), first.end(), m.name) != first.end();
    const double err = m.compared_error(), tol = m.tolerance;
    h += fmt::format(
        "<tr><td class=\"l\">{}{}{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{} ({})</td><td>{}</td><td "
        "class=\"l\">{}</td>"
        "<td class=\"st {}\">{}</td></tr>\n",
        headline ? "<b>" : "", esc(m.name), headline ? "</b> (headline)" : "", num(m.expected), num(m.measured),
        num(m.abs_error), rel ? num(m.rel_error) : "&ndash;", num(m.tolerance), to_string(m.kind),
        tol > 0 ? short_number(err / tol) : "&ndash;", esc(m.unit),
        info_only ? "skip"
        : m.pass  ? "pass"
                  : "fail",
        info_only ? "info (not counted)"
        : m.pass  ? "ok"
                  : "FAIL");
  }
  return h + "</table>\n";
}

/// The run's parameters with their units and meanings.
std::string params_table(const RunResult& r, const ScenarioInfo* info) {
  std::string h =
      "<h2 id=\"parameters\">Parameters of this run</h2>\n<table><tr><th class=\"l\">parameter</th><th>value</th><th "
      "class=\"l\">unit</th>"
      "<th class=\"l\">meaning</th></tr>\n";
  const nlohmann::json params = r.params.to_json();
  for (const auto& [k, v] : params.items()) {
    std::string unit, help;
    if (info)
      for (const auto& p : info->params)
        if (p.key == k) unit = p.unit, help = p.help;
    h += fmt::format("<tr><td class=\"l\">{}</td><td>{}</td><td class=\"l\">{}</td><td class=\"l\">{}</td></tr>\n",
                     esc(k), esc(v.is_string() ? v.get<std::string>() : v.dump()), esc(unit), esc(help));
  }
  return h + "</table>\n";
}

/// Every configuration on this scenario: verdict, headline, failing metrics, settings, reason.
std::string cross_engine_table(const SuiteResults& results, const std::string& sc, const ScenarioInfo* info) {
  std::string h = fmt::format(
      "<h2 id=\"engines\">Every configuration</h2>\n<table><tr><th class=\"l\">configuration</th><th>verdict</th>"
      "<th>{}{}</th><th>error / tolerance</th><th class=\"l\">decided by</th><th class=\"l\">failing metrics (error "
      "/ tolerance)</th><th class=\"l\">settings applied</th>"
      "<th class=\"l\">known failure: reason</th></tr>\n",
      esc(info ? info->headline_label : "headline"),
      info && !info->headline_unit.empty() ? ", " + esc(info->headline_unit) : "");
  for (const auto& e : engine_order(results)) {
    const RunResult* r = results.run(sc, e);
    if (!r) continue;
    const auto [cls, word] = status_of(*r);
    const auto fig = headline_figure(*r, info);
    std::string failing;
    for (const Metric& m : r->metrics)
      if (!m.pass && m.counted())
        failing += fmt::format(
            "{}{} {} ({:.2g}&times;)", failing.empty() ? "" : "; ", esc(m.name),
            esc(Figure{m.name, m.compared_error(), m.kind == TolKind::kRelative ? "" : m.unit, m.ratio()}.text()),
            m.ratio());
    const std::string applied = settings_text(r->settings);
    h += fmt::format(
        "<tr><td class=\"l\"><a href=\"#{0}\">{0}</a></td><td class=\"st {1}\">{2}</td><td>{3}</td><td>{4}</td><td "
        "class=\"l decided\">{8}</td><td class=\"l\">{5}</td>"
        "<td class=\"l\">{6}</td><td class=\"l\">{7}</td></tr>\n",
        esc(e), cls, word, fig ? short_number(fig->value) : "&ndash;", fig ? short_number(fig->ratio) : "&ndash;",
        failing, applied.empty() ? "" : "<code>" + esc(applied) + "</code>",
        r->expectation               ? esc(r->expectation->reason)
        : r->status == Status::kSkip ? esc(r->message)
                                     : "",
        esc(deciding_of(*r).text()));
  }
  return h + "</table>\n";
}

/// A figure of the page: a picture, linked to itself, with its caption.
std::string shot_figure(const ReportFile& s) {
  return fmt::format("<figure><a href=\"{0}\"><img src=\"{0}\" alt=\"{1}\"></a><figcaption>{2}</figcaption></figure>\n",
                     esc(s.file), esc(s.alt), esc(s.caption));
}

/// One configuration's section: verdict, reason, metrics, errors split, snapshots.
std::string engine_section(const SuiteResults& results, const RunResult& r, const ScenarioInfo* info) {
  const auto [cls, word] = status_of(r);
  std::string h =
      fmt::format("<h2 id=\"{0}\">{0}: <span class=\"st {1}\">&nbsp;{2}&nbsp;</span></h2>\n", esc(r.engine), cls, word);
  if (!r.message.empty()) h += "<p>" + esc(r.message) + "</p>\n";
  if (r.expectation)
    h += fmt::format("<p class=\"note\"><b>Known failure</b>: {}<br><i>Measured when reviewed:</i> {}</p>\n",
                     esc(r.expectation->reason), esc(r.expectation->measured));
  if (const std::string s = settings_text(r.settings); !s.empty())
    h += "<p class=\"meta\">Settings applied: <code>" + esc(s) + "</code></p>\n";
  if (!r.metrics.empty()) h += metric_table(r, info);
  const nlohmann::json& d = r.details;
  if (const auto load = d.find(detail_key::kGroundLoad);
      load != d.end() && load->is_object() && load->contains(detail_key::kNotMeasured))
    h += "<p class=\"note\">Not measured here: the ground's load (<code>load_at_rest</code>, "
         "<code>load_over_drive</code>): " +
         esc(scalar_text((*load)[detail_key::kNotMeasured])) + ".</p>\n";
  if (const auto er = d.find(detail_key::kErrors); er != d.end() && er->is_object())
    h += fmt::format(
        "<p class=\"note\">Actuation error (lift of the realized (alpha, beta) against the commanded lift): {:.3g} m; "
        "contact error (engine pose against the lift of its realized path): {:.3g} m.</p>\n",
        (*er)[detail_key::kActuationError].get<double>(), (*er)[detail_key::kContactError].get<double>());
  h += "<div class=\"shots\">\n";
  if (results.report)
    for (const auto& s : results.report->snapshots)
      if (s.scenario == r.scenario && s.engine == r.engine && s.tag != "start") h += shot_figure(s);
  h += "</div>\n";
  if (results.report)
    for (const auto& s : results.report->strips)
      if (s.scenario == r.scenario && s.engine == r.engine)
        h += fmt::format("<figure class=\"wide\"><img src=\"{0}\" alt=\"{1}\"><figcaption>{2}</figcaption></figure>\n",
                         esc(s.file), esc(s.alt), esc(s.caption));
  return h;
}

/// A sweep entry's gate: pass, known failure (it passes only through listed failures) or fail.
std::pair<std::string, std::string> gate_status(const Gate& g) {
  if (!g.pass) return {"fail", "FAIL"};
  if (g.points_known_failure > 0)
    return {"xfail", g.points_pass == 0 ? "KNOWN FAILURE" : fmt::format("pass, {} known", g.points_known_failure)};
  return {"pass", "pass"};
}

/// A sweep entry's points in one line: x and a mark each; its reasons once each.
std::string sweep_points(const Sweep& sw, const SweepEngine& e) {
  std::string pts;
  std::vector<std::string> reasons;
  for (const SweepPoint& pt : e.points) {
    const bool known = !pt.known_failure.empty();
    const Status st = pt.status;
    const char* cls = known ? "xfail" : st == Status::kPass ? "pass" : st == Status::kError ? "error" : "fail";
    const char* mark = known ? "&#10007;" : st == Status::kPass ? "&#10003;" : st == Status::kError ? "!" : "FAIL";
    const std::string x = nlohmann::json(pt.x).dump();
    pts += fmt::format("<span class=\"{}\" title=\"{} = {}: {}\">&nbsp;{}&nbsp;{}&nbsp;</span> ", cls, esc(sw.param),
                       esc(x), esc(pt.message.empty() ? to_string(st) : pt.message), esc(x), mark);
    if (known && std::find(reasons.begin(), reasons.end(), pt.known_failure) == reasons.end())
      reasons.push_back(pt.known_failure);
  }
  std::string why;
  for (const auto& p : e.gate.problems) why += "<li>" + esc(p) + "</li>";
  for (const auto& r : reasons) why += "<li class=\"xfail\">known failure: " + esc(r) + "</li>";
  const std::size_t notes = reasons.size() + e.gate.problems.size();
  return fmt::format("<td class=\"l\">{}</td><td class=\"l\">{}</td>", pts,
                     why.empty() ? ""
                                 : fmt::format("<details><summary>{} note{}</summary><ul>{}</ul></details>", notes,
                                               notes == 1 ? "" : "s", why));
}

std::string outcomes_table(const OutcomeSweep& sw) {
  std::string h =
      "<h3>Collision outcomes against the reference</h3>\n<table><tr><th class=\"l\">configuration</th><th>both "
      "collide</th>"
      "<th>neither</th><th>engine only</th><th>reference only</th><th>near boundary</th><th>unexplained</th><th>worst "
      "|t| error [steps]</th></tr>\n";
  for (const auto& e : sw.engines)
    h += fmt::format(
        "<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"st "
        "{}\">{}</td><td>{:.3f}</td></tr>\n",
        esc(e.engine), e.both_collide, e.neither, e.engine_only, e.reference_only, e.near_boundary_cases,
        e.unexplained_disagreements == 0 ? "pass" : "fail", e.unexplained_disagreements, e.worst_t_error_steps);
  return h + fmt::format(
                 "</table>\n<p class=\"note\">{} over the grid a &isin; {}, b &isin; {} and N's paths {}; near "
                 "boundary: the reference closest approach is within {} m of contact.</p>\n",
                 esc(sw.scenario), esc(nlohmann::json(sw.grid_a).dump()), esc(nlohmann::json(sw.grid_b).dump()),
                 esc(nlohmann::json(sw.grid_path).dump()), sw.near_boundary_m);
}

}  // namespace

/// The sweeps: their plots, a row per sweep x configuration with its points, the outcome sweep.
std::string sweeps_section(const SuiteResults& results) {
  std::string h = "<h2 id=\"sweeps\">Sweeps</h2>\n<details class=\"fold\"><summary>the sweeps' plots</summary>\n";
  if (results.report)
    for (const auto& p : results.report->plots)
      if (p.group == "sweeps" && p.file.rfind("plots/map-", 0) != 0)
        h += fmt::format(
            "<figure class=\"wide\"><img class=\"plot\" src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
            esc(p.file), esc(p.alt), esc(p.caption));
  h += "</details>\n<h3>Sweep gates</h3>\n<details class=\"fold\"><summary>each sweep's gate per configuration, "
       "its points</summary>\n<table><tr><th class=\"l\">sweep</th><th class=\"l\">configuration</th><th>gate</th><th "
       "class=\"l\">points "
       "(&#10003; pass, &#10007; known failure)</th><th class=\"l\">problems, known-failure reasons</th></tr>\n";
  for (const Sweep& sw : results.sweeps) {
    bool first = true;
    for (const SweepEngine& e : sw.engines) {
      const auto [cls, word] = gate_status(e.gate);
      std::string fit;
      if (e.fit && std::isfinite(e.fit->slope)) fit = fmt::format("<br><small>slope {:.3f}</small>", e.fit->slope);
      h += fmt::format("<tr{}><td class=\"l\">{}</td><td class=\"l\">{}</td><td class=\"st {}\">{}{}</td>{}</tr>\n",
                       first ? " id=\"sweep-" + esc(sw.name) + "\"" : "", esc(sw.name), esc(e.engine), cls, word, fit,
                       sweep_points(sw, e));
      first = false;
    }
  }
  h += "</table></details>\n";
  if (results.outcomes)
    h += "<details class=\"fold\"><summary>the outcome sweep</summary>\n" + outcomes_table(*results.outcomes) +
         "</details>\n";
  return h;
}

/// The configurations with their settings, the machine and the report's own problems.
std::string engines_section(const SuiteResults& results) {
  const SuiteContext& ctx = results.context;
  std::string h =
      "<h2 id=\"engines\">Engines and settings</h2>\n<details class=\"fold\"><summary>every configuration's "
      "description and settings</summary>\n<table><tr><th class=\"l\">engine</th><th "
      "class=\"l\">version</th><th class=\"l\">settings</th></tr>\n";
  for (const EngineContext& e : ctx.engines) {
    std::string settings = esc(e.description) + "<ul>";
    for (const auto& [k, v] : e.settings) settings += fmt::format("<li><b>{}</b>: {}</li>", esc(k), esc(v));
    settings += "</ul>";
    h += fmt::format(
        "<tr id=\"engine-{0}\"><td class=\"l\">{0}</td><td class=\"l\">{1}</td><td class=\"l\">{2}</td></tr>\n",
        esc(e.name), esc(e.version), settings);
  }
  h += "</table></details>\n";
  h += fmt::format("<p class=\"meta\">Machine: {} ({}), {} CPUs; renderer: {}.</p>\n", esc(ctx.machine.host),
                   esc(ctx.machine.os), ctx.machine.cpus,
                   esc(results.report && !results.report->gl_version.empty() ? results.report->gl_version : "none"));
  if (results.report)
    for (const auto& err : results.report->errors) h += "<p class=\"st error\">report: " + esc(err) + "</p>\n";
  return h;
}

namespace {

/// The scenario's start, drawn once: every configuration starts from the same pose.
std::string start_figure(const SuiteResults& results, const std::string& sc) {
  if (results.report)
    for (const auto& s : results.report->snapshots)
      if (s.scenario == sc && s.tag == "start")
        return fmt::format(
            "<div class=\"shots\"><figure><a href=\"{0}\"><img src=\"{0}\" alt=\"{2}\"></a><figcaption>the start, "
            "as every configuration starts (drawn from {1}'s record; a car settling on its wheels moves a few "
            "mm)</figcaption></figure></div>\n",
            esc(s.file), esc(s.engine), esc(s.alt));
  return "";
}

/// A list of names as prose: "a", "a and b", "a, b and c".
std::string names_text(const std::vector<std::string>& names) {
  std::string out;
  for (std::size_t i = 0; i < names.size(); ++i)
    out += (i == 0 ? "" : i + 1 == names.size() ? " and " : ", ") + names[i];
  return out;
}

}  // namespace

std::string scenario_html(const SuiteResults& results, const std::string& sc) {
  const ScenarioInfo* info = results.scenario(sc);
  std::string h = head("liftcheck: " + sc);
  h += "<p><a href=\"index.html\">&larr; summary</a></p>\n";
  h += fmt::format("<h1>{}</h1>\n", esc(sc));
  if (info) {
    h += fmt::format("<p>{}</p>\n<p class=\"meta\">Equations: {}</p>\n", esc(info->summary), esc(info->equations));
    if (info->negative_control)
      h += "<p class=\"note\"><b>Negative control</b>: meant to fail on every configuration with contact dynamics "
           "(it is as expected when it fails, listed or not).</p>\n";
    if (!info->headline_metrics.empty())
      h += fmt::format("<p class=\"meta\">Headline: {} (the largest of {}).</p>\n", esc(info->headline_label),
                       esc(names_text(info->headline_metrics)));
  }
  if (const std::string set = settings_text(results.context.set); !set.empty())
    h += "<p>Settings of this run (<code>--set</code>): <code>" + esc(set) + "</code>.</p>\n";
  h += cross_engine_table(results, sc, info);
  if (results.report)
    for (const auto& p : results.report->plots)
      if (p.group == sc)
        h += fmt::format(
            "<figure class=\"wide\"><img class=\"plot\" src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
            esc(p.file), esc(p.alt), esc(p.caption));
  h += start_figure(results, sc);
  bool params_done = false;
  for (const auto& e : engine_order(results)) {
    const RunResult* r = results.run(sc, e);
    if (!r) continue;
    if (!params_done) h += params_table(*r, info), params_done = true;
    h += engine_section(results, *r, info);
  }
  h += "</body>\n</html>\n";
  return h;
}

}  // namespace liftcheck
