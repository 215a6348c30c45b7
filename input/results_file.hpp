// results.json and baselines read back (`diff`, `validate --baseline`): every field that
// diff_results (reports/ci.cpp) reads is checked here for presence and type, so that a malformed
// file stops with one line naming the file, the field and the problem, and never reaches the diff.
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <utility>

namespace liftcheck {

/// Reads and checks a results or baseline file; InputError "FILE: runs[3].metrics.radius: missing
/// 'rel_error'" and the like.
nlohmann::json read_results(const std::string& path);

/// Both files of a diff, read and checked at once (each in a thread of its own); the first
/// file's error is reported when both have one.
std::pair<nlohmann::json, nlohmann::json> read_results_pair(const std::string& base, const std::string& head);

/// The same on text already read; `name` names it in errors.
nlohmann::json parse_results(const std::string& text, const std::string& name);

/// Checks a parsed results or baseline document; InputError naming `name` and the field.
void check_results(const nlohmann::json& results, const std::string& name);

}  // namespace liftcheck
