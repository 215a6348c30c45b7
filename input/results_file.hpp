// results.json and baselines read back (`report`, `merge`, `diff`, `validate --baseline`), and the
// compaction results.json is written in. A file is decoded once, strictly
// (input/results_codec.hpp): a malformed or inconsistent file stops with one line naming the file,
// the run and the field, and never reaches a reader.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>

#include "input/results_index.hpp"
#include "input/suite_result.hpp"

namespace liftcheck {

/// Reads and decodes a results file, a shard's or a baseline; InputError "FILE: runs[3].metrics.
/// radius: missing 'rel_error' (car.circle on ode)" and the like.
SuiteResults read_results(const std::string& path);
/// The same on text already read; `name` names it in errors.
SuiteResults parse_results(const std::string& text, const std::string& name);

/// results.json's text for `results`: the runs' details.reference traces kept once each
/// ("shared_references"; the exact lift is the same for every configuration of a scenario).
std::string results_text(const SuiteResults& results);
/// The shared references of a document put back in its runs (parse_results does it).
void expand_references(nlohmann::json& doc, const std::string& name);

/// The traces a run keeps for drawing (details.trace, details.reference, each of details.runs'
/// trace, details.after_contact.reference), thinned to at most kDrawnRows rows and their last,
/// every number to 9 significant digits (10 nm at 10 m). The metrics are measured before, on the
/// engine's full trace; `run --json` keeps the trace as the scenario recorded it.
inline constexpr std::size_t kDrawnRows = 100;
void thin_drawn_traces(nlohmann::json& details);

/// Reads a results or baseline file into what the diff compares, with every check of the full
/// reader (the same records are decoded and checked), without keeping a document of it: each run is
/// built, decoded and dropped in turn.
ResultsIndex read_results_index(const std::string& path);
/// Both files of a diff, each read in a thread of its own; the first file's error is reported when
/// both have one.
std::pair<ResultsIndex, ResultsIndex> read_results_index_pair(const std::string& base, const std::string& head);
/// The index of text already read; `name` names it in errors.
ResultsIndex parse_results_index(std::string_view text, const std::string& name);

}  // namespace liftcheck
