// What the files of an outside configuration share (engines/protocol/outside.hpp is the interface):
// the child processes of a configuration and the lease a run holds on one (child_pool.cpp), the
// requests' and replies' numbers (wire.cpp), and its car and disks over the protocol
// (protocol_car.cpp, protocol_disks.cpp), made by the hello (hello.cpp). Only those files include it.
#pragma once

#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <memory>
#include <mutex>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engines/driven_disks.hpp"
#include "engines/engine.hpp"
#include "engines/protocol/child.hpp"
#include "engines/protocol/flat_reply.hpp"
#include "engines/protocol/outside.hpp"
#include "engines/rigid_car.hpp"

namespace liftcheck::protocol_detail {

using nlohmann::json;

// ---- the child processes (child_pool.cpp) ----

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

inline double now_s() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

/// The hello of a child just started: the protocol version must be liftcheck's.
json hello(ProtocolChild& c, double deadline_s);

std::unique_ptr<ProtocolChild> start(Outside& o);

/// A child for one engine object: an idle one, or a new one past its hello.
std::unique_ptr<ProtocolChild> take(Outside& o, double deadline_s);

void give_back(Outside& o, std::unique_ptr<ProtocolChild> c);

/// Adds a described configuration to those whose idle children close_idle_children ends.
void keep_for_closing(const std::shared_ptr<Outside>& o);

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

// ---- the requests' and replies' numbers (wire.cpp) ----

json settings_json(const Settings& s);

json vec(const Eigen::Vector3d& v);
json vec(const disks::Vec2& v);
Eigen::Vector3d vec3(ProtocolChild& c, const json& j, const char* key, const char* where);

/// RigidCarState from a car reply (docs/protocol.md, "step (car)").
RigidCarState car_state(ProtocolChild& c, const json& r, int wheels);

double engine_seconds(ProtocolChild& c, const json& r);

/// A step request's numbers as JSON: fmt's shortest form that reads back to the same double.
void put(std::string& out, double v);

/// The slots of a car step reply (docs/protocol.md, "step (car)"), in the order car_state_of reads them.
std::vector<FlatReply::Slot> car_slots(int wheels);

/// The slot of the reply's "id" among car_slots(wheels).
size_t car_id_slot(int wheels);

/// RigidCarState from a reply read by the slots of car_slots(wheels).
RigidCarState car_state_of(const FlatReply& f, int wheels);

// ---- the vehicles over the protocol (protocol_car.cpp, protocol_disks.cpp) ----

/// A car of configuration `o` with the run's settings `s` (ProtocolCar).
std::unique_ptr<CarEngine> make_protocol_car(std::shared_ptr<Outside> o, Settings s);

/// Two disks of configuration `o` with the run's settings `s` (ProtocolDisks).
std::unique_ptr<DiskEngine> make_protocol_disks(std::shared_ptr<Outside> o, Settings s);

}  // namespace liftcheck::protocol_detail
