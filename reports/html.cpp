#include "reports/html.hpp"

#include <fmt/format.h>
#include <set>

namespace liftcheck {

namespace {

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    switch (c) {
      case '&': o += "&amp;"; break;
      case '<': o += "&lt;"; break;
      case '>': o += "&gt;"; break;
      case '"': o += "&quot;"; break;
      default: o += c;
    }
  }
  return o;
}

std::string num(const nlohmann::json& v) {
  return v.is_number() ? fmt::format("{:.6g}", v.get<double>()) : std::string("&ndash;");
}

}  // namespace

std::string index_html(const nlohmann::json& results) {
  const auto& ctx = results.at("context");
  std::string h;
  h += "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
       "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">"
       "<title>liftcheck validation report</title><style>"
       "body{font-family:sans-serif;margin:1.5em;max-width:75em}table{border-collapse:collapse;margin:1em 0}"
       "td,th{border:1px solid #999;padding:.25em .6em;text-align:right}th{background:#eee}"
       "td.l,th.l{text-align:left}.pass{background:#c8f0c8}.fail{background:#f6c0c0}"
       ".error{background:#f0d090}.skip{background:#ddd}</style></head><body>\n";
  h += fmt::format("<h1>liftcheck validation report</h1>\n<p>liftcheck {} (commit {}), {}, {} ({} CPUs), "
                   "wall time {:.2f} s.</p>\n",
                   esc(ctx["liftcheck"]["version"]), esc(ctx["liftcheck"]["commit"]), esc(ctx["date"]),
                   esc(ctx["machine"]["os"]), ctx["machine"]["cpus"].get<int>(), ctx["wall_s"].get<double>());
  const auto& s = results.at("summary");
  h += fmt::format("<p>{} runs: {} pass, {} fail, {} error, {} skip.</p>\n", s["total"].get<int>(),
                   s["pass"].get<int>(), s["fail"].get<int>(), s["error"].get<int>(), s["skip"].get<int>());

  std::vector<std::string> scen, eng;
  for (const auto& r : results["runs"]) {
    if (std::find(scen.begin(), scen.end(), r["scenario"]) == scen.end()) scen.push_back(r["scenario"]);
    if (std::find(eng.begin(), eng.end(), r["engine"]) == eng.end()) eng.push_back(r["engine"]);
  }
  h += "<h2>Summary</h2>\n<table><tr><th class=\"l\">scenario</th>";
  for (const auto& e : eng) h += fmt::format("<th>{}</th>", esc(e));
  h += "</tr>\n";
  for (const auto& sc : scen) {
    h += fmt::format("<tr><td class=\"l\"><a href=\"#{0}\">{0}</a></td>", esc(sc));
    for (const auto& e : eng) {
      const nlohmann::json* run = nullptr;
      for (const auto& r : results["runs"])
        if (r["scenario"] == sc && r["engine"] == e) run = &r;
      if (!run) { h += "<td>&ndash;</td>"; continue; }
      const std::string st = (*run)["status"];
      h += fmt::format("<td class=\"{0}\">{0} {1}</td>", st,
                       (*run)["worst_ratio"].is_number() ? fmt::format("({:.2g} of tol)", (*run)["worst_ratio"].get<double>()) : "");
    }
    h += "</tr>\n";
  }
  h += "</table>\n";
  for (const auto& r : results["runs"]) {
    h += fmt::format("<h3 id=\"{0}\">{0} on {1}: <span class=\"{2}\">{2}</span></h3>\n", esc(r["scenario"]),
                     esc(r["engine"]), esc(r["status"]));
    if (!r["message"].get<std::string>().empty()) h += fmt::format("<p>{}</p>\n", esc(r["message"]));
    h += "<table><tr><th class=\"l\">metric</th><th>expected</th><th>measured</th><th>abs error</th>"
         "<th>rel error</th><th>tolerance</th><th>unit</th><th>result</th></tr>\n";
    for (const auto& [name, m] : r["metrics"].items()) {
      const std::string st = m["pass"].get<bool>() ? "pass" : "fail";
      h += fmt::format("<tr><td class=\"l\">{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{} ({})</td>"
                       "<td>{}</td><td class=\"{}\">{}</td></tr>\n",
                       esc(name), num(m["expected"]), num(m["measured"]), num(m["abs_error"]), num(m["rel_error"]),
                       num(m["tolerance"]), esc(m["tolerance_kind"]), esc(m["unit"]), st, st);
    }
    h += "</table>\n";
  }
  h += "</body></html>\n";
  return h;
}

}  // namespace liftcheck
