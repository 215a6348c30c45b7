// What `liftcheck diff` and the baseline gate compare of a results file or baseline, and nothing
// more: per run its key, its verdict and, per metric, the error as a fraction of its tolerance. A
// file of a million runs is read into this (input/results_file.cpp: each run decoded and checked
// as the full reader does, then dropped) instead of a document of every field.
#pragma once

#include <map>
#include <memory>
#include <optional>
#include <nlohmann/json.hpp>
#include <string>
#include <unordered_map>
#include <vector>

#include "input/suite_result.hpp"

namespace liftcheck {

/// One metric of a run, as the diff compares it.
struct MetricFigures {
  std::string name;
  double ratio = 0.0;          ///< its error as a fraction of its tolerance (Metric::ratio)
  double error = NAN;          ///< its compared error (NaN: not finite)
  bool informational = false;  ///< not compared
  nlohmann::json measured;     ///< the measured value as written (a number or null), printed as it was
};

/// One run (or sweep point), as the diff compares it.
struct RunFigures {
  std::string scenario, engine;
  std::string point;    ///< a point's key ("sweep/radius_vs_beta/ode/x=0.1"); "" for a run
  std::string verdict;  ///< its verdict
  std::string message;  ///< "" when it has none
  bool as_expected = false;
  std::vector<MetricFigures> metrics;  ///< in name order
  /// Its parameters and settings as one text, key '\x1f' value '\x1e' in key order (a value as
  /// written: a string's text, a number's JSON), shared by the runs made alike (a suite of a
  /// million runs holds a few hundred distinct ones); the diff names those that differ.
  std::shared_ptr<const std::string> settings;
};

/// The distinct settings texts of one file.
using SettingsPool = std::unordered_map<std::string, std::shared_ptr<const std::string>>;

/// `pairs` (key, value) sorted and joined into a settings text, the pool's copy if it has one.
std::shared_ptr<const std::string> interned_settings(std::vector<std::pair<std::string, std::string>> pairs,
                                                     SettingsPool& pool);

/// A run's figures.
RunFigures figures_of(const RunResult& r, SettingsPool& pool);

/// The runs of one file, in the file's order, and its points (a baseline's sweep points and
/// outcome cases) by key.
struct ResultsIndex {
  std::vector<RunFigures> runs;
  std::vector<RunFigures> points;
  std::map<std::string, std::optional<bool>> outcomes;  ///< outcome_case_key -> the case's outcome
};

/// The same figures taken from typed results (the suite just run, a baseline read whole).
ResultsIndex index_of(const SuiteResults& results);

}  // namespace liftcheck
