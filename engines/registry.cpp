#include "engines/analytic/analytic.hpp"
#include "engines/bullet/bullet_car.hpp"
#include "engines/bullet/bullet_multibody.hpp"
#include "engines/bullet/bullet_raycast.hpp"
#include "engines/mujoco/mujoco_engine.hpp"
#include "engines/dart/dart_engine.hpp"
#include "engines/ode/ode_car.hpp"
#include "engines/engine.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

namespace liftcheck {

const std::vector<EngineInfo>& engines() {
  static const std::vector<EngineInfo> all = [] {
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
  }();
  return all;
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
  for (const EngineInfo& e : engines())
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace liftcheck
