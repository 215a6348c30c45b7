// Scenario parameters: declared with defaults, units and physical ranges; parsed from KEY=VALUE.
#pragma once

#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <stdexcept>
#include <string>
#include <variant>
#include <vector>

#include <Eigen/Dense>

namespace liftcheck {

/// Bad user input: reported as one line, exit status 2.
struct InputError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

enum class ParamKind { kNumber, kInteger, kVec2, kChoice };

struct ParamSpec {
  std::string key;
  ParamKind kind = ParamKind::kNumber;
  std::string default_text;  ///< parsed like user input
  std::string unit;          ///< SI unit, "rad", "1" for dimensionless, "" for choices
  std::string help;
  double min = -std::numeric_limits<double>::infinity();  ///< numbers: lower bound
  bool min_exclusive = false;
  double max = std::numeric_limits<double>::infinity();
  std::vector<std::string> choices;  ///< kChoice only

  nlohmann::json to_json() const;
};

/// KEY=VALUE overrides, already split.
using Overrides = std::vector<std::pair<std::string, std::string>>;

using ParamValue = std::variant<double, Eigen::Vector2d, std::string>;

/// Effective parameters of one run: every declared key has a value.
class Params {
 public:
  /// Defaults of `specs`, overridden by `overrides` ("KEY=VALUE" already split). Throws InputError.
  static Params resolve(const std::vector<ParamSpec>& specs, const Overrides& overrides, const std::string& scenario);

  double num(const std::string& key) const;
  int integer(const std::string& key) const { return static_cast<int>(num(key)); }
  Eigen::Vector2d vec(const std::string& key) const;
  const std::string& str(const std::string& key) const;
  bool has(const std::string& key) const { return values_.count(key) > 0; }
  /// Every value, by key.
  const std::map<std::string, ParamValue>& values() const { return values_; }
  nlohmann::json to_json() const;
  /// The values to_json wrote, read back as they are (what a worker is sent of a run resolved
  /// before it): nothing is parsed against a spec again. std::invalid_argument on another shape.
  static Params from_json(const nlohmann::json& values);
  bool operator==(const Params& o) const { return values_ == o.values_; }

 private:
  std::map<std::string, ParamValue> values_;
};

/// `text` as a value of `spec`, checked against its kind and range. Throws InputError.
ParamValue parse_param(const ParamSpec& spec, const std::string& text);

/// Splits "KEY=VALUE"; throws InputError naming the argument when there is no '='.
std::pair<std::string, std::string> split_assignment(const std::string& arg);

}  // namespace liftcheck
