// The numbers of the engine protocol's requests and replies (docs/protocol.md) as liftcheck writes
// and reads them: settings and vectors as JSON, a step request's numbers, a car reply's state read
// from its JSON tree or from the slots of the fast path (FlatReply).
#include <cmath>
#include <fmt/format.h>
#include <iterator>

#include "engines/protocol/outside_internal.hpp"

namespace liftcheck::protocol_detail {

json settings_json(const Settings& s) {
  json j = json::object();
  for (const auto& [k, v] : s.exact_texts()) j[k] = v;
  return j;
}

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
json vec(const disks::Vec2& v) { return json::array({v.x(), v.y()}); }
Eigen::Vector3d vec3(ProtocolChild& c, const json& j, const char* key, const char* where) {
  const std::vector<double> v = c.numbers(j, key, 3, where);
  return {v[0], v[1], v[2]};
}

RigidCarState car_state(ProtocolChild& c, const json& r, int wheels) {
  RigidCarState s{};
  const std::vector<double> spin = c.numbers(r, "spin_joint_rad", 0), steer = c.numbers(r, "steer_rad", 0);
  const size_t n_front = wheels == 4 ? 2 : 1;
  if (spin.size() < n_front || steer.size() < n_front)
    c.fail(fmt::format("'spin_joint_rad' and 'steer_rad' need {} entries for a {}-wheel car", n_front, wheels));
  for (size_t k = 0; k < 2; ++k) {
    s.spin_joint_rad[k] = k < spin.size() ? spin[k] : 0.0;
    s.steer_rad[k] = k < steer.size() ? steer[k] : 0.0;
  }
  s.x_m = c.number(r, "x_m"), s.y_m = c.number(r, "y_m"), s.z_m = c.number(r, "z_m");
  s.phi_rad = c.number(r, "phi_rad"), s.rear_z_m = c.number(r, "rear_z_m");
  const auto w = r.find("wheels");
  if (w == r.end() || !w->is_array() || w->size() != static_cast<size_t>(wheels))
    c.fail(fmt::format("'wheels' must be an array of the {} wheels' states", wheels));
  for (int k = 0; k < wheels; ++k) {
    const json& ws = (*w)[static_cast<size_t>(k)];
    if (!ws.is_object()) c.fail(fmt::format("wheels[{}] is not an object", k));
    const std::string where = fmt::format("wheels[{}].", k);
    s.wheels[k].v_hub_W = vec3(c, ws, "v_hub_W", where.c_str());
    s.wheels[k].omega_W = vec3(c, ws, "omega_W", where.c_str());
    s.wheels[k].axle_W = vec3(c, ws, "axle_W", where.c_str());
    s.wheels[k].hub_z_m = c.number(ws, "hub_z_m", where.c_str());
  }
  if (r.contains("v_chassis_W")) s.v_chassis_W = vec3(c, r, "v_chassis_W", "");
  return s;
}

double engine_seconds(ProtocolChild& c, const json& r) {
  const double s = c.number(r, "engine_s");
  if (s < 0.0) c.fail("'engine_s' is negative");
  return s;
}

void put(std::string& out, double v) {
  if (!std::isfinite(v)) throw EngineError("a step request with a non-finite number (the protocol has no NaN)");
  fmt::format_to(std::back_inserter(out), "{}", v);
}

std::vector<FlatReply::Slot> car_slots(int wheels) {
  const bool four = wheels == 4;
  std::vector<FlatReply::Slot> s{{"engine_s"},
                                 {"spin_joint_rad/0"},
                                 {"spin_joint_rad/1", four},
                                 {"steer_rad/0"},
                                 {"steer_rad/1", four},
                                 {"x_m"},
                                 {"y_m"},
                                 {"z_m"},
                                 {"phi_rad"},
                                 {"rear_z_m"}};
  for (int k = 0; k < wheels; ++k) {
    for (const char* v : {"v_hub_W", "omega_W", "axle_W"})
      for (int i = 0; i < 3; ++i) s.push_back({fmt::format("wheels/{}/{}/{}", k, v, i)});
    s.push_back({fmt::format("wheels/{}/hub_z_m", k)});
  }
  s.push_back({"id", true, true});  // the request's number (car_id_slot)
  for (int i = 0; i < 3; ++i) s.push_back({fmt::format("ground_force_W/{}", i), false});  // optional, after it
  for (int i = 0; i < 3; ++i) s.push_back({fmt::format("v_chassis_W/{}", i), false});     // optional
  s.push_back({"applied/0", false});  // a planned step's rates applied (spin, steering): optional
  s.push_back({"applied/1", false});
  return s;
}

size_t car_id_slot(int wheels) { return 10 + 10 * static_cast<size_t>(wheels); }

RigidCarState car_state_of(const FlatReply& f, int wheels) {
  RigidCarState s{};
  s.spin_joint_rad[0] = f.value(1), s.spin_joint_rad[1] = f.value(2), s.steer_rad[0] = f.value(3),
  s.steer_rad[1] = f.value(4);
  s.x_m = f.value(5), s.y_m = f.value(6), s.z_m = f.value(7), s.phi_rad = f.value(8), s.rear_z_m = f.value(9);
  size_t i = 10;
  for (int k = 0; k < wheels; ++k, i += 10) {
    s.wheels[k].v_hub_W = {f.value(i), f.value(i + 1), f.value(i + 2)};
    s.wheels[k].omega_W = {f.value(i + 3), f.value(i + 4), f.value(i + 5)};
    s.wheels[k].axle_W = {f.value(i + 6), f.value(i + 7), f.value(i + 8)};
    s.wheels[k].hub_z_m = f.value(i + 9);
  }
  return s;
}

}  // namespace liftcheck::protocol_detail
