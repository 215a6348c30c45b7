// The HTML report, built from results.json alone (runs, sweeps, the scenario catalogue, and the
// "report" block listing the snapshots and plots). Self-contained: relative links, inline CSS.
#pragma once

#include <string>

#include "input/suite_result.hpp"

namespace liftcheck {

/// index.html: first the counts and the summary matrix (a headline figure per cell), then what is
/// not as expected, the speed-accuracy map, a table of contents, and the rest (baseline, known
/// failures, sweeps, engines, errata).
std::string index_html(const SuiteResults& results);
/// scenario-<name>.html: what it checks, the run's settings, every configuration's headline and
/// failing metrics with known-failure reasons, plots, parameters, each configuration's section.
std::string scenario_html(const SuiteResults& results, const std::string& scenario);
/// File name of a scenario's page.
std::string scenario_page(const std::string& scenario);
/// ERRATA.md's Markdown as HTML (md4c, GitHub dialect: pipe tables).
std::string markdown_html(const std::string& md);

}  // namespace liftcheck
