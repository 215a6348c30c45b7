// The typed results (input/run_result.hpp, input/suite_result.hpp) as JSON: encoded once where
// they leave (results.json, a shard, a baseline, the worker's pipe) and decoded once where they
// enter. Decoding is strict: a field a verdict depends on that is missing, of another type, or
// disagreeing with the others (a failing metric marked pass, a status its metrics do not give, a
// verdict or `as_expected` its listing does not give, a run given twice) is an InputError naming
// the file, the run and the field. Nothing decisive is defaulted.
#pragma once

#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <utility>

#include "input/json_in.hpp"
#include "input/suite_result.hpp"

namespace liftcheck {

/// The format of results.json and baselines this liftcheck writes and reads ("liftcheck_results",
/// "liftcheck_baseline"): 2 since records carry what decides their verdicts.
inline constexpr int kResultsFormat = 2;

/// Where a run record is read from or written to: what it holds.
enum class RecordForm {
  kResults,   ///< results.json (and a shard's points): everything but the pipe's own fields
  kPipe,      ///< a worker's record: kResults and `input_error`, `shared`
  kBaseline,  ///< a baseline: what a regression gate compares (no details, timings or reasons)
};

nlohmann::json encode_metric(const Metric& m);
Metric decode_metric(const JsonIn& in, const std::string& name);

nlohmann::json encode_run(const RunResult& r, RecordForm form = RecordForm::kResults);
/// A run record, its verdict checked against decide(). `in` names where it is ("runs[3]").
RunResult decode_run(const JsonIn& in, RecordForm form = RecordForm::kResults);
/// A record from text (the worker's pipe): InputError naming `name` when it is not one.
RunResult decode_run_text(const std::string& text, const std::string& name, RecordForm form = RecordForm::kPipe);

/// Refuses a run key given twice among `runs` (file `file`, its array `array`): names the run and
/// both positions.
void refuse_repeated_runs(const std::vector<RunResult>& runs, const std::string& file, const std::string& array);

nlohmann::json encode_context(const SuiteContext& c);
/// One configuration of a context.
nlohmann::json encode_engine_context(const EngineContext& e);
/// A tune table entry (data/tune/table.json, context.tune_table).
TuneEntry decode_tune_entry(const JsonIn& in);
SuiteContext decode_context(const JsonIn& in);

nlohmann::json encode_scenario(const ScenarioInfo& s);
ScenarioInfo decode_scenario(const JsonIn& in);

nlohmann::json encode_sweep(const Sweep& s);
Sweep decode_sweep(const JsonIn& in);
nlohmann::json encode_outcomes(const OutcomeSweep& o);
OutcomeSweep decode_outcomes(const JsonIn& in);
nlohmann::json encode_map(const SpeedMap& m);
SpeedMap decode_map(const JsonIn& in);

nlohmann::json encode_report(const ReportInfo& r);
ReportInfo decode_report(const JsonIn& in);
nlohmann::json encode_diff(const ResultsDiff& d);
ResultsDiff decode_diff(const JsonIn& in);
nlohmann::json encode_simulated(const SimulatedBudget& s);
SimulatedBudget decode_simulated(const JsonIn& in);

/// results.json: {"context", "summary" (written for readers, recomputed on reading), "scenarios",
/// "runs", "sweeps", "maps", "simulated", "report", "baseline", "shard", "plan", "points"}.
nlohmann::json encode_results(const SuiteResults& results);
/// A results document, every record checked; `name` names it in errors.
SuiteResults decode_results(const nlohmann::json& doc, const std::string& name);
/// The same, the runs decoded by `runs` (the index reader of `diff` decodes them as it reads them)
/// at their place among the checks: after the format and the context, before the rest.
using RunsDecoder = std::function<std::vector<RunResult>(const JsonIn& top, RecordForm form)>;
SuiteResults decode_results(const nlohmann::json& doc, const std::string& name, const RunsDecoder& runs);
/// The form a document's runs are in ("liftcheck_baseline": the baseline form), once its format
/// is checked; InputError for another format.
RecordForm document_form(const JsonIn& top, const std::string& name);
/// The runs of `top` decoded in `form`, none given twice.
std::vector<RunResult> decode_runs(const JsonIn& top, RecordForm form, const std::string& name);

/// What a regression gate compares besides the runs, from a results or baseline document (its runs
/// left out): the points' records (their decisive fields) and the outcome grid's cases.
struct ComparableParts {
  std::map<std::string, RunResult> points;
  std::map<std::string, std::optional<bool>> outcomes;
};
ComparableParts decode_comparable(const nlohmann::json& doc, const std::string& name);

/// A baseline: {"liftcheck_baseline": 2, "context": {"liftcheck"}, "runs", "points"} with the
/// records in their baseline form.
nlohmann::json encode_baseline(const SuiteResults& results);

}  // namespace liftcheck
