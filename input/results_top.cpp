// The results document and the baseline: encode_results, decode_results, encode_baseline.
#include <fmt/format.h>

#include "input/results_codec.hpp"
#include "input/standing.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck {

using json = nlohmann::json;

namespace {

json encode_summary(const Summary& s) {
  return {{"total", s.total},
          {"pass", s.pass},
          {"known failure", s.known},
          {"unexpected pass", s.unexpected_pass},
          {"fail", s.fail},
          {"error", s.error},
          {"skip", s.skip},
          {"unexpected", s.unexpected()},
          {"sweep_gates", s.sweep_gates},
          {"sweep_gates_failed", s.sweep_gates_failed},
          {"baseline_problems", s.baseline_problems}};
}

json encode_shard(const ShardInfo& s) { return {{"index", s.index}, {"total", s.total}, {"items", s.items}}; }

void decode_shard(const JsonIn& top, SuiteResults& out) {
  const JsonIn sh = top.obj("shard");
  ShardInfo s;
  s.index = sh.integer("index");
  s.total = sh.integer("total");
  s.items = static_cast<std::size_t>(sh.integer_or("items", 0));
  const JsonIn plan = top.obj("plan");
  s.selection = plan.obj("selection").value();
  s.keys = plan.strings("keys");
  out.shard = std::move(s);
}

/// The records of "points", each decoded in `form`.
std::map<std::string, RunResult> decode_points(const JsonIn& top, RecordForm form) {
  std::map<std::string, RunResult> out;
  if (const auto points = top.opt_obj("points"))
    for (const auto& [key, r] : points->value().items()) out.emplace(key, decode_run(points->obj(key.c_str()), form));
  return out;
}

json encode_points(const std::map<std::string, RunResult>& points, RecordForm form) {
  json out = json::object();
  for (const auto& [key, p] : points) out[key] = encode_run(p, form);
  return out;
}

}  // namespace

ComparableParts decode_comparable(const json& doc, const std::string& name);

namespace {

SuiteResults decode_baseline(const JsonIn& top, const std::string& name, const RunsDecoder& runs) {
  SuiteResults out;
  out.is_baseline = true;
  const JsonIn lc = top.obj("context").obj("liftcheck");
  out.context.version = lc.str("version");
  out.context.commit = lc.str("commit");
  out.runs = runs(top, RecordForm::kBaseline);
  ComparableParts parts = decode_comparable(top.value(), name);
  out.points = std::move(parts.points);
  out.baseline_outcomes = std::move(parts.outcomes);
  return out;
}

}  // namespace

json encode_results(const SuiteResults& r) {
  json runs = json::array();
  for (const RunResult& run : r.runs) runs.push_back(encode_run(run));
  json scenarios = json::array();
  for (const auto& s : r.scenarios) scenarios.push_back(encode_scenario(s));
  json sweeps = json::array();
  for (const auto& s : r.sweeps) sweeps.push_back(encode_sweep(s));
  if (r.outcomes) sweeps.push_back(encode_outcomes(*r.outcomes));
  json maps = json::array();
  for (const auto& m : r.maps) maps.push_back(encode_map(m));
  json j{{"liftcheck_results", kResultsFormat},
         {"context", encode_context(r.context)},
         {"summary", encode_summary(summarize(r))},
         {"scenarios", scenarios},
         {"runs", runs},
         {"sweeps", sweeps},
         {"maps", maps},
         {"simulated", encode_simulated(r.simulated)}};
  if (r.report) j["report"] = encode_report(*r.report);
  if (r.baseline)
    j["baseline"] = {{"file", r.baseline->file},
                     {"worse_factor", r.baseline->worse_factor},
                     {"diff", encode_diff(r.baseline->diff)}};
  // The points' records are what merge assembles a shard's sweeps from; a whole suite's sweeps,
  // outcome grid and map hold what its pages and a diff read (the baseline keeps its points).
  if (r.shard) {
    j["points"] = encode_points(r.points, RecordForm::kResults);
    j["shard"] = encode_shard(*r.shard);
    j["plan"] = {{"selection", r.shard->selection}, {"keys", r.shard->keys}};
  }
  return j;
}

std::vector<RunResult> decode_runs(const JsonIn& top, RecordForm form, const std::string& name) {
  std::vector<RunResult> runs;
  const json& arr = top.arr("runs");
  runs.reserve(arr.size());
  for (std::size_t i = 0; i < arr.size(); ++i)
    runs.push_back(decode_run(JsonIn(arr[i], name, fmt::format("runs[{}]", i)), form));
  refuse_repeated_runs(runs, name, "runs");
  return runs;
}

RecordForm document_form(const JsonIn& top, const std::string& name) {
  const char* form = top.has("liftcheck_baseline") ? "liftcheck_baseline" : "liftcheck_results";
  const int format = top.has(form) ? top.integer(form) : 1;
  if (format != kResultsFormat)
    throw InputError(
        fmt::format("{}: is in the results format {} of another liftcheck; this one reads format {} "
                    "(write it again with this liftcheck's validate)",
                    name, format, kResultsFormat));
  return top.has("liftcheck_baseline") ? RecordForm::kBaseline : RecordForm::kResults;
}

