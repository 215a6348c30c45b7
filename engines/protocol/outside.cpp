#include "engines/protocol/outside.hpp"

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <nlohmann/json.hpp>
#include <set>
#include <sstream>
#include <system_error>
#include <thread>

#include "engines/driven_disks.hpp"
#include "engines/protocol/child.hpp"
#include "engines/protocol/flat_reply.hpp"
#include "engines/rigid_car.hpp"
#include "input/interrupt.hpp"
#include "input/params.hpp"  // InputError
#include "input/read_file.hpp"
#include "input/trace.hpp"  // parse_json_text, printable

#ifndef LIFTCHECK_OUTSIDE_DIR
#define LIFTCHECK_OUTSIDE_DIR "engines/outside"
#endif

namespace liftcheck {

using nlohmann::json;

namespace {

std::atomic<double> g_timeout_s{100.5};  // set_protocol_timeout(120), the default --timeout

/// An outside configuration's command and its idle child processes (one serves many runs).
struct Outside {
  std::string name;
  std::vector<std::string> argv;
  std::string cwd;  ///< the registration's folder: relative paths in the command resolve there
  bool four_wheels = false;
  std::string precision = "float64";
  std::string contact_forces;  ///< its hello's "contact forces" fact, if it declares one
  bool servo_steps = false;    ///< its hello's "servo_steps": it answers "steps" (docs/protocol.md)
  std::mutex m;
  std::vector<std::unique_ptr<ProtocolChild>> idle;
};

std::mutex g_all_m;
std::vector<std::weak_ptr<Outside>> g_all;  ///< for close_idle_children

double now_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// The hello of a child just started: the protocol version must be liftcheck's.
json hello(ProtocolChild& c, double deadline_s) {
  json r = c.call({{"op", "hello"}, {"protocol", kProtocolVersion}}, std::max(0.05, deadline_s - now_s()));
  const auto p = r.find("protocol");
  if (p == r.end() || !p->is_number_integer() || p->get<long>() != kProtocolVersion)
    c.fail(fmt::format("speaks protocol {}, liftcheck speaks {}", p == r.end() ? "(none given)" : p->dump(),
                       kProtocolVersion));
  return r;
}

std::unique_ptr<ProtocolChild> start(Outside& o) { return std::make_unique<ProtocolChild>(o.name, o.argv, o.cwd); }

/// A child for one engine object: an idle one, or a new one past its hello.
std::unique_ptr<ProtocolChild> take(Outside& o, double deadline_s) {
  {
    std::lock_guard<std::mutex> lock(o.m);
    while (!o.idle.empty()) {
      std::unique_ptr<ProtocolChild> c = std::move(o.idle.back());
      o.idle.pop_back();
      if (c->idle_and_clean()) return c;  // one that sent a line between runs is ended
    }
  }
  std::unique_ptr<ProtocolChild> c = start(o);
  hello(*c, deadline_s);
  return c;
}

void give_back(Outside& o, std::unique_ptr<ProtocolChild> c) {
  if (!c || !c->idle_and_clean()) return;  // a line after its run's last reply: not for the next run
  std::lock_guard<std::mutex> lock(o.m);
  o.idle.push_back(std::move(c));
}

/// The child an engine object uses for its run, back to the idle ones when it is done. Every
/// reply must come before the run's deadline (protocol_timeout_s from the engine object's making).
class Lease {
 public:
  explicit Lease(std::shared_ptr<Outside> o) : o_(std::move(o)), deadline_s_(now_s() + protocol_timeout_s()) {}
  ~Lease() { give_back(*o_, std::move(child_)); }
  ProtocolChild& get() {
    if (!child_ || !child_->healthy()) child_ = take(*o_, deadline_s_);
    return *child_;
  }
  json call(const json& request) {
    ProtocolChild& c = get();
    return c.call(request, std::max(0.05, deadline_s_ - now_s()));
  }
  const Outside& outside() const { return *o_; }
  double seconds_left() const { return std::max(0.05, deadline_s_ - now_s()); }
  /// The child of the request in flight (no new one: a reply owed comes from it or not at all).
  ProtocolChild* current() { return child_ && child_->healthy() ? child_.get() : nullptr; }

