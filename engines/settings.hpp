// The settings an engine declares and a run resolves: SettingSpec (a ParamSpec with the vehicle
// it applies to and its role) and the typed values of one run (Settings).
#pragma once

#include <map>
#include <optional>
#include <string>
#include <variant>

#include "input/params.hpp"
#include "input/vehicle.hpp"

namespace liftcheck {

/// What a setting is for, where the harness or a check needs to know it, whatever the engine calls
/// it: the solver's iteration count (the speed-accuracy map sweeps it on every configuration that
/// has one), a velocity damping the engine applies by default (the gravity check turns it off to
/// see gravity alone).
enum class SettingRole { kNone, kSolverIterations, kDamping };

/// A setting only some engines have (solver iterations, wheel shape, friction directions):
/// declared, typed and ranged by the engine that has it as a scenario parameter is (ParamSpec: the
/// one spec type), set with --set like a parameter, echoed in the record as applied, rejected for
/// an engine that does not declare it.
struct SettingSpec : ParamSpec {
  Vehicle vehicle = Vehicle::kCar;  ///< the vehicle it applies to
  SettingRole role = SettingRole::kNone;

  bool numeric() const { return kind != ParamKind::kChoice; }
  /// "1 to 10000", "(0, 2]" or "a | b": the range as a user reads it.
  std::string range_text() const;
  /// "integer", "real" or "choice": the kind as the protocol and results.json name it.
  const char* kind_name() const;
};
/// The kind named by kind_name(); nullopt for another name.
std::optional<ParamKind> setting_kind_named(const std::string& name);

/// Validated setting values by key, typed by their specs (a number or a choice), every declared
/// setting of the engine's vehicle present (resolve_settings makes them).
class Settings {
 public:
  using Value = std::variant<double, std::string>;
  double number(const std::string& key) const { return std::get<double>(values_.at(key)); }
  int integer(const std::string& key) const { return static_cast<int>(number(key)); }
  const std::string& choice(const std::string& key) const { return std::get<std::string>(values_.at(key)); }
  bool has(const std::string& key) const { return values_.count(key) > 0; }
  /// The value as the record and the protocol show it: a choice, or a number as "{:g}".
  std::string at(const std::string& key) const;
  Value& operator[](const std::string& key) { return values_[key]; }
  /// Every value as at() shows it, by key.
  std::map<std::string, std::string> texts() const;
  /// As texts(), each number in the shortest text that reads back as the same double (what an
  /// outside engine is sent, and what tells two runs apart): "{:g}" keeps six digits only.
  std::map<std::string, std::string> exact_texts() const;
  bool operator==(const Settings&) const = default;
  /// Every value as it is (numbers as numbers, unrounded), and read back: what a worker is sent
  /// of a run resolved before it. std::invalid_argument on another shape.
  nlohmann::json to_json() const;
  static Settings from_json(const nlohmann::json& values);

 private:
  std::map<std::string, Value> values_;
};

}  // namespace liftcheck
