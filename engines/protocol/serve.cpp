#include "engines/protocol/serve.hpp"

#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstring>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <nlohmann/json.hpp>

#include "engines/driven_disks.hpp"
#include "engines/protocol/child.hpp"
#include "engines/rigid_car.hpp"

namespace liftcheck {

using nlohmann::json;

namespace {

json vec(const Eigen::Vector3d& v) { return json::array({v.x(), v.y(), v.z()}); }
json vec(const disks::Vec2& v) { return json::array({v.x(), v.y()}); }
disks::Vec2 vec2(const json& j) { return {j.at(0).get<double>(), j.at(1).get<double>()}; }

/// Every number in `j` finite (the protocol has no NaN).
bool all_finite(const json& j) {
  if (j.is_number_float()) return std::isfinite(j.get<double>());
  if (j.is_structured())
    for (const auto& v : j)
      if (!all_finite(v)) return false;
  return true;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

}  // namespace

/// One compiled-in configuration behind the protocol: the requests call the hooks a RigidCar or
/// a DrivenDisks implements (build, actuate, step, read), the same calls the in-process loops make.
class ProtocolServer {
 public:
  explicit ProtocolServer(const EngineInfo& e) : e_(e) {}

  json handle(const json& req) {
    const std::string op = req.at("op").get<std::string>();
    if (op == "hello") return hello(req);
    if (op == "car") return car(req);
    if (op == "disks") return disks(req);
    if (op == "step")
      return car_ ? car_step(req) : disks_ ? disk_step(req) : throw EngineError("'step' before 'car' or 'disks'");
    throw EngineError(fmt::format("unknown op '{}'", op));
  }

 private:
  json hello(const json& req) const {
    if (req.at("protocol") != kProtocolVersion)
      throw EngineError(
          fmt::format("protocol {} asked, this server speaks {}", req.at("protocol").dump(), kProtocolVersion));
    json vehicles = json::array(), settings = json::array(), fixed = json::array();
    if (e_.make_car) vehicles.push_back("car");
    if (e_.make_disks) vehicles.push_back("disks");
    for (const SettingSpec& k : e_.knobs) {
      json j{{"key", k.key},
             {"vehicle", k.vehicle},
             {"default", k.default_text},
             {"help", k.help},
             {"kind", k.kind_name()}};
      if (k.numeric())
        j["min"] = k.min, j["max"] = k.max, j["min_exclusive"] = k.min_exclusive;
      else
        j["choices"] = k.choices;
      settings.push_back(j);
    }
    for (const auto& [k, v] : e_.settings) fixed.push_back({k, v});
    return {{"protocol", kProtocolVersion}, {"engine", e_.library}, {"version", e_.version},
            {"precision", e_.precision},    {"vehicles", vehicles}, {"four_wheels", e_.four_wheels},
            {"brakes", e_.brakes},          {"settings", settings}, {"fixed", fixed}};
  }

  /// The request's settings, every knob of `vehicle` present (its default where not given).
  Settings settings(const json& req, Vehicle vehicle) const {
    const Settings defaults = e_.defaults(vehicle);
    Overrides given;
    for (const auto& [k, v] : req.at("settings").items()) {
      if (!defaults.has(k))
        throw EngineError(fmt::format("'{}' has no setting '{}' for {}", e_.name, k, to_string(vehicle)));
      given.emplace_back(k, v.get<std::string>());
    }
    try {
      return resolve_settings(e_, vehicle, given, e_.name);
    } catch (const InputError& e) {
      throw EngineError(e.what());
    }
  }

