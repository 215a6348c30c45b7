// The two vehicles of the papers: Fecko's car and the two disks of the reactive-collision paper.
// Their names ("car", "disks") are read and written only through to_string and parse_vehicle (and
// the JSON conversions below, which use them): results.json, the protocol, --set, traces.
#pragma once

#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <string_view>

namespace liftcheck {

enum class Vehicle { kCar, kDisks };

/// Every vehicle, in the order the catalogue and the listings show them.
inline constexpr Vehicle kVehicles[] = {Vehicle::kCar, Vehicle::kDisks};

/// "car" or "disks".
inline const char* to_string(Vehicle v) { return v == Vehicle::kCar ? "car" : "disks"; }

/// The vehicle named `name`; nullopt for another name.
inline std::optional<Vehicle> parse_vehicle(std::string_view name) {
  for (Vehicle v : kVehicles)
    if (name == to_string(v)) return v;
  return std::nullopt;
}

/// As results.json and the protocol write it: its name.
inline void to_json(nlohmann::json& j, Vehicle v) { j = to_string(v); }
/// A vehicle's name; anything else is a json type_error (as a wrong type in any field is).
inline void from_json(const nlohmann::json& j, Vehicle& v) {
  const auto parsed = j.is_string() ? parse_vehicle(j.get_ref<const std::string&>()) : std::nullopt;
  if (!parsed) throw nlohmann::json::type_error::create(302, "vehicle must be \"car\" or \"disks\"", &j);
  v = *parsed;
}

}  // namespace liftcheck
