#include "engines/analytic/analytic.hpp"
#include "engines/bullet/bullet_car.hpp"
#include "engines/bullet/bullet_multibody.hpp"
#include "engines/bullet/bullet_raycast.hpp"
#include "engines/mujoco/mujoco_engine.hpp"
#include "engines/dart/dart_engine.hpp"
#include "engines/ode/ode_car.hpp"
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
  for (EngineInfo& e : registry())
    if (!e.described) describe_outside(e);
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

Settings EngineInfo::defaults(const std::string& vehicle) const {
  Settings s;
  for (const SettingSpec& k : knobs)
    if (k.vehicle == vehicle) s[k.key] = k.default_text;
  return s;
}

std::string SettingSpec::range_text() const {
  switch (kind) {
    case kInteger: return fmt::format("{:g} to {:g}", min, max);
    case kReal: return fmt::format("{}{:g}, {:g}]", min_exclusive ? "(" : "[", min, max);
    case kChoice: break;
  }
  return fmt::format("{}", fmt::join(choices, " | "));
}

const EngineInfo& reference_engine() {
  for (const EngineInfo& e : engines())
    if (e.is_reference) return e;
  throw std::logic_error("no reference engine registered");
}

const EngineInfo* find_engine(const std::string& name) {
  for (EngineInfo& e : registry())
    if (e.name == name) {
      if (!e.described) describe_outside(e);
      return &e;
    }
  return nullptr;
}

}  // namespace liftcheck