 private:
  std::shared_ptr<Outside> o_;
  double deadline_s_;
  std::unique_ptr<ProtocolChild> child_;
};

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

/// RigidCarState from a car reply (docs/protocol.md, "step (car)").
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

/// A step request's numbers as JSON: fmt's shortest form that reads back to the same double.
void put(std::string& out, double v) {
  if (!std::isfinite(v)) throw EngineError("a step request with a non-finite number (the protocol has no NaN)");
  fmt::format_to(std::back_inserter(out), "{}", v);
}

/// The slots of a car step reply (docs/protocol.md, "step (car)"), in the order car_state_of reads them.
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

/// The slot of the reply's "id" among car_slots(wheels).
size_t car_id_slot(int wheels) { return 10 + 10 * static_cast<size_t>(wheels); }

/// RigidCarState from a reply read by the slots of car_slots(wheels).
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

/// A car stepped by an outside engine: RigidCar's servo and bookkeeping over the protocol.
class ProtocolCar final : public RigidCar {
 public:
  ProtocolCar(std::shared_ptr<Outside> o, Settings s)
      : RigidCar(std::move(s)),
        lease_(std::move(o)),
        wheel_shape_(settings_.has("wheel") ? settings_.choice("wheel") : "sphere") {}
  /// A run ended with lines of its last "steps" unread (liftcheck stopped it: a blow-up): they are
  /// read and dropped, a little while at most each, so that the child serves the next run in step;
  /// one that does not come ends the child (fail() kills it).
  ~ProtocolCar() override {
    ProtocolChild* c = planned_ > 0 ? lease_.current() : nullptr;
    try {
      for (; c && planned_ > 0; --planned_) c->next_line(std::min(2.0, lease_.seconds_left()));
    } catch (...) {  // the child is ended; the run's own error stands
    }
  }
  double reported_engine_s() const override { return engine_s_; }

