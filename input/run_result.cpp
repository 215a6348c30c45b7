#include "input/run_result.hpp"

#include <algorithm>
#include <fmt/format.h>

namespace liftcheck {

const char* to_string(Status s) {
  switch (s) {
    case Status::kPass:
      return "pass";
    case Status::kFail:
      return "fail";
    case Status::kError:
      return "error";
    case Status::kSkip:
      return "skip";
  }
  return "error";
}

std::optional<Status> parse_status(std::string_view text) {
  for (Status s : {Status::kPass, Status::kFail, Status::kError, Status::kSkip})
    if (text == to_string(s)) return s;
  return std::nullopt;
}

const char* to_string(Verdict v) {
  switch (v) {
    case Verdict::kPass:
      return "pass";
    case Verdict::kKnownFailure:
      return "known failure";
    case Verdict::kUnexpectedPass:
      return "unexpected pass";
    case Verdict::kFail:
      return "fail";
    case Verdict::kError:
      return "error";
    case Verdict::kSkip:
      return "skip";
  }
  return "error";
}

std::optional<Verdict> parse_verdict(std::string_view text) {
  for (Verdict v : {Verdict::kPass, Verdict::kKnownFailure, Verdict::kUnexpectedPass, Verdict::kFail, Verdict::kError,
                    Verdict::kSkip})
    if (text == to_string(v)) return v;
  return std::nullopt;
}

double metric_ratio(double error, double tolerance, double abs_error, double floor) {
  const auto inf = [](double v) { return std::isnan(v) ? INFINITY : v; };
  error = inf(error), abs_error = inf(abs_error);
  if (std::isnan(tolerance)) tolerance = 0.0;
  double r = tolerance > 0 ? error / tolerance : (error > 0 ? INFINITY : 0.0);
  if (floor > 0.0) r = std::min(r, abs_error / floor);
  return r;
}

bool Metric::passes_by_figures() const {
  const double err = compared_error();
  return (std::isfinite(err) && err <= tolerance) || (std::isfinite(abs_error) && abs_error <= floor);
}

bool Metric::operator==(const Metric& o) const {
  // NaN figures (null in a file) are equal to each other: two records of one run compare equal.
  const auto same = [](double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); };
  return name == o.name && unit == o.unit && same(expected, o.expected) && same(measured, o.measured) &&
         same(abs_error, o.abs_error) && same(rel_error, o.rel_error) && same(tolerance, o.tolerance) &&
         kind == o.kind && pass == o.pass && floor == o.floor && informational == o.informational;
}

std::vector<std::string> beyond_ceilings(const Ceilings& ceilings,
                                         const std::vector<std::pair<std::string, double>>& failed) {
  std::vector<std::string> problems;
  for (const auto& [name, error] : failed) {
    const auto it = ceilings.find(name);
    if (it == ceilings.end())
      problems.push_back(fmt::format("{} fails but is not among the known failure's metrics", name));
    else if (!(error <= it->second))
      problems.push_back(fmt::format("{} error {:.3g} is above its known ceiling {:.3g}", name, error, it->second));
  }
  return problems;
}

namespace {

/// How a run's metrics exceed a listing of metrics: failures beyond the ceilings, and listed
/// metrics that were not measured (or not counted), which would hide the failure they list.
std::vector<std::string> beyond_listing(const VerdictInputs& in) {
  std::vector<std::pair<std::string, double>> failed;
  for (const auto& m : in.metrics)
    if (!m.pass && m.counted) failed.emplace_back(std::string(m.name), m.compared_error);
  std::vector<std::string> problems = beyond_ceilings(in.expectation->ceilings, failed);
  for (const auto& listed : in.expectation->ceilings) {
    const std::string& name = listed.first;
    if (std::none_of(in.metrics.begin(), in.metrics.end(),
                     [&](const VerdictInputs::Figure& m) { return m.name == name && m.counted; }))
      problems.push_back(fmt::format("{} is listed but was not measured", name));
  }
  return problems;
}

bool any_failed(const VerdictInputs& in) {
  return std::any_of(in.metrics.begin(), in.metrics.end(),
                     [](const VerdictInputs::Figure& m) { return !m.pass && m.counted; });
}

Verdict unlisted_verdict(Status s) {
  return s == Status::kPass ? Verdict::kPass : s == Status::kFail ? Verdict::kFail : Verdict::kError;
}

}  // namespace

