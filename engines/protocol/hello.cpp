// The hello of an outside configuration (docs/protocol.md, "hello"): what the configuration is
// (engine, version, precision, vehicles, knobs, fixed settings) read from its first child process
// when it is first looked up, or why it is unavailable.
#include <algorithm>
#include <atomic>
#include <exception>
#include <filesystem>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <system_error>
#include <thread>

#include "engines/protocol/outside.hpp"
#include "engines/protocol/outside_internal.hpp"
#include "input/interrupt.hpp"
#include "input/params.hpp"  // InputError
#include "input/trace.hpp"   // printable

namespace liftcheck {

using namespace protocol_detail;

namespace {

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
  if (vehicles.count(Vehicle::kCar)) e.make_car = [o](const Settings& s) { return make_protocol_car(o, s); };
  if (vehicles.count(Vehicle::kDisks)) e.make_disks = [o](const Settings& s) { return make_protocol_disks(o, s); };
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
    keep_for_closing(o);
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

}  // namespace liftcheck