SuiteResults decode_results(const json& doc, const std::string& name) {
  return decode_results(doc, name, [&](const JsonIn& top, RecordForm form) { return decode_runs(top, form, name); });
}

SuiteResults decode_results(const json& doc, const std::string& name, const RunsDecoder& runs) {
  if (!doc.is_object())
    throw InputError(fmt::format("{}: is not a liftcheck results file (the top level is {}, not an object)", name,
                                 json_type_of(doc)));
  if (!doc.contains("runs")) throw InputError(fmt::format("{}: is not a liftcheck results file (no \"runs\")", name));
  if (!doc["runs"].is_array())
    throw InputError(fmt::format("{}: 'runs' is {}, not an array", name, json_type_of(doc["runs"])));
  const JsonIn top(doc, name, "");
  if (document_form(top, name) == RecordForm::kBaseline) return decode_baseline(top, name, runs);
  SuiteResults out;
  out.context = decode_context(top.obj("context"));
  out.runs = runs(top, RecordForm::kResults);
  for (std::size_t i = 0; i < top.arr("scenarios").size(); ++i)
    out.scenarios.push_back(decode_scenario(top.element("scenarios", i)));
  for (std::size_t i = 0; i < top.arr("sweeps").size(); ++i) {
    const JsonIn s = top.element("sweeps", i);
    if (s.str_or("kind", "") == "outcomes")
      out.outcomes = decode_outcomes(s);
    else
      out.sweeps.push_back(decode_sweep(s));
  }
  for (std::size_t i = 0; i < top.arr("maps").size(); ++i) out.maps.push_back(decode_map(top.element("maps", i)));
  out.simulated = decode_simulated(top.obj("simulated"));
  if (const auto rep = top.opt_obj("report")) out.report = decode_report(*rep);
  if (const auto b = top.opt_obj("baseline"))
    out.baseline = BaselineComparison{b->str("file"), b->num_or("worse_factor", 0.0), decode_diff(b->obj("diff"))};
  out.points = decode_points(top, RecordForm::kResults);
  if (top.has("shard")) decode_shard(top, out);
  return out;
}

ComparableParts decode_comparable(const json& doc, const std::string& name) {
  ComparableParts out;
  if (!doc.is_object()) return out;
  const JsonIn top(doc, name, "");
  const bool baseline = top.has("liftcheck_baseline");
  out.points = decode_points(top, baseline ? RecordForm::kBaseline : RecordForm::kResults);
  if (baseline) {
    if (const auto o = top.opt_obj("outcomes"))
      for (const auto& [key, v] : o->value().items()) {
        if (!v.is_boolean() && !v.is_null()) o->fail(fmt::format("'{}' must be true, false or null", key));
        out.outcomes[key] = v.is_null() ? std::nullopt : std::optional<bool>(v.get<bool>());
      }
    return out;
  }
  for (std::size_t i = 0; i < top.arr_or_empty("sweeps").size(); ++i)
    if (const JsonIn s = top.element("sweeps", i); s.str_or("kind", "") == "outcomes")
      out.outcomes = outcome_flags(decode_outcomes(s));
  return out;
}

json encode_baseline(const SuiteResults& r) {
  json runs = json::array();
  for (const RunResult& run : r.runs) runs.push_back(encode_run(run, RecordForm::kBaseline));
  json outcomes = json::object();
  const auto flags = r.outcomes ? outcome_flags(*r.outcomes) : r.baseline_outcomes;
  for (const auto& [key, hit] : flags) outcomes[key] = hit ? json(*hit) : json();
  return {{"liftcheck_baseline", kResultsFormat},
          {"context", {{"liftcheck", {{"version", r.context.version}, {"commit", r.context.commit}}}}},
          {"runs", runs},
          {"points", encode_points(r.points, RecordForm::kBaseline)},
          {"outcomes", outcomes}};
}

std::string outcome_case_key(const std::string& engine, const OutcomeCase& c) {
  return fmt::format("{}/{}/a={}/b={}", engine, c.path, c.a, c.b);
}

std::map<std::string, std::optional<bool>> outcome_flags(const OutcomeSweep& o) {
  std::map<std::string, std::optional<bool>> out;
  for (const auto& e : o.engines)
    for (const auto& c : e.cases) out[outcome_case_key(e.engine, c)] = c.engine;
  return out;
}

const ScenarioInfo* SuiteResults::scenario(const std::string& name) const {
  for (const auto& s : scenarios)
    if (s.name == name) return &s;
  return nullptr;
}

const RunResult* SuiteResults::run(const std::string& sc, const std::string& engine) const {
  for (const auto& r : runs)
    if (r.scenario == sc && r.engine == engine) return &r;
  return nullptr;
}

std::vector<std::string> SuiteResults::scenario_order() const {
  std::vector<std::string> v;
  for (const auto& r : runs)
    if (std::find(v.begin(), v.end(), r.scenario) == v.end()) v.push_back(r.scenario);
  return v;
}

}  // namespace liftcheck
