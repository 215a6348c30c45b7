// What `liftcheck diff` reads of a results file or baseline, and nothing more: per run its key, its
// verdict and, per metric, the error as a fraction of its tolerance. A file of a million runs is
// read into this (input/results_file.cpp, with every check of the full reader) instead of a
// document of every field: a tenth of the memory and of the time.
#pragma once

#include <nlohmann/json.hpp>
#include <memory>
#include <string>
#include <unordered_map>
#include <vector>

namespace liftcheck {

/// One metric of a run, as the diff compares it.
struct MetricFigures {
  std::string name;
  double ratio = 0.0;          ///< its error as a fraction of its tolerance (MetricView::ratio)
  bool informational = false;  ///< not compared
  nlohmann::json measured;     ///< the measured value as written (a number or null), printed as it was
};

/// One run, as the diff compares it.
struct RunFigures {
  std::string scenario, engine;
  std::string verdict;  ///< its verdict, or its status in files written before verdicts
  std::string message;  ///< "" when it has none
  bool as_expected = false;
  bool has_metrics = false;            ///< a "metrics" object (an empty one included)
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

/// The runs of one file, in the file's order (a later record of the same run wins).
struct ResultsIndex {
  std::vector<RunFigures> runs;
};

/// The same figures taken from a document (a results file in memory, a baseline read whole).
ResultsIndex index_of(const nlohmann::json& results);

}  // namespace liftcheck