 protected:
  void build(const CarSetup& setup, const TricycleDef& d, const car::Config& q0) override {
    const json car{{"R_m", d.R_m},
                   {"l_m", d.l_m},
                   {"track_m", d.track_m},
                   {"wheels", d.wheels},
                   {"parallel_steering", d.parallel_steering},
                   {"wheel_width_m", d.wheel_width_m},
                   {"wheel_shape", wheel_shape_},
                   {"chassis_height_m", d.chassis_height_m},
                   {"chassis_mass_kg", d.chassis_mass_kg},
                   {"wheel_mass_kg", d.wheel_mass_kg},
                   {"knuckle_mass_kg", d.knuckle_mass_kg}};
    json req{
        {"op", "car"},
        {"settings", settings_json(settings_)},
        {"dt_s", setup.dt_s},
        {"mu", setup.mu},
        {"gravity_W", vec(setup.gravity_W())},
        {"car", car},
        {"q0", {{"x_m", q0.x_m}, {"y_m", q0.y_m}, {"phi_rad", q0.phi_rad}, {"beta_rad", q0.beta_rad}}},
        {"servo",
         {{"spin_torque_max_Nm", servo_.spin_torque_max_Nm}, {"steer_torque_max_Nm", servo_.steer_torque_max_Nm}}}};
    // Braked runs only (an adapter whose hello declares "brakes"): each rear wheel's brake torque.
    if (servo_.rear_brake_torque_max_Nm > 0.0)
      req["servo"]["rear_brake_torque_max_Nm"] = servo_.rear_brake_torque_max_Nm;
    const json r = lease_.call(req);
    state_ = car_state(lease_.get(), r, d.wheels);
  }
  void actuate(const FrontRates& rates, const ServoDef&) override { rates_ = rates; }
  /// The tricycle's next steps in one exchange where the adapter answers "steps" (docs/protocol.md):
  /// it applies the servo's law of RigidCar::drive, rate = feed-forward + gain x (target - angle),
  /// with the wheel angle booked as drive() books it, and replies a line per step; step() reads
  /// them one by one and checks the rates applied against its own servo's, bit for bit.
  void plan(const std::vector<ServoTarget>& next, double alpha_rad, const RigidCarState& now) override {
    if (!lease_.outside().servo_steps || def_.wheels != 3 || next.size() < 2) return;
    request_.assign(R"({"op":"steps","dt_s":)");
    put(request_, setup_.dt_s);
    request_ += R"(,"spin_gain_per_s":)", put(request_, servo_.spin_gain_per_s);
    request_ += R"(,"steer_gain_per_s":)", put(request_, servo_.steer_gain_per_s);
    request_ += R"(,"alpha_rad":)", put(request_, alpha_rad);
    request_ += R"(,"spin_rad":)", put(request_, now.spin_joint_rad[0]);
    request_ += R"(,"steer_rad":)", put(request_, now.steer_rad[0]);
    request_ += R"(,"targets":[)";
    for (size_t i = 0; i < next.size(); ++i) {
      const ServoTarget& g = next[i];
      request_ += i ? ",[" : "[";
      put(request_, g.alpha_rad), request_ += ',', put(request_, g.beta_rad), request_ += ',';
      put(request_, g.alpha_rate_radps), request_ += ',', put(request_, g.beta_rate_radps), request_ += ']';
    }
    request_ += "]}";
    lease_.get().send("step", request_, lease_.seconds_left());
    planned_ = next.size();
  }
  /// One step: the request written with fmt (or the next line of a planned run), the reply read
  /// by its slots; a reply the fast path does not take is read the checked way (which names what
  /// is wrong with it).
  void step(double dt_s) override {
    if (planned_ > 0) {
      ProtocolChild* c = lease_.current();
      if (!c) {
        planned_ = 0;
        throw EngineError(fmt::format("engine '{}' (step): the process ended before its planned steps' replies",
                                      lease_.outside().name));
      }
      if (dt_s != setup_.dt_s) throw EngineError("a planned step of another dt (liftcheck's own error)");
      planned_ -= 1;
      try {
        take_reply(*c, c->next_line(lease_.seconds_left()), true);
      } catch (...) {  // an error reply ends the adapter's lines; any other failure has ended the child
        planned_ = 0;
        throw;
      }
      return;
    }
    ProtocolChild& c = lease_.get();
    request_.assign(R"({"op":"step","spin_radps":[)");
    put(request_, rates_.spin_radps[0]), request_ += ',', put(request_, rates_.spin_radps[1]);
    request_ += R"(],"steer_radps":[)";
    put(request_, rates_.steer_radps[0]), request_ += ',', put(request_, rates_.steer_radps[1]);
    request_ += R"(],"dt_s":)";
    put(request_, dt_s);
    request_ += '}';
    take_reply(c, c.exchange("step", request_, lease_.seconds_left()), false);
  }
  /// A step's reply line: the state, the optional force and chassis velocity; in a planned run
  /// (`planned`), the rates the adapter applied, which must be those of actuate().
  void take_reply(ProtocolChild& c, const std::string& line, bool planned) {
    if (!reply_ || reply_wheels_ != def_.wheels) reply_.emplace(car_slots(def_.wheels)), reply_wheels_ = def_.wheels;
    const size_t f = car_id_slot(def_.wheels) + 1;  // ground_force_W: all three numbers or none
    const size_t v = f + 3;                         // v_chassis_W: all three numbers or none
    const int forces = reply_->read(line) ? reply_->given(f) + reply_->given(f + 1) + reply_->given(f + 2) : -1;
    const int chassis = forces >= 0 ? reply_->given(v) + reply_->given(v + 1) + reply_->given(v + 2) : -1;
    // A field named but not read as three numbers (null, [], a string) is the checked path's to name.
    const bool unread = (forces == 0 && line.find(R"("ground_force_W")") != std::string::npos) ||
                        (chassis == 0 && line.find(R"("v_chassis_W")") != std::string::npos);
    if (!unread && (forces == 0 || forces == 3) && (chassis == 0 || chassis == 3) && reply_->value(0) >= 0.0 &&
        reply_->value(car_id_slot(def_.wheels)) == static_cast<double>(c.request_id())) {
      engine_s_ += reply_->value(0);
      state_ = car_state_of(*reply_, def_.wheels);
      if (chassis == 3) state_.v_chassis_W = {reply_->value(v), reply_->value(v + 1), reply_->value(v + 2)};
      force_.reset();
      if (forces == 3) force_ = Eigen::Vector3d(reply_->value(f), reply_->value(f + 1), reply_->value(f + 2));
      if (planned) {
        const size_t a = v + 3;
        if (!reply_->given(a) || !reply_->given(a + 1))
          c.fail("a reply to \"steps\" without the rates it applied ('applied')");
        check_applied(c, reply_->value(a), reply_->value(a + 1));
      }
      return;
    }
    const json r = c.checked_reply(line);
    engine_s_ += engine_seconds(c, r);
    state_ = car_state(c, r, def_.wheels);
    force_.reset();
    if (r.contains("ground_force_W")) force_ = vec3(c, r, "ground_force_W", "");
    if (planned) {
      const std::vector<double> applied = c.numbers(r, "applied", 2);
      check_applied(c, applied[0], applied[1]);
    }
  }
  /// A planned step's rates as the adapter applied them against those liftcheck's servo gives.
  void check_applied(ProtocolChild& c, double spin_radps, double steer_radps) {
    if (spin_radps == rates_.spin_radps[0] && steer_radps == rates_.steer_radps[0]) return;
    c.fail(fmt::format(
        "its servo loop applied spin {} and steering {} rad/s where liftcheck's servo gives {} and {}: not the law of "
        "docs/protocol.md (\"steps\")",
        spin_radps, steer_radps, rates_.spin_radps[0], rates_.steer_radps[0]));
  }
  /// The optional "ground_force_W" of the step's reply (docs/protocol.md): absent, not measured.
  std::optional<Eigen::Vector3d> ground_force_W() const override { return force_; }
  std::string ground_force_absent_why() const override {
    const std::string& fact = lease_.outside().contact_forces;
    return fact.empty() ? "its adapter's step replies carry no contact forces (the protocol's optional ground_force_W)"
                        : "its step replies carry no contact forces: " + fact;
  }
  bool four_wheels() const override { return lease_.outside().four_wheels; }
  RigidCarState read() const override { return state_; }

