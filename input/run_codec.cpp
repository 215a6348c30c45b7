// Run records as JSON, and the checks that a record read back says what its own fields give.
#include <algorithm>
#include <fmt/format.h>
#include <map>

#include "input/results_codec.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck {

using json = nlohmann::json;

json encode_metric(const Metric& m) {
  json j = {{"expected", finite_or_null(m.expected)},
            {"measured", finite_or_null(m.measured)},
            {"abs_error", finite_or_null(m.abs_error)},
            {"rel_error", finite_or_null(m.rel_error)},
            {"tolerance", finite_or_null(m.tolerance)},
            {"tolerance_kind", to_string(m.kind)},
            {"unit", m.unit},
            {"pass", m.pass}};
  if (m.floor > 0.0) j["floor"] = m.floor;
  if (m.informational) j["informational"] = true;
  return j;
}

Metric decode_metric(const JsonIn& in, const std::string& name) {
  Metric m;
  m.name = name;
  m.kind = in.one_of("tolerance_kind", {"rel", "abs"}) == 0 ? TolKind::kRelative : TolKind::kAbsolute;
  m.tolerance = in.num_or_null("tolerance");
  m.abs_error = in.num_or_null("abs_error");
  m.rel_error = m.kind == TolKind::kRelative ? in.num_or_null("rel_error") : in.opt_num_or_null("rel_error");
  m.measured = in.num_or_null("measured");
  m.expected = in.opt_num_or_null("expected");
  m.floor = in.num_or("floor", 0.0);
  m.informational = in.boolean_or("informational", false);
  m.pass = in.boolean("pass");
  m.unit = in.str_or("unit", "");
  if (m.pass != m.passes_by_figures())
    in.fail(fmt::format("'pass' is {} but its {} error {:.6g} is {} its tolerance {:.6g}", m.pass,
                        m.kind == TolKind::kRelative ? "relative" : "absolute", m.compared_error(),
                        m.pass ? "over" : "within", m.tolerance));
  return m;
}

namespace {

json encode_expectation(const Expectation& e, const Decision& d, RecordForm form) {
  json j = json::object();
  if (e.error.empty())
    j["metrics"] = e.ceilings;
  else
    j["error"] = e.error;
  if (form == RecordForm::kBaseline) return j;
  j["reason"] = e.reason;
  j["measured"] = e.measured;
  j["beyond"] = d.beyond;
  return j;
}

Expectation decode_expectation(const JsonIn& in, RecordForm form) {
  Expectation e;
  if (in.has("error")) {
    e.error = in.str("error");
    if (e.error.empty()) in.fail("'error' is empty: a listed error is the start of its message");
  } else {
    e.ceilings = in.number_map("metrics");
    if (e.ceilings.empty()) in.fail("'metrics' is empty: a listing names the metrics that may fail");
  }
  const bool reviewed = form != RecordForm::kBaseline;
  e.reason = reviewed ? in.str("reason") : in.str_or("reason", "");
  e.measured = reviewed ? in.str("measured") : in.str_or("measured", "");
  return e;
}

json encode_settings(const std::map<std::string, std::string>& s) {
  json j = json::object();
  for (const auto& [k, v] : s) j[k] = v;
  return j;
}

/// A status its metrics give: a pass needs a counted metric and none failing, a fail one failing.
void check_status(const JsonIn& in, const RunResult& r) {
  const bool counted = std::any_of(r.metrics.begin(), r.metrics.end(), [](const Metric& m) { return m.counted(); });
  const bool failing = !r.failed_metrics().empty();
  if (r.status == Status::kPass && (!counted || failing))
    in.fail(counted ? fmt::format("'status' is 'pass' but {} fails", r.failed_metrics().front())
                    : "'status' is 'pass' but no counted metric measured it");
  if (r.status == Status::kFail && !failing) in.fail("'status' is 'fail' but every counted metric passes");
}

/// The stored verdict and as_expected against decide() of the record's own fields.
void check_decision(const JsonIn& in, const RunResult& r) {
  const std::string verdict = in.str("verdict");
  const bool as_expected = in.boolean("as_expected");
  const auto parsed = parse_verdict(verdict);
  if (!parsed)
    in.fail(fmt::format("'verdict' is '{}', not one of pass|known failure|unexpected pass|fail|error|skip",
                        printable(verdict, 40)));
  if (as_expected != r.decision.as_expected)
    in.fail(fmt::format("'as_expected' is {} but its {} gives {}", as_expected,
                        r.expectation ? "listing" : "status without a listing", r.decision.as_expected));
  if (*parsed != r.decision.verdict)
    in.fail(fmt::format("'verdict' is '{}' but its fields give '{}'", verdict, to_string(r.decision.verdict)));
}

}  // namespace

