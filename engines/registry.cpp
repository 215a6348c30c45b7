#include "engines/analytic/analytic.hpp"
#include "engines/bullet/bullet_car.hpp"
#include "engines/bullet/bullet_multibody.hpp"
#include "engines/bullet/bullet_raycast.hpp"
#include "engines/mujoco/mujoco_engine.hpp"
#include "engines/dart/dart_engine.hpp"
#include "engines/ode/ode_car.hpp"
#include "engines/simbody/simbody_engine.hpp"
#include "engines/engine.hpp"
#include "engines/protocol/outside.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace liftcheck {

namespace {

std::vector<std::string> g_registration_problems;

std::vector<EngineInfo> compiled_in() {
  std::vector<EngineInfo> v;
  v.push_back(analytic_engine());
  v.push_back(ode_engine());
  v.push_back(ode_quick_engine());
  v.push_back(bullet_engine());
  v.push_back(bullet_multibody_engine());
  v.push_back(bullet_raycast_engine());
  v.push_back(mujoco_engine());
  v.push_back(mujoco_noslip_engine());
  v.push_back(mujoco_stiff_engine());
  v.push_back(dart_engine());
  v.push_back(dart_primitive_engine());
  v.push_back(simbody_engine());
  return v;
}

/// The entries stay where they are (never resized after it is built): an outside entry is
/// described in place.
std::vector<EngineInfo>& registry() {
  static std::vector<EngineInfo> all = [] {
    std::vector<EngineInfo> v = compiled_in();
    std::vector<std::string> names;
    for (const EngineInfo& e : v) names.push_back(e.name);
    for (EngineInfo& e : outside_engines(names, g_registration_problems)) v.push_back(std::move(e));
    return v;
  }();
  return all;
}

}  // namespace

const std::vector<EngineInfo>& engines() { return registry(); }

const std::vector<EngineInfo>& described_engines() {
  std::vector<EngineInfo*> todo;
  for (EngineInfo& e : registry())
    if (!e.outside.described) todo.push_back(&e);
  describe_outside_all(todo);
  return registry();
}

const std::vector<std::string>& registration_problems() {
  (void)registry();
  return g_registration_problems;
}

double bookkeeping_factor(const std::string& precision) {
  // float32 stores a coordinate with a relative rounding error of up to 2^-24 = 6e-8, 6e-7 m at
  // the 10 m from the origin the disk scenarios reach; an engine rounds N's pose a few times per
  // step (its kinematic target, its integration, its transform), so 1e-9 m (the float64 floor)
  // becomes 1e-5 m: about 16 such roundings at 10 m. Physics tolerances do not change.
  return precision == "float32" ? 1e4 : 1.0;
}

Settings EngineInfo::defaults(Vehicle vehicle) const { return resolve_settings(*this, vehicle, {}, name); }

Settings resolve_settings(const EngineInfo& engine, Vehicle vehicle, const Overrides& overrides,
                          const std::string& scenario) {
  std::vector<ParamSpec> specs;
  for (const SettingSpec& k : engine.knobs)
    if (k.vehicle == vehicle) specs.push_back(k);
  const Params resolved = Params::resolve(specs, overrides, scenario);
  Settings s;
  for (const auto& [key, value] : resolved.values())
    if (const double* d = std::get_if<double>(&value))
      s[key] = *d;
    else
      s[key] = std::get<std::string>(value);
  return s;
}

std::string Settings::at(const std::string& key) const {
  const Value& v = values_.at(key);
  if (const double* d = std::get_if<double>(&v)) return fmt::format("{:g}", *d);
  return std::get<std::string>(v);
}

std::map<std::string, std::string> Settings::texts() const {
  std::map<std::string, std::string> out;
  for (const auto& [key, value] : values_) out[key] = at(key);
  return out;
}

std::map<std::string, std::string> Settings::exact_texts() const {
  std::map<std::string, std::string> out;
  for (const auto& [key, value] : values_)
    out[key] = std::holds_alternative<double>(value) ? fmt::format("{}", std::get<double>(value)) : at(key);
  return out;
}

nlohmann::json Settings::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [key, value] : values_) {
    if (const double* d = std::get_if<double>(&value))
      j[key] = *d;
    else
      j[key] = std::get<std::string>(value);
  }
  return j;
}

Settings Settings::from_json(const nlohmann::json& values) {
  Settings s;
  for (const auto& [key, v] : values.items()) {
    if (v.is_number())
      s.values_[key] = v.get<double>();
    else if (v.is_string())
      s.values_[key] = v.get<std::string>();
    else
      throw std::invalid_argument("setting '" + key + "': neither a number nor a choice");
  }
  return s;
}

std::string SettingSpec::range_text() const {
  switch (kind) {
    case ParamKind::kInteger:
      return fmt::format("{:g} to {:g}", min, max);
    case ParamKind::kNumber:
      return fmt::format("{}{:g}, {:g}]", min_exclusive ? "(" : "[", min, max);
    default:
      break;
  }
  return fmt::format("{}", fmt::join(choices, " | "));
}

const char* SettingSpec::kind_name() const {
  return kind == ParamKind::kInteger ? "integer" : kind == ParamKind::kNumber ? "real" : "choice";
}

std::optional<ParamKind> setting_kind_named(const std::string& name) {
  if (name == "integer") return ParamKind::kInteger;
  if (name == "real") return ParamKind::kNumber;
  if (name == "choice") return ParamKind::kChoice;
  return std::nullopt;
}

const EngineInfo& reference_engine() {
  for (const EngineInfo& e : engines())
    if (e.is_reference) return e;
  throw std::logic_error("no reference engine registered");
}

const EngineInfo* find_engine(const std::string& name) {
  for (EngineInfo& e : registry())
    if (e.name == name) {
      if (!e.outside.described) describe_outside(e);
      return &e;
    }
  return nullptr;
}

}  // namespace liftcheck