  json car(const json& req) {
    disks_holder_.reset(), disks_ = nullptr, car_holder_.reset(), car_ = nullptr;
    auto engine = e_.make_car(settings(req, Vehicle::kCar));
    car_ = dynamic_cast<RigidCar*>(engine.get());
    if (!car_) throw EngineError(fmt::format("'{}' is not a rigid-body car: it cannot be served", e_.name));
    car_holder_ = std::move(engine);
    const json& c = req.at("car");
    CarSetup setup;
    setup.car.R_m = c.at("R_m"), setup.car.l_m = c.at("l_m");
    setup.dt_s = req.at("dt_s"), setup.mu = req.at("mu");
    // Engines read gravity as gravity_W(): the request's vector itself, not a renormalised one.
    setup.gravity_mps2 = 1.0;
    setup.gravity_dir_W =
        Eigen::Vector3d(req.at("gravity_W").at(0), req.at("gravity_W").at(1), req.at("gravity_W").at(2));
    setup.wheels = c.at("wheels"), setup.track_m = c.at("track_m"), setup.parallel_steering = c.at("parallel_steering");
    const json& q = req.at("q0");
    const car::Config q0{0.0, q.at("beta_rad"), q.at("x_m"), q.at("y_m"), q.at("phi_rad")};
    // The request's motor limits (docs/protocol.md), not ones derived again from this setup's unit
    // gravity, in place before the engine builds (MuJoCo writes them into its model).
    ServoDef servo = ServoDef::for_car(setup, TricycleDef::from(setup));
    servo.spin_torque_max_Nm = req.at("servo").at("spin_torque_max_Nm");
    servo.steer_torque_max_Nm = req.at("servo").at("steer_torque_max_Nm");
    servo.rear_brake_torque_max_Nm = req.at("servo").value("rear_brake_torque_max_Nm", 0.0);
    setup.rear_brake = servo.rear_brake_torque_max_Nm > 0.0;
    car_->reset_with(setup, q0, servo);
    return car_state();
  }

  json car_state() const {
    const RigidCarState s = car_->read();
    json wheels = json::array();
    for (int k = 0; k < (car_->def_.wheels == 4 ? 4 : 3); ++k) {
      const WheelState& w = s.wheels[k];
      wheels.push_back({{"v_hub_W", vec(w.v_hub_W)},
                        {"omega_W", vec(w.omega_W)},
                        {"axle_W", vec(w.axle_W)},
                        {"hub_z_m", w.hub_z_m}});
    }
    return {{"spin_joint_rad", {s.spin_joint_rad[0], s.spin_joint_rad[1]}},
            {"steer_rad", {s.steer_rad[0], s.steer_rad[1]}},
            {"x_m", s.x_m},
            {"y_m", s.y_m},
            {"z_m", s.z_m},
            {"phi_rad", s.phi_rad},
            {"rear_z_m", s.rear_z_m},
            {"wheels", wheels}};
  }

  json car_step(const json& req) {
    FrontRates rates;
    for (size_t k = 0; k < 2; ++k) {
      rates.spin_radps[k] = req.at("spin_radps").at(k);
      rates.steer_radps[k] = req.at("steer_radps").at(k);
    }
    const double dt = req.at("dt_s");
    const auto t0 = std::chrono::steady_clock::now();
    car_->actuate(rates, car_->servo_);
    car_->step(dt);
    const double engine_s = seconds_since(t0);
    json r = car_state();
    r["engine_s"] = engine_s;
    if (const std::optional<Eigen::Vector3d> f = car_->ground_force_W()) r["ground_force_W"] = vec(*f);
    if (const Eigen::Vector3d v = car_->read().v_chassis_W; v.allFinite()) r["v_chassis_W"] = vec(v);
    return r;
  }

  json disks(const json& req) {
    disks_holder_.reset(), disks_ = nullptr, car_holder_.reset(), car_ = nullptr;
    auto engine = e_.make_disks(settings(req, Vehicle::kDisks));
    disks_ = dynamic_cast<DrivenDisks*>(engine.get());
    if (!disks_) throw EngineError(fmt::format("'{}' has no stepped disks: they cannot be served", e_.name));
    disks_holder_ = std::move(engine);
    DiskSetup setup;
    setup.radius_m = req.at("radius_m"), setup.dt_s = req.at("dt_s"), setup.mu_MN = req.at("mu_MN");
    if (!(setup.mu_MN >= 0.0)) throw EngineError("disks request.mu_MN must be a number >= 0");
    disks_->build(setup, vec2(req.at("cM0")), vec2(req.at("cN0")));
    const DrivenDisks::State s = disks_->read();
    return {{"cM", vec(s.cM)}, {"cN", vec(s.cN)}};
  }