Decision decide(const VerdictInputs& in) {
  Decision d;
  if (in.status == Status::kSkip) return {Verdict::kSkip, true, {}};
  const Expectation* e = in.expectation;
  if (!e) {
    if (in.negative_control) {  // must fail: a pass means the scenario no longer sees what it is built to see
      if (in.status == Status::kFail) return {Verdict::kKnownFailure, true, {}};
      return {in.status == Status::kPass ? Verdict::kUnexpectedPass : Verdict::kError, false, {}};
    }
    return {unlisted_verdict(in.status), in.status == Status::kPass, {}};
  }
  if (!e->error.empty()) {
    const bool as_listed = in.status == Status::kError && in.message.substr(0, e->error.size()) == e->error;
    if (as_listed) return {Verdict::kKnownFailure, true, {}};
    if (in.status == Status::kPass) return {Verdict::kUnexpectedPass, false, {}};
    return {unlisted_verdict(in.status), false, {}};
  }
  d.beyond = beyond_listing(in);
  if (in.status == Status::kPass) return {Verdict::kUnexpectedPass, false, std::move(d.beyond)};
  if (in.status == Status::kError) return {Verdict::kError, false, std::move(d.beyond)};
  d.as_expected = any_failed(in) && d.beyond.empty();
  d.verdict = d.as_expected ? Verdict::kKnownFailure : Verdict::kFail;
  return d;
}

VerdictInputs RunResult::verdict_inputs() const {
  VerdictInputs in;
  in.status = status;
  in.message = message;
  in.expectation = expectation ? &*expectation : nullptr;
  in.negative_control = negative_control;
  in.metrics.reserve(metrics.size());
  for (const Metric& m : metrics) in.metrics.push_back({m.name, m.compared_error(), m.pass, m.counted()});
  return in;
}

void RunResult::judge() { decision = decide(verdict_inputs()); }

std::vector<std::string> RunResult::failed_metrics() const {
  std::vector<std::string> out;
  for (const auto& m : metrics)
    if (!m.pass && m.counted()) out.push_back(m.name);
  return out;
}

const Metric* RunResult::metric(std::string_view name) const {
  for (const auto& m : metrics)
    if (m.name == name) return &m;
  return nullptr;
}

std::vector<const Metric*> RunResult::metrics_worst_first() const {
  std::vector<const Metric*> out;
  for (const auto& m : metrics) out.push_back(&m);
  std::sort(out.begin(), out.end(), [](const Metric* a, const Metric* b) { return a->name < b->name; });
  std::stable_sort(out.begin(), out.end(), [](const Metric* a, const Metric* b) { return a->ratio() > b->ratio(); });
  return out;
}

double RunResult::worst_ratio() const {
  double worst = 0.0;
  for (const auto& m : metrics)
    if (m.counted()) worst = std::max(worst, m.ratio());
  return worst;
}

double RunResult::worst_rel_error() const {
  double worst = NAN;
  for (const auto& m : metrics)
    if (m.kind == TolKind::kRelative && std::isfinite(m.rel_error))
      worst = std::isnan(worst) ? m.rel_error : std::max(worst, m.rel_error);
  return worst;
}

std::string run_identity(const RunResult& r) {
  std::string changed;
  for (const auto& [key, value] : r.settings)
    changed += fmt::format("{}{}={}", changed.empty() ? "" : ", ", key, value);
  return fmt::format("{} on {}{}", r.scenario, r.engine, changed.empty() ? "" : " (" + changed + ")");
}

std::string run_key_of(const RunResult& r) {
  std::string key = r.scenario + '\x1f' + r.engine;
  key += '\x1e' + r.params.to_json().dump();
  for (const auto& [k, v] : r.settings) key += '\x1e' + k + '\x1f' + v;
  return key;
}

RunResult error_result(const std::string& scenario, const std::string& engine, Vehicle vehicle,
                       const std::string& message) {
  RunResult r;
  r.scenario = scenario;
  r.engine = engine;
  r.vehicle = vehicle;
  r.status = Status::kError;
  r.message = message;
  r.judge();
  return r;
}

}  // namespace liftcheck
