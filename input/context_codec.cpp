// A suite's context as JSON (results.json "context").
#include <fmt/format.h>

#include "input/results_codec.hpp"

namespace liftcheck {

using json = nlohmann::json;

namespace {

json encode_knob(const KnobInfo& k) {
  json j{{"key", k.key}, {"vehicle", k.vehicle}, {"default", k.default_text}, {"help", k.help}, {"kind", k.kind}};
  if (!k.role.empty()) j["role"] = k.role;
  if (k.kind == "choice")
    j["choices"] = k.choices;
  else
    j["min"] = finite_or_null(k.min), j["max"] = finite_or_null(k.max), j["min_exclusive"] = k.min_exclusive;
  return j;
}

KnobInfo decode_knob(const JsonIn& in) {
  KnobInfo k;
  k.key = in.str("key");
  const auto v = parse_vehicle(in.str("vehicle"));
  if (!v) in.fail("'vehicle' must be \"car\" or \"disks\"");
  k.vehicle = *v;
  k.default_text = in.str("default");
  k.help = in.str("help");
  k.kind = in.str("kind");
  k.role = in.str_or("role", "");
  if (k.kind == "choice") {
    k.choices = in.strings("choices");
  } else {
    k.min = in.opt_num_or_null("min");
    k.max = in.opt_num_or_null("max");
    k.min_exclusive = in.boolean_or("min_exclusive", false);
  }
  return k;
}

}  // namespace

json encode_engine_context(const EngineContext& e) {
  json settings = json::object();
  for (const auto& [k, v] : e.settings) settings[k] = v;
  json knobs = json::array();
  for (const auto& k : e.knobs) knobs.push_back(encode_knob(k));
  json j{{"name", e.name},         {"library", e.library},
         {"version", e.version},   {"description", e.description},
         {"color", e.color},       {"is_reference", e.is_reference},
         {"vehicles", e.vehicles}, {"features", e.features},
         {"settings", settings},   {"knobs", knobs}};
  if (!e.registration.empty()) j["registration"] = e.registration, j["adapter"] = e.adapter;
  return j;
}

namespace {

EngineContext decode_engine(const JsonIn& in) {
  EngineContext e;
  e.name = in.str("name");
  e.library = in.str("library");
  e.version = in.str("version");
  e.description = in.str("description");
  e.color = in.str("color");
  e.is_reference = in.boolean("is_reference");
  for (const auto& v : in.strings("vehicles")) {
    const auto parsed = parse_vehicle(v);
    if (!parsed) in.fail("'vehicles' must hold \"car\" or \"disks\"");
    e.vehicles.push_back(*parsed);
  }
  e.features = in.strings("features");
  e.settings = in.text_pairs("settings");
  for (std::size_t i = 0; i < in.arr("knobs").size(); ++i) e.knobs.push_back(decode_knob(in.element("knobs", i)));
  e.registration = in.str_or("registration", "");
  e.adapter = in.str_or("adapter", "");
  return e;
}

json encode_tune(const TuneEntry& t) {
  json change = json::object();
  for (const auto& [k, v] : t.change) change[k] = v;
  return {{"change", change},
          {"passes", t.passes},
          {"default_passes", t.default_passes},
          {"cost_ratio", finite_or_null(t.cost_ratio)},
          {"worst_ratio", finite_or_null(t.worst_ratio)},
          {"cost_ms_per_s", finite_or_null(t.cost_ms_per_s)},
          {"default_cost_ms_per_s", finite_or_null(t.default_cost_ms_per_s)},
          {"model_cost", finite_or_null(t.model_cost)},
          {"runs", t.runs},
          {"budget", t.budget},
          {"unmade", t.unmade},
          {"fingerprint", t.fingerprint}};
}

}  // namespace

TuneEntry decode_tune_entry(const JsonIn& in) {
  TuneEntry t;
  t.change = in.text_pairs("change");
  t.passes = in.boolean("passes");
  t.default_passes = in.boolean("default_passes");
  t.cost_ratio = in.opt_num_or_null("cost_ratio");
  t.worst_ratio = in.opt_num_or_null("worst_ratio");
  t.cost_ms_per_s = in.opt_num_or_null("cost_ms_per_s");
  t.default_cost_ms_per_s = in.opt_num_or_null("default_cost_ms_per_s");
  t.model_cost = in.opt_num_or_null("model_cost");
  t.runs = in.integer_or("runs", 0);
  t.budget = in.integer_or("budget", 0);
  t.unmade = in.integer_or("unmade", 0);
  t.fingerprint = in.str_or("fingerprint", "");
  return t;
}

json encode_context(const SuiteContext& c) {
  json engines = json::array();
  for (const auto& e : c.engines) engines.push_back(encode_engine_context(e));
  json tune = json::object();
  for (const auto& [pair, t] : c.tune_table) tune[pair] = encode_tune(t);
  json set = json::object();
  for (const auto& [k, v] : c.set) set[k] = v;
  json j{{"liftcheck", {{"version", c.version}, {"commit", c.commit}}},
         {"date", c.date},
         {"machine",
          {{"host", c.machine.host}, {"os", c.machine.os}, {"cpus", c.machine.cpus}, {"compiler", c.machine.compiler}}},
         {"engines", engines},
         {"wall_s", c.wall_s},
         {"runs_s", c.runs_s},
         {"points_s", c.points_s},
         {"worker_s", c.worker_s},
         {"stepping_s", finite_or_null(c.stepping_s)},
         {"engine_s_by_part", c.engine_s_by_part},
         {"engine_s_by_configuration", c.engine_s_by_configuration},
         {"worker_s_by_part", c.worker_s_by_part},
         {"worker_s_by_configuration", c.worker_s_by_configuration},
         {"stepping_s_by_configuration", c.stepping_s_by_configuration},
         {"jobs", c.jobs},
         {"timeout_s", c.timeout_s},
         {"memory_limit_mib", c.memory_limit_mib},
         {"outside_suite", {{"folder", c.outside_folder}, {"beside_binary", c.outside_beside_binary}}},
         {"set", set},
         {"errata", c.errata},
         {"tune_table", tune}};
  if (c.merged_shards > 0) j["merged_shards"] = c.merged_shards;
  return j;
}

SuiteContext decode_context(const JsonIn& in) {
  SuiteContext c;
  const JsonIn lc = in.obj("liftcheck");
  c.version = lc.str("version");
  c.commit = lc.str("commit");
  c.date = in.str("date");
  const JsonIn m = in.obj("machine");
  c.machine = {m.str("host"), m.str("os"), m.str("compiler"), m.integer("cpus")};
  for (std::size_t i = 0; i < in.arr("engines").size(); ++i)
    c.engines.push_back(decode_engine(in.element("engines", i)));
  c.wall_s = in.num("wall_s");
  c.runs_s = in.num("runs_s");
  c.points_s = in.num("points_s");
  c.worker_s = in.num_or("worker_s", 0.0);
  c.stepping_s = in.opt_num_or_null("stepping_s");
  c.engine_s_by_part = in.number_map("engine_s_by_part", false);
  c.engine_s_by_configuration = in.number_map("engine_s_by_configuration", false);
  c.worker_s_by_part = in.number_map("worker_s_by_part", false);
  c.worker_s_by_configuration = in.number_map("worker_s_by_configuration", false);
  c.stepping_s_by_configuration = in.number_map("stepping_s_by_configuration", false);
  c.jobs = in.integer("jobs");
  c.timeout_s = in.num("timeout_s");
  c.memory_limit_mib = in.num_or("memory_limit_mib", 0.0);
  if (const auto o = in.opt_obj("outside_suite"))
    c.outside_folder = o->str("folder"), c.outside_beside_binary = o->boolean("beside_binary");
  for (const auto& kv : in.text_pairs("set")) c.set.push_back(kv);
  c.merged_shards = in.integer_or("merged_shards", 0);
  c.errata = in.str("errata");
  if (const auto t = in.opt_obj("tune_table"))
    for (const auto& [pair, entry] : t->value().items()) c.tune_table[pair] = decode_tune_entry(t->obj(pair.c_str()));
  return c;
}

const EngineContext* SuiteContext::engine(const std::string& name) const {
  for (const auto& e : engines)
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace liftcheck
