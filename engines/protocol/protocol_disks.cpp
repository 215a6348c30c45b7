// Two disks in an outside engine (docs/protocol.md, "disks", "step (disks)"): DrivenDisks' control
// loop and contact bookkeeping, the engine's positions and contacts read from its replies.
#include <algorithm>
#include <memory>
#include <string>
#include <vector>

#include "engines/protocol/outside_internal.hpp"

namespace liftcheck {

using namespace protocol_detail;

namespace {

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

}  // namespace

std::unique_ptr<DiskEngine> protocol_detail::make_protocol_disks(std::shared_ptr<Outside> o, Settings s) {
  return std::make_unique<ProtocolDisks>(std::move(o), std::move(s));
}

}  // namespace liftcheck
