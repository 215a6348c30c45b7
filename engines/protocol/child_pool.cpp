// The child processes of the outside configurations (engines/protocol/outside.hpp): each
// configuration keeps its idle ones for the next run, a run leases one (Lease), and
// close_idle_children ends them.
#include <algorithm>
#include <atomic>
#include <fmt/format.h>
#include <memory>
#include <mutex>
#include <vector>

#include "engines/protocol/outside.hpp"
#include "engines/protocol/outside_internal.hpp"

namespace liftcheck {

using namespace protocol_detail;

namespace {

std::atomic<double> g_timeout_s{100.5};  // set_protocol_timeout(120), the default --timeout

std::mutex g_all_m;
std::vector<std::weak_ptr<Outside>> g_all;  ///< for close_idle_children

}  // namespace

namespace protocol_detail {

json hello(ProtocolChild& c, double deadline_s) {
  json r = c.call({{"op", "hello"}, {"protocol", kProtocolVersion}}, std::max(0.05, deadline_s - now_s()));
  const auto p = r.find("protocol");
  if (p == r.end() || !p->is_number_integer() || p->get<long>() != kProtocolVersion)
    c.fail(fmt::format("speaks protocol {}, liftcheck speaks {}", p == r.end() ? "(none given)" : p->dump(),
                       kProtocolVersion));
  return r;
}

std::unique_ptr<ProtocolChild> start(Outside& o) { return std::make_unique<ProtocolChild>(o.name, o.argv, o.cwd); }

/// Ends the idle children of every configuration but `keep`: a process keeps the adapters of the
/// configuration it runs now, not one of each it ever ran (an adapter holds 60 to 160 MB;
/// docs/performance.md).
void close_idle_except(const Outside& keep) {
  std::vector<std::shared_ptr<Outside>> others;
  {
    std::lock_guard<std::mutex> lock(g_all_m);
    for (const auto& w : g_all)
      if (auto o = w.lock(); o && o.get() != &keep) others.push_back(o);
  }
  std::vector<std::unique_ptr<ProtocolChild>> idle;
  for (const auto& o : others) {
    std::lock_guard<std::mutex> lock(o->m);
    for (auto& c : o->idle) idle.push_back(std::move(c));
    o->idle.clear();
  }
  for (auto& c : idle) c->close(1.0);
}

std::unique_ptr<ProtocolChild> take(Outside& o, double deadline_s) {
  close_idle_except(o);
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

void keep_for_closing(const std::shared_ptr<Outside>& o) {
  std::lock_guard<std::mutex> all(g_all_m);
  g_all.push_back(o);
}

}  // namespace protocol_detail

void set_protocol_timeout(double run_timeout_s) {
  // The replies of a run may take most of the run's time limit, not all of it: before the engine
  // object is made, the worker process has started and read the configuration's hello (about a
  // second on a loaded machine), and after a hang it must still write the error record before
  // its own limit stops it.
  g_timeout_s = std::max(0.5, 0.85 * run_timeout_s - 1.5);
}
double protocol_timeout_s() { return g_timeout_s; }

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