  json disk_step(const json& req) {
    const auto t0 = std::chrono::steady_clock::now();
    const DrivenDisks::StepContacts c =
        disks_->step(vec2(req.at("vM_cmd")), vec2(req.at("cN_next")), vec2(req.at("vN")), req.at("dt_s"));
    const double engine_s = seconds_since(t0);
    const DrivenDisks::State s = disks_->read();
    json contacts{{"count", c.count}};
    if (c.count > 0)
      contacts["depth_max_m"] = c.depth_max_m,
      contacts["distance_min_m"] = std::isnan(c.distance_min_m) ? -c.depth_max_m : c.distance_min_m;
    return {
        {"engine_s", engine_s}, {"cM", vec(s.cM)}, {"cN", vec(s.cN)}, {"wM", vec(s.wM_radps)}, {"contacts", contacts}};
  }

  const EngineInfo& e_;
  std::unique_ptr<CarEngine> car_holder_;
  RigidCar* car_ = nullptr;
  std::unique_ptr<DiskEngine> disks_holder_;
  DrivenDisks* disks_ = nullptr;
};

/// One reply line written whole to `fd`; false with errno set when it cannot be.
bool write_reply(int fd, const std::string& text) {
  for (size_t done = 0; done < text.size();) {
    const ssize_t put = ::write(fd, text.data() + done, text.size() - done);
    if (put < 0 && errno == EINTR) continue;
    if (put <= 0) {
      if (put == 0) errno = EIO;
      return false;
    }
    done += static_cast<size_t>(put);
  }
  return true;
}

/// The reply to one request line: its number ("id") echoed, {"ok": false, "error": ...} for
/// anything the server or the engine refuses. Empty after "bye".
std::string reply_to(ProtocolServer& server, const std::string& line, bool& bye) {
  json reply, id;
  try {
    const json req = json::parse(line);
    if (req.is_object() && req.contains("id")) id = req["id"];
    if (req.value("op", "") == "bye") {
      bye = true;
      reply = json::object();
    } else {
      reply = server.handle(req);
      if (!all_finite(reply)) throw EngineError("the engine's state is not finite");
    }
    reply["ok"] = true;
  } catch (const std::exception& err) {
    std::string why = err.what();
    for (char& ch : why)
      if (ch == '\n' || ch == '\r') ch = ' ';
    reply = {{"ok", false}, {"error", why}};
  }
  if (!id.is_null()) reply["id"] = id;
  return reply.dump(-1, ' ', false, json::error_handler_t::replace) + "\n";
}

int serve_main(const std::string& config) {
  const EngineInfo* e = nullptr;
  for (const EngineInfo& x : engines())
    if (x.name == config && !x.is_outside()) e = &x;
  if (!e || e->is_reference) {
    std::cerr << fmt::format(
        "liftcheck: error: serve: '{}' is not a compiled-in rigid-body configuration (see 'liftcheck engines')\n",
        config);
    return 2;
  }
  // Replies go to the original standard output; anything an engine prints there goes to stderr.
  const int replies_fd = ::dup(STDOUT_FILENO);
  ::dup2(STDERR_FILENO, STDOUT_FILENO);
  ProtocolServer server(*e);
  // Requests are read from a buffer filled in large reads, not a character at a time through stdio.
  std::ios::sync_with_stdio(false);
  std::string line;
  line.reserve(4096);
  while (std::getline(std::cin, line)) {
    if (line.size() > kProtocolLineMax) {
      std::cerr << "liftcheck: error: serve: a request line longer than 1 MiB\n";
      return 2;
    }
    bool bye = false;
    if (!write_reply(replies_fd, reply_to(server, line, bye))) {
      std::cerr << fmt::format("liftcheck: error: cannot write to standard output: {}\n", std::strerror(errno));
      return 2;
    }
    if (bye) return 0;
  }
  return 0;
}

}  // namespace liftcheck
