// The HTML report, built from results.json alone (runs, sweeps, the scenario catalogue, and the
// "report" block listing the snapshots and plots). Self-contained: relative links, inline CSS.
#pragma once

#include <nlohmann/json.hpp>
#include <string>

namespace liftcheck {

/// index.html: summary matrix, context, sweeps, errata.
std::string index_html(const nlohmann::json& results);
/// scenario-<name>.html: what it checks, parameters, metric tables, snapshots, plots.
std::string scenario_html(const nlohmann::json& results, const std::string& scenario);
/// File name of a scenario's page.
std::string scenario_page(const std::string& scenario);
/// The small Markdown subset of ERRATA.md (headings, pipe tables, paragraphs, `code`).
std::string markdown_html(const std::string& md);

}  // namespace liftcheck
