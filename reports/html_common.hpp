// Pieces shared by the report's pages (reports/html.cpp, reports/html_scenario.cpp): escaping,
// the page head with its CSS, a run's status, and lookups in results.json.
#pragma once

#include <cmath>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>
#include <vector>

#include "input/standing.hpp"
#include "input/suite_result.hpp"
#include "reports/escape.hpp"

namespace liftcheck::html {

using json = nlohmann::json;

inline std::string esc(const std::string& s) { return escape_markup(s); }

/// A figure: NaN (null or absent in the record) is a dash.
inline std::string num(double v) { return std::isnan(v) ? "&ndash;" : fmt::format("{:.6g}", v); }

inline constexpr const char* kCss =
    "body{font-family:'DejaVu Sans',Arial,sans-serif;margin:0 auto;padding:.5em "
    ".6em;max-width:96em;color:#222;line-height:1.35}"
    "h1{font-size:1.35em;margin:.2em 0}h2{margin-top:1.4em;border-bottom:1px solid #ccc;font-size:1.25em}"
    "table{border-collapse:collapse;margin:.5em 0}td,th{border:1px solid #bbb;padding:.2em "
    ".5em;text-align:right;vertical-align:top}"
    "th{background:#eee}td.l,th.l{text-align:left}"
    ".pass{background:#c6efce;color:#0b5a17}.fail{background:#ffc7ce;color:#8a0010}.error{background:#ffe09a;color:#"
    "6b4300}"
    ".skip{background:#e4e4e4;color:#555}.xfail{background:#d6e8f7;color:#104a7a}"
    "td.st,span.st{font-weight:bold;text-align:center;white-space:nowrap}"
    "p.counts{margin:.2em 0 .4em 0}"
    // 24 configurations and 21 scenarios on the first screen of a 1366 x 768 window (tests/screenshot_check.py).
    "table.matrix{font-size:9px;line-height:1.15;margin:.2em 0}table.matrix td,table.matrix th{padding:1px "
    "2px;vertical-align:middle;white-space:nowrap}"
    "table.matrix th.sc{white-space:normal;max-width:5em;font-size:8.5px;line-height:1.1;vertical-align:bottom;"
    "text-align:center}table.matrix th.sc a{color:#123;font-weight:bold}"
    "table.matrix th.sc small{display:block;font-weight:normal;color:#555;font-size:8px}"
    "table.matrix th.cfg{text-align:left;font-weight:normal}table.matrix th.cfg a{color:#123}"
    "span.sw{display:inline-block;width:.8em;height:.8em;margin-right:.3em;vertical-align:-1px;border-radius:2px}"
    "table.matrix td.standing{max-width:19.5em;overflow:hidden;text-overflow:ellipsis}"
    "table.matrix td.c{text-align:left;padding:0}table.matrix td.c a{display:block;padding:1px "
    "2px;color:#222;text-decoration:none}"
    "table.matrix td.c a:hover{outline:2px solid #333}"
    ".neg{background:repeating-linear-gradient(135deg,#e6e6ee 0 3px,#d2d2de 3px 6px)!important}"
    ".unexp{outline:2px solid #8a0010;outline-offset:-2px;font-weight:bold}"
    ".key{padding:0 .35em;margin:0 .1em;border:1px solid #ccc}"
    ".legend{font-size:.8em;color:#444;margin:.1em 0}"
    ".shots{display:flex;flex-wrap:wrap;gap:10px}.shots figure{margin:0;width:480px}.shots img{width:480px;border:1px "
    "solid #ccc}"
    "figure.wide img{max-width:100%;border:1px solid #ccc}figcaption{font-size:.85em;color:#555}"
    "img.plot{max-width:100%;border:1px solid #ddd}code{background:#f3f3f3;padding:0 .2em}"
    ".meta{color:#555;font-size:.85em}.note{font-size:.9em;color:#444}details summary{cursor:pointer}"
    "ul.toc{columns:2;font-size:.95em}td ul{margin:0;padding-left:1.1em}"
    "table.tune{font-size:.8em;table-layout:fixed;width:100%}table.tune td{overflow-wrap:anywhere}";

inline std::string head(const std::string& title) {
  return fmt::format(
      "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n"
      "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">\n<title>{}</title>\n"
      "<style>{}</style>\n</head>\n<body>\n",
      esc(title), kCss);
}

/// CSS class and word for a run's verdict (a reviewed known failure has its own colour; a listed
/// failure that passes is as unexpected as a failure).
inline std::pair<std::string, std::string> status_of(const RunResult& r) {
  switch (r.verdict()) {
    case Verdict::kKnownFailure:
      return {"xfail", "KNOWN FAILURE"};
    case Verdict::kUnexpectedPass:
      return {"fail", "UNEXPECTED PASS"};
    case Verdict::kPass:
      return {"pass", "PASS"};
    case Verdict::kFail:
      return {"fail", "FAIL"};
    case Verdict::kError:
      return {"error", "ERROR"};
    case Verdict::kSkip:
      return {"skip", "SKIP"};
  }
  return {"error", "ERROR"};
}

inline std::vector<std::string> engine_order(const SuiteResults& results) {
  std::vector<std::string> v;
  for (const auto& e : results.context.engines) v.push_back(e.name);
  return v;
}

/// "dx: measured 7.7e-4, expected 7.38e-4, relative error 0.043, tolerance 0.02 (2.1× tolerance)".
inline std::string metric_figures(const Metric& m) {
  const double tol = m.tolerance, e = m.compared_error();
  return fmt::format("{}: measured {} {}, expected {}, {} error {:.3g}, tolerance {:.3g} ({:.3g}&times; tolerance)",
                     esc(m.name), num(m.measured), esc(m.unit), num(m.expected),
                     m.kind == TolKind::kRelative ? "relative" : "absolute", e, tol, tol > 0 ? e / tol : INFINITY);
}

/// KEY=VALUE pairs as text ("" when there are none): a run's settings, the suite's --set.
template <class Pairs>
std::string settings_text(const Pairs& pairs) {
  std::string s;
  for (const auto& [k, v] : pairs) s += fmt::format("{}{}={}", s.empty() ? "" : ", ", k, v);
  return s;
}

}  // namespace liftcheck::html