json encode_run(const RunResult& r, RecordForm form) {
  json ms = json::object();
  for (const auto& m : r.metrics) ms[m.name] = encode_metric(m);
  json j = {{"scenario", r.scenario},
            {"engine", r.engine},
            {"params", r.params.to_json()},
            {"settings", encode_settings(r.settings)},
            {"status", to_string(r.status)},
            {"message", r.message},
            {"metrics", ms},
            {"verdict", to_string(r.decision.verdict)},
            {"as_expected", r.decision.as_expected},
            {"negative_control", r.negative_control},
            {"expectation", r.expectation ? encode_expectation(*r.expectation, r.decision, form) : json()}};
  if (form == RecordForm::kBaseline) return j;
  j["vehicle"] = r.vehicle;
  j["worst_ratio"] = r.metrics.empty() ? json() : finite_or_null(r.worst_ratio());
  j["worst_rel_error"] = finite_or_null(r.worst_rel_error());
  j["wall_s"] = r.wall_s;
  j["simulated_s"] = r.simulated_s;
  j["details"] = r.details;
  if (std::isfinite(r.engine_s)) j["engine_s"] = r.engine_s;
  if (form != RecordForm::kPipe) return j;
  if (r.input_error) j["input_error"] = true;
  if (!r.shared.empty()) {
    j["shared"] = json::array();
    for (const RunResult& s : r.shared) j["shared"].push_back(encode_run(s, form));
  }
  return j;
}

namespace {

Params decode_params(const JsonIn& in) {
  const json* p = in.get("params");
  if (!p->is_object()) in.fail(fmt::format("'params' is {}, not an object", json_type_of(*p)));
  try {
    return Params::from_json(*p);
  } catch (const std::invalid_argument& e) {
    in.fail(fmt::format("'params': {}", e.what()));
  }
}

void decode_fields(const JsonIn& in, RunResult& r, RecordForm form) {
  r.params = decode_params(in);
  for (const auto& [k, v] : in.text_pairs("settings")) r.settings[k] = v;
  r.message = in.str("message");
  r.negative_control = in.boolean("negative_control");
  if (const auto e = in.opt_obj("expectation")) r.expectation = decode_expectation(*e, form);
  if (form == RecordForm::kBaseline) return;
  const auto vehicle = parse_vehicle(in.str("vehicle"));
  if (!vehicle) in.fail("'vehicle' must be \"car\" or \"disks\"");
  r.vehicle = *vehicle;
  r.wall_s = in.num("wall_s");
  r.simulated_s = in.num("simulated_s");
  r.engine_s = in.num_or("engine_s", NAN);
  r.details = *in.get("details");
  if (!r.details.is_object()) in.fail("'details' must be an object");
}

}  // namespace

RunResult decode_run(const JsonIn& in_, RecordForm form) {
  JsonIn in = in_;
  RunResult r;
  r.scenario = in.str("scenario");
  r.engine = in.str("engine");
  in.name_it(r.scenario + " on " + r.engine);
  r.status = static_cast<Status>(in.one_of("status", {"pass", "fail", "error", "skip"}));
  // The fields a verdict is read from are there before any is checked against another: a record
  // without one is refused by its name.
  (void)in.str("verdict"), (void)in.boolean("as_expected");
  const json* ms = in.get("metrics");
  if (!ms->is_object()) in.fail(fmt::format("'metrics' is {}, not an object", json_type_of(*ms)));
  const JsonIn metrics = in.obj("metrics");
  for (const auto& [name, m] : ms->items()) r.metrics.push_back(decode_metric(metrics.obj(name.c_str()), name));
  decode_fields(in, r, form);
  if (r.status == Status::kPass || r.status == Status::kFail) check_status(in, r);
  r.judge();
  check_decision(in, r);
  if (form == RecordForm::kPipe) {
    r.input_error = in.boolean_or("input_error", false);
    for (std::size_t i = 0; i < in.arr_or_empty("shared").size(); ++i)
      r.shared.push_back(decode_run(in.element("shared", i), form));
  }
  return r;
}

RunResult decode_run_text(const std::string& text, const std::string& name, RecordForm form) {
  const json j = json::parse(text, nullptr, false);
  if (j.is_discarded()) throw InputError(fmt::format("{}: a record that is not JSON", name));
  return decode_run(JsonIn(j, name, "record"), form);
}

void refuse_repeated_runs(const std::vector<RunResult>& runs, const std::string& file, const std::string& array) {
  std::map<std::string, std::size_t> seen;
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const auto [at, added] = seen.emplace(run_key_of(runs[i]), i);
    if (!added)
      throw InputError(fmt::format("{}: {}[{}] repeats {}[{}]: {} is one run, given twice", file, array, i, array,
                                   at->second, printable(run_identity(runs[i]), 200)));
  }
}

}  // namespace liftcheck