 private:
  Lease lease_;
  std::string wheel_shape_;  ///< the "wheel" setting, read once (sphere when the engine has none)
  FrontRates rates_;
  RigidCarState state_{};
  std::optional<Eigen::Vector3d> force_;
  double engine_s_ = 0.0;
  size_t planned_ = 0;  ///< reply lines of the last "steps" still to read
  std::string request_;
  std::optional<FlatReply> reply_;
  int reply_wheels_ = 0;
};

/// Two disks in an outside engine: DrivenDisks' control loop and contact bookkeeping over the protocol.
class ProtocolDisks final : public DrivenDisks {
 public:
  ProtocolDisks(std::shared_ptr<Outside> o, Settings s) : lease_(std::move(o)), settings_(std::move(s)) {}
  double reported_engine_s() const override { return engine_s_; }

 protected:
  void build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) override {
    const json req{{"op", "disks"},
                   {"settings", settings_json(settings_)},
                   {"radius_m", setup.radius_m},
                   {"dt_s", setup.dt_s},
                   {"mu_MN", setup.mu_MN},
                   {"cM0", vec(cM0)},
                   {"cN0", vec(cN0)}};
    const json r = lease_.call(req);
    state_ = positions(lease_.get(), r);
  }
  StepContacts step(const disks::Vec2& vM_cmd, const disks::Vec2& cN_next, const disks::Vec2& vN,
                    double dt_s) override {
    request_.assign(R"({"op":"step","vM_cmd":[)");
    put(request_, vM_cmd.x()), request_ += ',', put(request_, vM_cmd.y());
    request_ += R"(],"cN_next":[)";
    put(request_, cN_next.x()), request_ += ',', put(request_, cN_next.y());
    request_ += R"(],"vN":[)";
    put(request_, vN.x()), request_ += ',', put(request_, vN.y());
    request_ += R"(],"dt_s":)";
    put(request_, dt_s);
    request_ += '}';
    ProtocolChild& c = lease_.get();
    const std::string& line = c.exchange("step", request_, lease_.seconds_left());
    // The fast path: engine_s, cM, cN, contacts.count and, where there are contacts, their depth and
    // distance; the reply's number (slot 8) the request's.
    if (reply_.read(line) && reply_.value(8) == static_cast<double>(c.request_id()) && reply_.value(0) >= 0.0 &&
        reply_.value(5) >= 0.0 &&
        (reply_.value(5) == 0.0 || (reply_.given(6) && reply_.given(7) && reply_.value(6) >= 0.0))) {
      engine_s_ += reply_.value(0);
      state_ = {disks::Vec2(reply_.value(1), reply_.value(2)), disks::Vec2(reply_.value(3), reply_.value(4)),
                Eigen::Vector3d(reply_.value(9), reply_.value(10), reply_.value(11))};
      StepContacts out;
      out.count = static_cast<int>(std::min(reply_.value(5), 1e6));
      if (out.count > 0) out.depth_max_m = reply_.value(6), out.distance_min_m = reply_.value(7);
      return out;
    }
    const json r = c.checked_reply(line);
    engine_s_ += engine_seconds(c, r);
    state_ = positions(c, r);
    const std::vector<double> w = c.numbers(r, "wM", 3);
    state_.wM_radps = Eigen::Vector3d(w[0], w[1], w[2]);
    const auto ct = r.find("contacts");
    if (ct == r.end() || !ct->is_object()) c.fail("the reply has no object 'contacts'");
    const auto n = ct->find("count");
    if (n == ct->end() || !n->is_number_integer() || n->get<long>() < 0)
      c.fail("'contacts.count' is not a whole number >= 0");
    StepContacts out;
    out.count = static_cast<int>(std::min<long>(n->get<long>(), 1000000));
    if (out.count > 0) {
      out.depth_max_m = c.number(*ct, "depth_max_m", "contacts.");
      out.distance_min_m = c.number(*ct, "distance_min_m", "contacts.");
      if (out.depth_max_m < 0.0) c.fail("'contacts.depth_max_m' is negative");
    }
    return out;
  }
  State read() const override { return state_; }
  /// A contact reported within the precision's bookkeeping tolerance of touching (1e-9 m, 1e-5 m
  /// for float32) touches; one further apart is speculative.
  double touching_distance_m() const override { return 1e-9 * bookkeeping_factor(lease_.outside().precision); }

