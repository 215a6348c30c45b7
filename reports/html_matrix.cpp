// index.html's first screen: a row per configuration, its counts and a one-line standing, then a
// cell per scenario with the verdict's mark, the figure that decided it and a colour that grows
// with the worst error's multiple of its tolerance on a log scale.
#include <algorithm>
#include <cmath>
#include <limits>

#include "reports/html.hpp"
#include "reports/html_common.hpp"

namespace liftcheck {

using namespace html;

namespace {

/// A failure's background: pale yellow at 1x its tolerance to deep red at 1e4x and beyond,
/// linear in log10 of the multiple.
std::string failure_shade(double multiple) {
  const double t = std::clamp(std::log10(std::max(multiple, 1.0)) / 4.0, 0.0, 1.0);
  return fmt::format("hsl({:.0f},95%,{:.0f}%)", 55.0 * (1.0 - t), 88.0 - 36.0 * t);
}

/// "42×", or "∞×" for a zero tolerance.
std::string times(double ratio) { return (std::isinf(ratio) ? "&infin;" : short_number(ratio)) + "&times;"; }

/// "4.5e-6" (the headline, when its metric decided the verdict or the run passed) or "42×" (the
/// multiple of tolerance of the failing metric that decided it); the metric shown.
std::pair<std::string, std::string> deciding_figure(const std::optional<Figure>& head, const std::string& cls,
                                                    const Deciding& m) {
  if (cls == "pass" || cls == "skip" || cls == "error" || m.metric.empty())
    return {head ? short_number(head->value) : "", head ? head->metric : ""};
  if (head && head->metric == m.metric) return {short_number(head->value), head->metric};
  return {times(m.ratio), m.metric};
}

/// A cell's tooltip: its verdict, what decided it, its listing's reason and its message.
std::string cell_tip(const RunResult& r, const std::string& word, const Deciding& d, const std::string& metric) {
  std::string tip = word;
  if (!d.metric.empty())
    tip += std::isnan(d.error)   ? fmt::format(": decided by {}, not measured (no finite error)", d.metric)
           : std::isinf(d.ratio) ? fmt::format(": decided by {}, {:.3g} against a zero tolerance", d.metric, d.error)
                                 : fmt::format(": decided by {}, {:.3g}× its tolerance", d.metric, d.ratio);
  else if (!metric.empty())
    tip += fmt::format(": {}, {:.3g}× its tolerance at most", metric, d.finite);
  if (r.negative_control) tip += "\nnegative control: must fail";
  if (r.expectation) tip += "\nknown failure: " + r.expectation->reason;
  if (!r.message.empty()) tip += "\n" + r.message;
  return tip;
}

/// One cell: its mark and deciding figure, coloured by the multiple; the whole verdict in the
/// tooltip; a link to the configuration's section of the scenario page.
std::string cell(const RunResult& r, const ScenarioInfo* info) {
  const auto [cls, word] = status_of(r);
  const Deciding deciding = deciding_of(r);
  const std::optional<Figure> headline = headline_figure(r, info);
  const auto [figure, metric] = deciding_figure(headline, cls, deciding);
  const bool unexpected = !r.as_expected();
  std::string mark = cls == "pass" ? "&#10003;" : cls == "skip" ? "&ndash;" : cls == "error" ? "ERROR" : "&#10007;";
  if (unexpected) mark = word == "UNEXPECTED PASS" ? "UNEXP. PASS" : word;
  std::string style, klass = "c " + cls;
  if (r.negative_control && !unexpected)
    klass += " neg";
  else if (cls != "pass" && cls != "skip" && cls != "error")
    style = " style=\"background:" + failure_shade(deciding.finite) + "\"";
  if (unexpected) klass += " unexp";
  const std::string tip = cell_tip(r, word, deciding, metric);
  const auto head = cls == "skip" || cls == "error" ? std::nullopt : headline;
  const std::string data = fmt::format(" data-ratio=\"{:.17g}\" data-metric=\"{}\"{}", deciding.finite, esc(metric),
                                       head ? fmt::format(" data-headline=\"{:.17g}\"", head->value) : std::string());
  std::string body = mark + (figure.empty() ? "" : "&nbsp;" + figure);
  if (unexpected && !deciding.metric.empty())  // rare and loud: the failing metric named in the cell itself
    body += fmt::format("<br><small>{} {}tol</small>", esc(deciding.metric),
                        std::isinf(deciding.ratio) ? "&infin;&times;" : fmt::format("{:.2g}&times;", deciding.ratio));
  return fmt::format("<td class=\"{}\"{}{}><a href=\"{}#{}\" title=\"{}\">{}</a></td>", klass, style, data,
                     scenario_page(r.scenario), esc(r.engine), esc(tip), body);
}

/// "✓15 ✗5 –1": passes, known failures, skips (none: no dash).
std::string counts_text(const Standing& s) {
  std::string c = fmt::format("&#10003;{} &#10007;{}", s.pass, s.known);
  if (s.skip > 0) c += fmt::format(" &ndash;{}", s.skip);
  return c;
}

/// The configuration in a line: its counts, then what is not as expected, or where it is furthest
/// off (negative controls aside): the standing every output prints (input/standing.hpp).
std::string standing_line(const Standing& s) {
  if (s.unexpected > 0) {
    std::string where;
    for (const auto& sc : s.unexpected_in) where += (where.empty() ? "" : ", ") + esc(sc);
    return fmt::format("<b class=\"fail\">&nbsp;{} not as expected&nbsp;</b> {}", s.unexpected, where);
  }
  const std::string counts = counts_text(s);
  if (!s.worst) return counts + (s.reference ? " &middot; the reference" : " &middot; passes all it runs");
  // The row names the worst failure's figure and scenario; its metric is in the title (the line
  // must fit its column: tests/screenshot_check.py), as summary.md prints it whole.
  return fmt::format("{} &middot; worst <span class=\"worst\" title=\"{}\">{}</span>", counts, esc(s.worst_text()),
                     esc(s.worst_short_text()));
}

/// A scenario's column head: its name (breaking after dots and hyphens) over its headline's label.
std::string column_head(const ScenarioInfo* info, const std::string& sc) {
  std::string name;
  for (char c : sc) name += c == '.' || c == '-' ? std::string(1, c) + "<wbr>" : esc(std::string(1, c));
  std::string label = info ? info->headline_label : "";
  if (info && !info->headline_unit.empty()) label += ", " + info->headline_unit;
  if (info && info->negative_control) label = "control: must fail";
  return fmt::format("<th class=\"sc\" title=\"{}\"><a href=\"{}\">{}</a><small>{}</small></th>",
                     info ? esc(info->equations) : "", scenario_page(sc), name, esc(label));
}

}  // namespace

std::string matrix_section(const SuiteResults& results) {
  const auto scenarios = results.scenario_order();
  std::string h =
      "<table id=\"matrix\" class=\"matrix\"><tr><th class=\"l\">configuration</th><th class=\"l\">standing: "
      "&#10003; &#10007; &ndash;, worst</th>";
  std::vector<const ScenarioInfo*> infos;  // each scenario's, looked up once
  for (const auto& sc : scenarios) infos.push_back(results.scenario(sc)), h += column_head(infos.back(), sc);
  h += "</tr>\n";
  const std::vector<Standing> all = standings(results);
  for (std::size_t k = 0; k < all.size(); ++k) {
    const EngineContext& e = results.context.engines[k];
    h += fmt::format(
        "<tr><th class=\"l cfg\"><span class=\"sw\" style=\"background:{}\"></span><a href=\"#engine-{}\">{}</a></th>"
        "<td class=\"l standing\">{}</td>",
        esc(e.color.empty() ? "#888" : e.color), esc(e.name), esc(e.name), standing_line(all[k]));
    for (std::size_t i = 0; i < scenarios.size(); ++i) {
      const RunResult* r = results.run(scenarios[i], e.name);
      h += r ? cell(*r, infos[i]) : "<td class=\"c\"></td>";
    }
    h += "</tr>\n";
  }
  h += "</table>\n<p class=\"legend\">A row per configuration. &#10003; pass, with the scenario's headline (the "
       "engine's own error on what the scenario is about) &middot; &#10007; reviewed known failure, with the figure "
       "that decided it: the headline, or <i>k</i>&times; when another metric failed, by <i>k</i> times its "
       "tolerance (&infin;&times;: a tolerance of zero, which any error fails, or an error not measured) &middot; "
       "colour: the largest finite "
       "multiple of a tolerance, "
       "<span class=\"key\" "
       "style=\"background:" +
       failure_shade(1.5) + "\">1&times;</span><span class=\"key\" style=\"background:" + failure_shade(30) +
       "\">10&times;</span><span class=\"key\" style=\"background:" + failure_shade(300) +
       "\">100&times;</span><span class=\"key\" style=\"background:" + failure_shade(3000) +
       "\">1000&times;</span><span class=\"key\" style=\"background:" + failure_shade(1e5) +
       "\">10<sup>4</sup>&times;+</span> &middot; <span class=\"key neg\">hatched</span>: a negative control, which "
       "must fail &middot; <span class=\"key unexp\">FAIL</span>, ERROR, UNEXPECTED PASS: not as expected (below) "
       "&middot; &ndash; not run. Each cell links to the engine's section of the scenario page, its tooltip names "
       "the deciding metric.</p>\n";
  return h;
}

}  // namespace liftcheck
