#include "input/results_file.hpp"

#include <cstdlib>
#include <fmt/format.h>
#include <exception>
#include <future>
#include <map>
#include <optional>

#include "input/read_file.hpp"
#include "input/results_codec.hpp"
#include "input/trace.hpp"

namespace liftcheck {

namespace {

using json = nlohmann::json;

constexpr char kShared[] = "shared_references";

/// The run's details.reference, or null when it has none.
json* reference_of(json& run) {
  if (!run.is_object() || !run.contains("details") || !run["details"].is_object()) return nullptr;
  json& d = run["details"];
  return d.contains("reference") ? &d["reference"] : nullptr;
}

/// Each distinct details.reference of the document's runs once, in "shared_references"; a run's
/// reference becomes {"shared": k}.
void share_references(json& doc) {
  std::map<std::string, std::size_t> index;
  json shared = json::array();
  for (auto& run : doc["runs"]) {
    json* ref = reference_of(run);
    if (!ref || !ref->is_array()) continue;
    const auto [it, added] = index.emplace(ref->dump(), shared.size());
    if (added) shared.push_back(std::move(*ref));
    *ref = json{{"shared", it->second}};
  }
  if (!shared.empty()) doc[kShared] = std::move(shared);
}

/// 9 significant digits: the shortest text nlohmann writes for the double is then at most 9 digits.
double nine_digits(double v) {
  char buf[40];
  const auto end = fmt::format_to_n(buf, sizeof buf - 1, "{:.9g}", v).out;
  *end = '\0';
  return std::strtod(buf, nullptr);
}

/// A trace's rows, every stride-th and the last, each number to 9 digits; anything else untouched.
void thin_rows(json& rows) {
  if (!rows.is_array() || rows.empty()) return;
  // Every stride-th row from the first, and the last: at most kDrawnRows in all, so that thinning
  // what was thinned keeps it as it is (merge and report write what validate wrote).
  const std::size_t n = rows.size();
  const std::size_t stride = n <= kDrawnRows ? 1 : (n - 1 + kDrawnRows - 2) / (kDrawnRows - 1);
  json kept = json::array();
  for (std::size_t i = 0; i < rows.size(); ++i) {
    if (i % stride != 0 && i + 1 != rows.size()) continue;
    json row = std::move(rows[i]);
    if (row.is_array())
      for (auto& v : row)
        if (v.is_number_float()) v = nine_digits(v.get<double>());
    kept.push_back(std::move(row));
  }
  rows = std::move(kept);
}

}  // namespace

void thin_drawn_traces(json& d) {
  if (!d.is_object()) return;
  for (const char* key : {"trace", "reference"})
    if (d.contains(key)) thin_rows(d[key]);
  if (d.contains("runs") && d["runs"].is_array())
    for (auto& r : d["runs"])
      if (r.is_object() && r.contains("trace")) thin_rows(r["trace"]);
  if (d.contains("after_contact") && d["after_contact"].is_object() && d["after_contact"].contains("reference"))
    thin_rows(d["after_contact"]["reference"]);
}

void expand_references(json& doc, const std::string& name) {
  if (!doc.is_object() || !doc.contains(kShared)) return;
  json shared = std::move(doc[kShared]);
  doc.erase(kShared);
  if (!shared.is_array()) throw InputError(fmt::format("{}: '{}' must be an array", name, kShared));
  if (!doc.contains("runs") || !doc["runs"].is_array()) return;
  std::size_t i = 0;
  for (auto& run : doc["runs"]) {
    json* ref = reference_of(run);
    ++i;
    if (!ref || !ref->is_object()) continue;
    const json k = ref->value("shared", json());
    if (!k.is_number_unsigned() || k.get<std::size_t>() >= shared.size())
      throw InputError(
          fmt::format("{}: runs[{}].details.reference: 'shared' must be an index into '{}' (below {}), not {}", name,
                      i - 1, kShared, shared.size(), printable(k.dump(), 40)));
    *ref = shared[k.get<std::size_t>()];
  }
}

std::string results_text(const SuiteResults& results) {
  json doc = encode_results(results);
  share_references(doc);  // compact and each exact lift once: 12 MB, was 48
  return doc.dump();
}

SuiteResults parse_results(const std::string& text, const std::string& name) {
  json doc = parse_json_text(text, name);
  expand_references(doc, name);
  return decode_results(doc, name);
}

SuiteResults read_results(const std::string& path) {
  require_utf8(path, "results file name");
  return parse_results(read_text_file(path, kMaxResultsBytes, "results file"), printable(path, 200));
}

namespace {

/// The runs of a document read one at a time into the figures the diff compares, each decoded and
/// checked as the full reader decodes it; what the full reader would report is reported at its
/// place among its checks (finish()).
class RunStream {
 public:
  RunStream(const std::string& name, ResultsIndex& index) : name_(name), index_(index) {}
  /// A run has ended; the document read so far holds the top level's keys before "runs".
  void take(std::size_t i, json& run, const json& so_far) {
    if (!form_) form_ = form_of(so_far);
    if (*form_ == Form::kUnknown) return buffered_.emplace_back(i, std::move(run)), void();
    figures(i, run, *form_ == Form::kBaseline ? RecordForm::kBaseline : RecordForm::kResults);
  }
  /// The runs' checks at their place (decode_results' RunsDecoder): any run buffered decoded now,
  /// the first bad run's error, then the first run given twice.
  std::vector<RunResult> finish(RecordForm form) {
    for (auto& [i, run] : buffered_) figures(i, run, form);
    buffered_.clear();
    if (bad_run_) std::rethrow_exception(bad_run_);
    if (!repeated_.empty()) throw InputError(repeated_);
    return {};
  }