 private:
  static State positions(ProtocolChild& c, const json& r) {
    const std::vector<double> m = c.numbers(r, "cM", 2), n = c.numbers(r, "cN", 2);
    return {disks::Vec2(m[0], m[1]), disks::Vec2(n[0], n[1])};
  }
  Lease lease_;
  Settings settings_;
  State state_;
  double engine_s_ = 0.0;
  std::string request_;
  FlatReply reply_{{{"engine_s"},
                    {"cM/0"},
                    {"cM/1"},
                    {"cN/0"},
                    {"cN/1"},
                    {"contacts/count", true, true},
                    {"contacts/depth_max_m", false},
                    {"contacts/distance_min_m", false},
                    {"id", true, true},
                    {"wM/0"},
                    {"wM/1"},
                    {"wM/2"}}};
};

// ---- the hello: what the configuration is ----

std::string text_field(ProtocolChild& c, const json& j, const char* key, const std::string& where,
                       bool required = true) {
  const auto it = j.find(key);
  if (it == j.end() && !required) return "";
  if (it == j.end() || !it->is_string()) c.fail(fmt::format("hello: '{}{}' must be a string", where, key));
  return printable(it->get<std::string>(), 300);  // what an engine says is shown on one line
}

/// A setting's optional "role": "solver_iterations" (an iteration count: its cost grows with it; tune
/// ranks by it) or "damping" (a velocity damping the gravity check turns off).
SettingRole knob_role(ProtocolChild& c, const json& j, const std::string& where) {
  const auto r = j.find("role");
  if (r == j.end()) return SettingRole::kNone;
  if (r->is_string() && *r == "solver_iterations") return SettingRole::kSolverIterations;
  if (r->is_string() && *r == "damping") return SettingRole::kDamping;
  c.fail(fmt::format("hello: {}role must be 'solver_iterations' or 'damping'", where));
  return SettingRole::kNone;
}

SettingSpec knob(ProtocolChild& c, const json& j, size_t i) {
  const std::string where = fmt::format("settings[{}].", i);
  if (!j.is_object()) c.fail(fmt::format("hello: settings[{}] is not an object", i));
  SettingSpec k;
  k.key = text_field(c, j, "key", where);
  if (k.key.empty() || k.key.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789_") != std::string::npos)
    c.fail(fmt::format("hello: {}key '{}' must be lower-case letters, digits and '_'", where, k.key));
  const std::optional<Vehicle> vehicle = parse_vehicle(text_field(c, j, "vehicle", where));
  if (!vehicle) c.fail(fmt::format("hello: {}vehicle must be 'car' or 'disks'", where));
  k.vehicle = *vehicle;
  const std::string kind = text_field(c, j, "kind", where);
  const std::optional<ParamKind> named = setting_kind_named(kind);
  if (!named) c.fail(fmt::format("hello: {}kind must be integer, real or choice", where));
  k.kind = *named;
  const auto d = j.find("default");
  if (d == j.end() || !(d->is_string() || d->is_number())) c.fail(fmt::format("hello: {}default is missing", where));
  k.default_text = d->is_string() ? printable(d->get<std::string>(), 300) : fmt::format("{:g}", d->get<double>());
  k.help = text_field(c, j, "help", where, false);
  k.role = knob_role(c, j, where);
  if (k.numeric()) {
    k.min = c.number(j, "min", where.c_str()), k.max = c.number(j, "max", where.c_str());
    if (j.contains("min_exclusive") && !j["min_exclusive"].is_boolean())
      c.fail(fmt::format("hello: {}min_exclusive must be true or false", where));
    k.min_exclusive = j.value("min_exclusive", false);
    k.unit = "1";
    try {
      (void)parse_param(k, k.default_text);
    } catch (const InputError&) {
      c.fail(fmt::format("hello: {}default '{}' is outside its range {}", where, k.default_text, k.range_text()));
    }
  } else {
    const auto ch = j.find("choices");
    if (ch == j.end() || !ch->is_array() || ch->empty())
      c.fail(fmt::format("hello: {}choices must be a non-empty array", where));
    for (const auto& v : *ch) {
      if (!v.is_string()) c.fail(fmt::format("hello: {}choices must be strings", where));
      k.choices.push_back(printable(v.get<std::string>(), 300));
    }
    if (std::find(k.choices.begin(), k.choices.end(), k.default_text) == k.choices.end())
      c.fail(fmt::format("hello: {}default '{}' is not one of its choices", where, k.default_text));
  }
  // A role the harness acts on must fit what it does with it: tune counts an iteration count's
  // passes, the gravity check sets a damping to 0.
  if (k.role == SettingRole::kSolverIterations && (k.kind != ParamKind::kInteger || k.min < 0.0))
    c.fail(fmt::format("hello: {}role 'solver_iterations' needs an integer setting whose min is at least 0", where));
  if (k.role == SettingRole::kDamping && (!k.numeric() || k.min > 0.0 || (k.min == 0.0 && k.min_exclusive)))
    c.fail(fmt::format("hello: {}role 'damping' needs a number setting whose range includes 0", where));
  return k;
}

/// Fills `e` from the hello reply `r` of child `c` (fail() on anything malformed).
void apply_hello(EngineInfo& e, ProtocolChild& c, const json& r, const std::shared_ptr<Outside>& o) {
  e.library = text_field(c, r, "engine", "");
  e.version = text_field(c, r, "version", "");
  e.precision = text_field(c, r, "precision", "");
  if (e.precision != "float32" && e.precision != "float64")
    c.fail(fmt::format("hello: precision '{}' must be float32 or float64", e.precision));
  o->precision = e.precision;
  const auto v = r.find("vehicles");
  if (v == r.end() || !v->is_array()) c.fail("hello: 'vehicles' must be an array of \"car\" and \"disks\"");
  std::set<Vehicle> vehicles;
  for (const auto& x : *v) {
    const std::optional<Vehicle> vehicle = x.is_string() ? parse_vehicle(x.get<std::string>()) : std::nullopt;
    if (!vehicle) c.fail("hello: 'vehicles' must hold \"car\" and/or \"disks\"");
    vehicles.insert(*vehicle);
  }
  if (vehicles.empty()) c.fail("hello: 'vehicles' names no vehicle");
  if (r.contains("four_wheels") && !r["four_wheels"].is_boolean()) c.fail("hello: 'four_wheels' must be true or false");
  e.four_wheels = o->four_wheels = r.value("four_wheels", false);
  if (r.contains("brakes") && !r["brakes"].is_boolean()) c.fail("hello: 'brakes' must be true or false");
  e.brakes = r.value("brakes", false);
  if (r.contains("servo_steps") && !r["servo_steps"].is_boolean()) c.fail("hello: 'servo_steps' must be true or false");
  o->servo_steps = r.value("servo_steps", false);
  e.knobs.clear();
  if (const auto s = r.find("settings"); s != r.end()) {
    if (!s->is_array()) c.fail("hello: 'settings' must be an array");
    for (size_t i = 0; i < s->size(); ++i) e.knobs.push_back(knob(c, (*s)[i], i));
  }
  std::set<std::pair<std::string, Vehicle>> seen;
  for (const SettingSpec& k : e.knobs)
    if (!seen.insert({k.key, k.vehicle}).second)
      c.fail(fmt::format("hello: setting '{}' declared twice for {}", k.key, to_string(k.vehicle)));
  e.settings.clear();
  if (const auto f = r.find("fixed"); f != r.end()) {
    if (!f->is_array()) c.fail("hello: 'fixed' must be an array of [name, value] pairs");
    for (const auto& p : *f) {
      if (!p.is_array() || p.size() != 2 || !p[0].is_string() || !p[1].is_string())
        c.fail("hello: 'fixed' must be an array of [name, value] pairs");
      e.settings.emplace_back(printable(p[0].get<std::string>(), 300), printable(p[1].get<std::string>(), 1000));
    }
  }
  e.settings.insert(e.settings.begin(), {"protocol", fmt::format("{} (docs/protocol.md), precision {}",
                                                                 fmt::join(e.outside.command, " "), e.precision)});
  for (const auto& [k, v] : e.settings)
    if (k == "contact forces") o->contact_forces = v;
  if (std::none_of(e.settings.begin(), e.settings.end(), [](const auto& f) { return f.first == "contact forces"; }))
    e.settings.emplace_back("contact forces",
                            "not declared by its adapter: liftcheck books the step replies' optional ground_force_W "
                            "where they carry it (docs/protocol.md); a run without it skips the load and momentum "
                            "checks and says so in details.ground_load");
  if (vehicles.count(Vehicle::kCar))
    e.make_car = [o](const Settings& s) { return std::make_unique<ProtocolCar>(o, s); };
  if (vehicles.count(Vehicle::kDisks))
    e.make_disks = [o](const Settings& s) { return std::make_unique<ProtocolDisks>(o, s); };
}

/// A configuration whose hello failed: every run of it is an error record saying why.
void make_unavailable(EngineInfo& e, const std::string& why) {
  e.outside.unavailable = why;
  e.library = "unavailable";
  e.version = "-";
  e.knobs.clear();
  e.settings = {{"unavailable", why}};
  e.make_car = [why](const Settings&) -> std::unique_ptr<CarEngine> { throw EngineError(why); };
  e.make_disks = [why](const Settings&) -> std::unique_ptr<DiskEngine> { throw EngineError(why); };
}

std::string registration_problem(const std::filesystem::path& file, const std::string& what) {
  return fmt::format("engine registration '{}': {}", file.string(), what);
}

/// One registration file, or a problem.
bool read_registration(const std::filesystem::path& file, EngineInfo& e, std::string& problem) {
  // Read as every JSON file a user gives: bounded, 64 levels at most, no key twice in an object.
  json j;
  try {
    j = parse_json_text(read_text_file(file, kProtocolLineMax, "engine registration"), file.filename().string());
  } catch (const InputError& err) {
    return problem = registration_problem(file, err.what()), false;
  }
  const auto str = [&](const char* key) {
    return j.contains(key) && j[key].is_string() ? j[key].get<std::string>() : std::string();
  };
  if (!j.is_object()) return problem = registration_problem(file, "not a JSON object"), false;
  e.name = str("name");
  if (e.name.empty() || e.name.find_first_not_of("abcdefghijklmnopqrstuvwxyz0123456789.-_") != std::string::npos)
    return problem = registration_problem(file, "'name' must be lower-case letters, digits, '.', '-' and '_'"), false;
  if (e.name != file.stem().string())
    return problem = registration_problem(file, fmt::format("'name' '{}' must be the file's name", e.name)), false;
  if (!j.contains("command") || !j["command"].is_array() || j["command"].empty())
    return problem = registration_problem(file, "'command' must be a non-empty array of strings (an argument vector)"),
           false;
  for (const auto& a : j["command"]) {
    if (!a.is_string() || a.get<std::string>().empty())
      return problem = registration_problem(file, "'command' must hold non-empty strings"), false;
    // An argument vector holds C strings: a NUL would cut the argument short, unseen.
    if (a.get<std::string>().find('\0') != std::string::npos)
      return problem =
                 registration_problem(file, fmt::format("'command' argument {} holds a NUL byte ('{}')",
                                                        e.outside.command.size(), printable(a.get<std::string>(), 80))),
             false;
    e.outside.command.push_back(a.get<std::string>());
  }
  e.description = str("description");
  e.color = str("color");
  const bool hex = e.color.size() == 7 && e.color[0] == '#' &&
                   e.color.find_first_not_of("0123456789abcdefABCDEF", 1) == std::string::npos;
  if (!hex) return problem = registration_problem(file, "'color' must be \"#rrggbb\""), false;
  // "points": "map": the configuration joins a suite's runs and its speed-accuracy map only; "runs":
  // its runs only, the map showing its default run (the rest with validate --all-points).
  const std::string points = j.contains("points") ? str("points") : "all";
  if (points != "all" && points != "map" && points != "runs")
    return problem = registration_problem(file, "'points' must be \"all\", \"map\" or \"runs\""), false;
  e.points = points == "all" ? SuitePoints::kAll : points == "map" ? SuitePoints::kMap : SuitePoints::kRuns;
  e.outside.registration = std::filesystem::absolute(file).lexically_normal().string();
  return true;
}

}  // namespace

void set_protocol_timeout(double run_timeout_s) {
  // The replies of a run may take most of the run's time limit, not all of it: before the engine
  // object is made, the worker process has started and read the configuration's hello (about a
  // second on a loaded machine), and after a hang it must still write the error record before
  // its own limit stops it.
  g_timeout_s = std::max(0.5, 0.85 * run_timeout_s - 1.5);
}
double protocol_timeout_s() { return g_timeout_s; }

std::string default_suite_dir() {
  static const std::string dir = [] {
    std::error_code ec;
    const std::filesystem::path exe = std::filesystem::read_symlink("/proc/self/exe", ec);
    if (!ec) {
      const std::filesystem::path beside = exe.parent_path() / "outside" / "suite";
      if (std::filesystem::is_directory(beside, ec)) return beside.string();
    }
    return std::string(LIFTCHECK_OUTSIDE_DIR);
  }();
  return dir;
}

bool default_suite_is_beside_binary() { return default_suite_dir() != LIFTCHECK_OUTSIDE_DIR; }

std::string adapter_path(const EngineInfo& e) {
  if (e.outside.registration.empty()) return {};
  const std::filesystem::path cwd = std::filesystem::path(e.outside.registration).parent_path();
  std::error_code ec;
  for (size_t i = 0; i < e.outside.command.size(); ++i) {
    const std::string& a = e.outside.command[i];
    // A bare command[0] is looked up on PATH (the interpreter); options are not files.
    if ((i == 0 && a.find('/') == std::string::npos) || a.empty() || a[0] == '-') continue;
    const std::filesystem::path p = cwd / a;  // an absolute argument stands for itself
    if (std::filesystem::is_regular_file(p, ec)) return std::filesystem::weakly_canonical(p, ec).string();
  }
  return {};
}

std::vector<std::string> engine_dirs() {
  std::vector<std::string> dirs{default_suite_dir()};
  if (const char* path = std::getenv("LIFTCHECK_ENGINE_PATH")) {
    std::stringstream ss(path);
    std::string d;
    while (std::getline(ss, d, ':'))
      if (!d.empty()) dirs.push_back(d);
  }
  return dirs;
}

std::vector<EngineInfo> outside_engines(const std::vector<std::string>& compiled_names,
                                        std::vector<std::string>& problems) {
  std::vector<EngineInfo> out;
  std::set<std::string> taken(compiled_names.begin(), compiled_names.end());
  std::set<std::string> dirs_seen;
  for (const std::string& dir : engine_dirs()) {
    std::error_code ec;
    const std::filesystem::path d = std::filesystem::weakly_canonical(std::filesystem::absolute(dir), ec);
    if (!dirs_seen.insert(d.string()).second) continue;
    if (!std::filesystem::is_directory(d, ec)) {
      if (dir != default_suite_dir())
        problems.push_back(
            fmt::format("engine folder '{}' (--engine-dir or LIFTCHECK_ENGINE_PATH) is not a folder", dir));
      continue;
    }
    std::vector<std::filesystem::path> files;
    for (const auto& entry : std::filesystem::directory_iterator(d, ec)) {
      const std::string name = entry.path().filename().string();
      if (entry.path().extension() == ".json" && name != "package.json" && name != "package-lock.json")
        files.push_back(entry.path());
    }
    // By configuration name (the file's stem), so that "cannon" comes before "cannon-accurate".
    std::sort(files.begin(), files.end(),
              [](const auto& a, const auto& b) { return a.stem().string() < b.stem().string(); });
    for (const auto& f : files) {
      EngineInfo e;
      std::string problem;
      if (!read_registration(f, e, problem)) {
        problems.push_back(problem);
        continue;
      }
      if (!taken.insert(e.name).second) {
        problems.push_back(registration_problem(
            f, fmt::format("the name '{}' is taken (by a compiled-in configuration or another registration)", e.name)));
        continue;
      }
      e.library = "outside";
      e.version = "?";
      e.contact_dynamics = true;
      e.outside.described = false;
      out.push_back(std::move(e));
    }
  }
  return out;
}

namespace {

std::mutex g_describe_m;  ///< one description of an entry at a time

/// describe_outside's work, the caller holding g_describe_m.
void describe_locked(EngineInfo& e) {
  if (e.outside.described) return;
  auto o = std::make_shared<Outside>();
  o->name = e.name;
  o->argv = e.outside.command;
  o->cwd = std::filesystem::path(e.outside.registration).parent_path().string();
  try {
    std::unique_ptr<ProtocolChild> c = start(*o);
    const json r = hello(*c, now_s() + protocol_timeout_s());
    apply_hello(e, *c, r, o);
    give_back(*o, std::move(c));
    std::lock_guard<std::mutex> all(g_all_m);
    g_all.push_back(o);
  } catch (const EngineError& err) {
    make_unavailable(e, err.what());
  } catch (const Interrupted&) {
    throw;                               // a signal while it started: the command ends, the configuration is not judged
  } catch (const std::exception& err) {  // a mistyped optional field of the hello
    make_unavailable(e, fmt::format("engine '{}' (hello): malformed: {}", e.name, err.what()));
  }
  e.outside.described = true;
}

}  // namespace

void describe_outside(EngineInfo& e) {
  std::lock_guard<std::mutex> lock(g_describe_m);
  describe_locked(e);
}

void describe_outside_all(const std::vector<EngineInfo*>& entries) {
  std::lock_guard<std::mutex> lock(g_describe_m);
  // As many at once as there are cores: each start is mostly its engine's CPU (a WASM module
  // compiled), so more would only share the cores; entries are distinct, so threads share none.
  const size_t n = std::min<size_t>(entries.size(), std::max(1u, std::thread::hardware_concurrency()));
  std::atomic<size_t> next{0};
  std::exception_ptr first;
  std::mutex first_m;
  const auto work = [&] {
    for (size_t i; (i = next++) < entries.size();) {
      try {
        describe_locked(*entries[i]);
      } catch (...) {  // Interrupted: the others end their hellos, then it is thrown on
        std::lock_guard<std::mutex> l(first_m);
        if (!first) first = std::current_exception();
        next = entries.size();
      }
    }
  };
  std::vector<std::thread> threads;
  for (size_t k = 1; k < n; ++k) {
    try {
      threads.emplace_back(work);
    } catch (const std::system_error&) {  // no thread to be had: fewer at once
      break;
    }
  }
  work();
  for (auto& t : threads) t.join();
  if (first) std::rethrow_exception(first);
}

EngineInfo outside_engine(const std::string& name, const std::vector<std::string>& command, const std::string& dir) {
  EngineInfo e;
  e.name = name;
  e.outside.command = command;
  e.outside.registration = (std::filesystem::path(dir) / (name + ".json")).string();
  e.color = "#e7298a";
  e.contact_dynamics = true;
  e.outside.described = false;
  describe_outside(e);
  return e;
}

void close_idle_children() {
  std::vector<std::shared_ptr<Outside>> all;
  {
    std::lock_guard<std::mutex> lock(g_all_m);
    for (const auto& w : g_all)
      if (auto o = w.lock()) all.push_back(o);
  }
  for (const auto& o : all) {
    std::vector<std::unique_ptr<ProtocolChild>> idle;
    {
      std::lock_guard<std::mutex> lock(o->m);
      idle.swap(o->idle);
    }
    for (auto& c : idle) c->close(1.0);
  }
}

}  // namespace liftcheck
