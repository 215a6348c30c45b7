// "Did you mean": the nearest valid name to a mistyped one, by edit distance.
#pragma once

#include <string>
#include <vector>

namespace liftcheck {

/// Optimal string alignment distance (Levenshtein with adjacent transpositions), case-sensitive;
/// beyond 256 characters an upper bound (the rest of each name counted as edits).
std::size_t edit_distance(const std::string& a, const std::string& b);

/// The candidate nearest to `name`, if it is near enough to be a typo (distance at most a third of
/// the longer name, and at least 1; a candidate that differs only in case always counts); else,
/// for a name without a dot, the candidate whose part after its last dot is that name or within a
/// third of its length ("circle", "circel" for "car.circle"); "" if none.
std::string nearest_name(const std::string& name, const std::vector<std::string>& candidates);

/// "; did you mean 'X'?" for the nearest candidate, or "" when none is near.
std::string did_you_mean(const std::string& name, const std::vector<std::string>& candidates);

}  // namespace liftcheck