 private:
  enum class Form { kUnknown, kResults, kBaseline };
  /// The form, when the format key came before "runs" (as liftcheck writes it: keys sorted).
  static Form form_of(const json& so_far) {
    if (!so_far.is_object()) return Form::kUnknown;
    if (so_far.contains("liftcheck_baseline")) return Form::kBaseline;
    return so_far.contains("liftcheck_results") ? Form::kResults : Form::kUnknown;
  }
  void figures(std::size_t i, json& run, RecordForm form) {
    if (bad_run_) return;
    try {
      const RunResult r = decode_run(JsonIn(run, name_, fmt::format("runs[{}]", i)), form);
      const auto [at, added] = seen_.emplace(run_key_of(r), i);
      if (!added && repeated_.empty())
        repeated_ = fmt::format("{}: runs[{}] repeats runs[{}]: {} is one run, given twice", name_, i, at->second,
                                printable(run_identity(r), 200));
      index_.runs.push_back(figures_of(r, pool_));
    } catch (const InputError&) {
      bad_run_ = std::current_exception();
    }
  }

  const std::string& name_;
  ResultsIndex& index_;
  SettingsPool pool_;
  std::optional<Form> form_;
  std::vector<std::pair<std::size_t, json>> buffered_;  ///< runs before the format key (none as liftcheck writes)
  std::map<std::string, std::size_t> seen_;
  std::string repeated_;
  std::exception_ptr bad_run_;
};

}  // namespace

ResultsIndex parse_results_index(std::string_view text, const std::string& name) {
  ResultsIndex index;
  RunStream stream(name, index);
  // The syntax, the depth and a repeated key stop the parse at once; the runs' checks come at their
  // place among the full reader's, as decode_results makes them.
  const json top =
      parse_json_runs(text, name, [&](std::size_t i, json& run, const json& so_far) { stream.take(i, run, so_far); });
  const SuiteResults rest =
      decode_results(top, name, [&](const JsonIn&, RecordForm form) { return stream.finish(form); });
  SettingsPool pool;
  for (const auto& [key, p] : rest.points) {
    index.points.push_back(figures_of(p, pool));
    index.points.back().point = key;
  }
  index.outcomes = rest.outcomes ? outcome_flags(*rest.outcomes) : rest.baseline_outcomes;
  return index;
}

ResultsIndex read_results_index(const std::string& path) {
  require_utf8(path, "results file name");
  return parse_results_index(read_text_file(path, kMaxResultsBytes, "results file"), printable(path, 200));
}

std::pair<ResultsIndex, ResultsIndex> read_results_index_pair(const std::string& base, const std::string& head) {
  // Read here (a blocking read is interrupted by a signal in this thread), parsed in two threads.
  require_utf8(base, "results file name");
  require_utf8(head, "results file name");
  const std::string base_text = read_text_file(base, kMaxResultsBytes, "results file");
  const std::string head_text = read_text_file(head, kMaxResultsBytes, "results file");
  auto later = std::async(std::launch::async, [&] { return parse_results_index(head_text, printable(head, 200)); });
  ResultsIndex b;
  try {
    b = parse_results_index(base_text, printable(base, 200));
  } catch (...) {
    later.wait();
    throw;
  }
  return {std::move(b), later.get()};
}

}  // namespace liftcheck
