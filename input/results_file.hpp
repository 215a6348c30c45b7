// results.json and baselines read back (`diff`, `validate --baseline`): every field that
// diff_results (reports/ci.cpp) reads is checked here for presence and type, so that a malformed
// file stops with one line naming the file, the field and the problem, and never reaches the diff.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <string_view>
#include <utility>

#include "input/results_index.hpp"

namespace liftcheck {

/// Reads and checks a results or baseline file; InputError "FILE: runs[3].metrics.radius: missing
/// 'rel_error'" and the like.
nlohmann::json read_results(const std::string& path);

/// The runs' details.reference traces kept once each: results["shared_references"] holds every
/// distinct one and a run's reference becomes {"shared": k} (the exact lift is the same for every
/// configuration of a scenario: 19 traces for 467 runs). expand_references undoes it; read_results
/// expands what it reads, so only results.json on disk holds the shared form.
void share_references(nlohmann::json& results);
void expand_references(nlohmann::json& results, const std::string& name);

/// The traces results.json keeps for drawing (details.trace, details.reference, each of
/// details.runs' trace, details.after_contact.reference), thinned to at most kDrawnRows rows and
/// their last, every number to 9 significant digits (10 nm at 10 m). The metrics are measured
/// before, on the engine's full trace; `run --json` keeps the trace as the scenario recorded it.
inline constexpr std::size_t kDrawnRows = 100;
void thin_drawn_traces(nlohmann::json& results);

/// Both files of a diff, read and checked at once (each in a thread of its own); the first
/// file's error is reported when both have one.
std::pair<nlohmann::json, nlohmann::json> read_results_pair(const std::string& base, const std::string& head);

/// Reads and checks a results or baseline file as read_results does (the same checks, the same
/// messages), keeping only what the diff compares: no document is built.
ResultsIndex read_results_index(const std::string& path);

/// Both files of a diff, as read_results_pair reads them, into their indexes.
std::pair<ResultsIndex, ResultsIndex> read_results_index_pair(const std::string& base, const std::string& head);

/// The index of text already read; `name` names it in errors.
ResultsIndex parse_results_index(std::string_view text, const std::string& name);

/// The same on text already read; `name` names it in errors.
nlohmann::json parse_results(const std::string& text, const std::string& name);

/// Checks a parsed results or baseline document; InputError naming `name` and the field.
void check_results(const nlohmann::json& results, const std::string& name);

}  // namespace liftcheck
