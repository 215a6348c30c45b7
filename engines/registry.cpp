#include "engines/analytic/analytic.hpp"
#include "engines/bullet/bullet_car.hpp"
#include "engines/ode/ode_car.hpp"
#include "engines/engine.hpp"

namespace liftcheck {

const std::vector<EngineInfo>& engines() {
  static const std::vector<EngineInfo> all = [] {
    std::vector<EngineInfo> v;
    v.push_back(analytic_engine());
    v.push_back(bullet_engine());
    v.push_back(ode_engine());
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

const EngineInfo* find_engine(const std::string& name) {
  for (const EngineInfo& e : engines())
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace liftcheck
