// A car stepped by an outside engine (docs/protocol.md, "car", "step (car)", "steps"): RigidCar's
// servo and bookkeeping, the engine's state read from its replies.
#include <algorithm>
#include <fmt/format.h>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "engines/protocol/outside_internal.hpp"

namespace liftcheck {

using namespace protocol_detail;

namespace {

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

}  // namespace

std::unique_ptr<CarEngine> protocol_detail::make_protocol_car(std::shared_ptr<Outside> o, Settings s) {
  return std::make_unique<ProtocolCar>(std::move(o), std::move(s));
}

}  // namespace liftcheck
