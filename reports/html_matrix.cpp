// index.html's first screen: a row per configuration, its counts and a one-line standing, then a
// cell per scenario with the verdict's mark, the figure that decided it and a colour that grows
// with the worst error's multiple of its tolerance on a log scale.
#include <algorithm>
#include <cmath>
#include <limits>

#include "reports/headline.hpp"
#include "reports/html.hpp"
#include "reports/html_common.hpp"

namespace liftcheck {

using namespace html;

namespace {

/// A run's errors against their tolerances, as the matrix shows them: the largest finite multiple
/// among its counted metrics, and the failing metric that decided the verdict (the one with the
/// largest finite multiple; a metric with a zero tolerance, whose multiple is infinite, only when
/// no other failed). A zero tolerance says "any error fails", not how far off the engine is.
struct Multiple {
  double finite = 0;            ///< largest finite multiple of tolerance among the counted metrics
  std::string deciding;         ///< the failing metric that decided it ("" when none failed)
  double deciding_ratio = 0;    ///< its multiple (infinite for a zero tolerance)
  double deciding_error = 0;    ///< its compared error
  bool zero_tolerance = false;  ///< a metric with a zero tolerance (or no finite error) failed
};

Multiple multiple_of(const json& r) {
  Multiple m;
  RecordView(r).each_metric([&](const std::string& name, const MetricView& v) {
    if (!v.counted()) return;
    const double ratio = v.ratio();
    if (std::isfinite(ratio)) m.finite = std::max(m.finite, ratio);
    if (v.pass()) return;
    if (!std::isfinite(ratio)) m.zero_tolerance = true;
    const bool better =
        m.deciding.empty() || (std::isfinite(ratio) && (!std::isfinite(m.deciding_ratio) || ratio > m.deciding_ratio));
    if (better) m.deciding = name, m.deciding_ratio = ratio, m.deciding_error = v.compared_error();
  });
  return m;
}

/// "42×", or "∞×" for a zero tolerance.
std::string times(double ratio) { return (std::isinf(ratio) ? "&infin;" : short_number(ratio)) + "&times;"; }

bool negative_control(const json& results, const std::string& sc) {
  const json* info = scenario_info(results, sc);
  return info && info->value("negative_control", false);
}

/// A failure's background: pale yellow at 1x its tolerance to deep red at 1e4x and beyond,
/// linear in log10 of the multiple.
std::string failure_shade(double multiple) {
  const double t = std::clamp(std::log10(std::max(multiple, 1.0)) / 4.0, 0.0, 1.0);
  return fmt::format("hsl({:.0f},95%,{:.0f}%)", 55.0 * (1.0 - t), 88.0 - 36.0 * t);
}

/// "4.5e-6" (the headline, when its metric decided the verdict or the run passed) or "42×" (the
/// multiple of tolerance of the failing metric that decided it); the metric shown.
std::pair<std::string, std::string> deciding_figure(const std::optional<Figure>& head, const std::string& cls,
                                                    const Multiple& m) {
  if (cls == "pass" || cls == "skip" || cls == "error" || m.deciding.empty())
    return {head ? short_number(head->value) : "", head ? head->metric : ""};
  if (head && head->metric == m.deciding) return {short_number(head->value), head->metric};
  return {times(m.deciding_ratio), m.deciding};
}

/// One cell: its mark and deciding figure, coloured by the multiple; the whole verdict in the
/// tooltip; a link to the configuration's section of the scenario page.
std::string cell(const json& results, const json& r, const json& def) {
  const auto [cls, word] = status_of(r);
  const std::string sc = r["scenario"], eng = r["engine"];
  const bool control = negative_control(results, sc);
  const Multiple multiple = multiple_of(r);
  const std::optional<Figure> headline = headline_figure(r, def);
  const auto [figure, metric] = deciding_figure(headline, cls, multiple);
  const bool unexpected = !r.value("as_expected", true);
  std::string mark = cls == "pass" ? "&#10003;" : cls == "skip" ? "&ndash;" : cls == "error" ? "ERROR" : "&#10007;";
  if (unexpected) mark = word == "UNEXPECTED PASS" ? "UNEXP. PASS" : word;
  std::string style, klass = "c " + cls;
  if (control && !unexpected)
    klass += " neg";
  else if (cls != "pass" && cls != "skip" && cls != "error")
    style = " style=\"background:" + failure_shade(multiple.finite) + "\"";
  if (unexpected) klass += " unexp";
  std::string tip = word;
  if (!multiple.deciding.empty())
    tip += std::isnan(multiple.deciding_error)
               ? fmt::format(": decided by {}, not measured (no finite error)", multiple.deciding)
           : std::isinf(multiple.deciding_ratio)
               ? fmt::format(": decided by {}, {:.3g} against a zero tolerance", multiple.deciding,
                             multiple.deciding_error)
               : fmt::format(": decided by {}, {:.3g}× its tolerance", multiple.deciding, multiple.deciding_ratio);
  else if (!metric.empty())
    tip += fmt::format(": {}, {:.3g}× its tolerance at most", metric, multiple.finite);
  if (control) tip += "\nnegative control: must fail";
  if (has_expectation(r)) tip += "\nknown failure: " + r["expectation"].value("reason", "");
  if (!r.value("message", "").empty()) tip += "\n" + r["message"].get<std::string>();
  const auto head = cls == "skip" || cls == "error" ? std::nullopt : headline;
  const std::string data = fmt::format(" data-ratio=\"{:.17g}\" data-metric=\"{}\"{}", multiple.finite, esc(metric),
                                       head ? fmt::format(" data-headline=\"{:.17g}\"", head->value) : std::string());
  std::string body = mark + (figure.empty() ? "" : "&nbsp;" + figure);
  if (unexpected && !multiple.deciding.empty())  // rare and loud: the failing metric named in the cell itself
    body += fmt::format(
        "<br><small>{} {}tol</small>", esc(multiple.deciding),
        std::isinf(multiple.deciding_ratio) ? "&infin;&times;" : fmt::format("{:.2g}&times;", multiple.deciding_ratio));
  return fmt::format("<td class=\"{}\"{}{}><a href=\"{}#{}\" title=\"{}\">{}</a></td>", klass, style, data,
                     scenario_page(sc), esc(eng), esc(tip), body);
}

struct Standing {
  int pass = 0, known = 0, skip = 0, unexpected = 0, control = 0;
  std::vector<std::string> unexpected_in;
  double worst = 0;  ///< the worst multiple among the known failures, negative controls aside
  std::string worst_in;
  double worst_error = NAN;     ///< its deciding metric's error (shown when only a zero tolerance failed)
  bool worst_zero = false;      ///< the worst is off only against a zero tolerance
  bool worst_is_error = false;  ///< the worst is a listed error (no metrics)
};

Standing standing_of(const json& results, const std::string& eng) {
  Standing s;
  for (const auto& r : results["runs"]) {
    if (r["engine"] != eng) continue;
    const std::string sc = r["scenario"];
    const auto [cls, word] = status_of(r);
    if (!r.value("as_expected", true)) {
      ++s.unexpected, s.unexpected_in.push_back(sc);
      continue;
    }
    if (cls == "pass") ++s.pass;
    if (cls == "skip") ++s.skip;
    if (cls != "xfail") continue;
    ++s.known;
    if (negative_control(results, sc)) {
      ++s.control;
      continue;
    }
    // Ranked by the finite multiple; a run off only against a zero tolerance ranks last (∞×).
    const Multiple m = multiple_of(r);
    const double rank = m.finite > 1.0 || !m.zero_tolerance ? m.finite : 0.0;
    if (s.worst_in.empty() || rank > s.worst) {
      s.worst = rank, s.worst_in = sc;
      s.worst_zero = rank == 0.0 && m.zero_tolerance, s.worst_error = m.deciding_error;
      s.worst_is_error = rank == 0.0 && r.value("status", "") == "error";
    }
  }
  return s;
}

/// "✓15 ✗5 –1": passes, known failures, skips (none: no dash).
std::string counts_text(const Standing& s) {
  std::string c = fmt::format("&#10003;{} &#10007;{}", s.pass, s.known);
  if (s.skip > 0) c += fmt::format(" &ndash;{}", s.skip);
  return c;
}

/// The configuration in a line: its counts, then what is not as expected, or where it is furthest
/// off (negative controls aside).
std::string standing_line(const Standing& s, bool reference) {
  if (s.unexpected > 0) {
    std::string where;
    for (const auto& sc : s.unexpected_in) where += (where.empty() ? "" : ", ") + esc(sc);
    return fmt::format("<b class=\"fail\">&nbsp;{} not as expected&nbsp;</b> {}", s.unexpected, where);
  }
  const std::string counts = counts_text(s);
  if (s.known == s.control) return counts + (reference ? " &middot; the reference" : " &middot; passes all it runs");
  if (s.worst_is_error) return fmt::format("{} &middot; worst {}: an error (listed)", counts, esc(s.worst_in));
  if (s.worst_zero)  // only a metric with a zero tolerance failed: its error in the tooltip
    return fmt::format("{} &middot; worst <span title=\"{} against a zero tolerance\">&infin;&times;</span> {}", counts,
                       short_number(s.worst_error), esc(s.worst_in));
  return fmt::format("{} &middot; worst {}&times; {}", counts, short_number(s.worst), esc(s.worst_in));
}

/// A scenario's column head: its name (breaking after dots and hyphens) over its headline's label.
std::string column_head(const json& results, const std::string& sc) {
  const json def = headline_def(results, sc);
  std::string name;
  for (char c : sc) name += c == '.' || c == '-' ? std::string(1, c) + "<wbr>" : esc(std::string(1, c));
  std::string label = def.is_object() ? def.value("label", "") : "";
  if (def.is_object() && !def.value("unit", "").empty()) label += ", " + def["unit"].get<std::string>();
  if (negative_control(results, sc)) label = "control: must fail";
  const json* info = scenario_info(results, sc);
  return fmt::format("<th class=\"sc\" title=\"{}\"><a href=\"{}\">{}</a><small>{}</small></th>",
                     info ? esc(info->value("equations", "")) : "", scenario_page(sc), name, esc(label));
}

}  // namespace

std::string matrix_section(const json& results) {
  const auto scenarios = scenario_order(results);
  std::string h =
      "<table id=\"matrix\" class=\"matrix\"><tr><th class=\"l\">configuration</th><th class=\"l\">standing: "
      "&#10003; &#10007; &ndash;, worst</th>";
  std::vector<json> defs;  // each scenario's headline, looked up once
  for (const auto& sc : scenarios) h += column_head(results, sc), defs.push_back(headline_def(results, sc));
  h += "</tr>\n";
  for (const auto& e : results["context"]["engines"]) {
    const std::string eng = e["name"];
    const Standing s = standing_of(results, eng);
    h += fmt::format(
        "<tr><th class=\"l cfg\"><span class=\"sw\" style=\"background:{}\"></span><a href=\"#engine-{}\">{}</a></th>"
        "<td class=\"l standing\">{}</td>",
        esc(e.value("color", "#888")), esc(eng), esc(eng), standing_line(s, e.value("is_reference", false)));
    for (std::size_t i = 0; i < scenarios.size(); ++i) {
      const json* r = find_run(results, scenarios[i], eng);
      h += r ? cell(results, *r, defs[i]) : "<td class=\"c\"></td>";
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
