#include "input/results_file.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <fmt/format.h>
#include <fstream>
#include <cstdlib>
#include <future>
#include <map>
#include <numeric>
#include <sstream>
#include <unordered_set>
#include <vector>

#include "input/interrupt.hpp"
#include "input/params.hpp"
#include "input/read_file.hpp"
#include "input/record_view.hpp"
#include "input/trace.hpp"

namespace liftcheck {

namespace {

using json = nlohmann::json;

/// The type of a value (a json, or a Slot of the index reader) for messages.
template <class V>
const char* type_of(const V& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean";
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return "a binary value";
}

const json* field_of(const json& obj, const char* key) {
  const auto it = obj.find(key);
  return it == obj.end() ? nullptr : &*it;
}
std::string_view text_of(const json& v) { return v.get_ref<const std::string&>(); }

/// Checks the fields of one JSON object (a json, or a SlotObject of the index reader), naming
/// `where` ("runs[3].metrics.radius") in errors.
template <class Obj>
class Fields {
 public:
  /// `run` and `metric` say where: "runs[RUN]" or "runs[RUN].metrics.METRIC" (made only for a
  /// message: a file of a million runs is checked without a string per field).
  Fields(const Obj& obj, const std::string& name, std::size_t run, const std::string* metric = nullptr)
      : obj_(obj), name_(name), run_(run), metric_(metric) {
    if (!obj_.is_object()) fail(fmt::format("is {}, not an object", type_of(obj_)));
  }
  [[noreturn]] void fail(const std::string& problem) const {
    const std::string where =
        metric_ ? fmt::format("runs[{}].metrics.{}", run_, *metric_) : fmt::format("runs[{}]", run_);
    throw InputError(fmt::format("{}: {}: {}", name_, printable(where, 160), problem));
  }
  auto get(const char* key, bool required) const {
    const auto* v = field_of(obj_, key);
    if (!v && required) fail(fmt::format("missing '{}'", key));
    return v;
  }
  template <class Ok>
  void want(const char* key, bool required, Ok ok, const char* what) const {
    if (const auto* v = get(key, required); v && !ok(*v))
      fail(fmt::format("'{}' is {}, not {}", key, type_of(*v), what));
  }
  void string(const char* key, bool required) const {
    want(
        key, required, [](const auto& v) { return v.is_string(); }, "a string");
  }
  void boolean(const char* key, bool required) const {
    want(
        key, required, [](const auto& v) { return v.is_boolean(); }, "a boolean");
  }
  void number(const char* key, bool required) const {
    want(
        key, required, [](const auto& v) { return v.is_number(); }, "a number");
  }
  /// A number, or null (liftcheck writes a NaN or an infinite error as null).
  void number_or_null(const char* key, bool required) const {
    want(
        key, required, [](const auto& v) { return v.is_number() || v.is_null(); }, "a number or null");
  }
  void one_of(const char* key, bool required, std::initializer_list<const char*> values) const {
    const auto* v = get(key, required);
    if (!v) return;
    if (!v->is_string()) fail(fmt::format("'{}' is {}, not a string", key, type_of(*v)));
    for (const char* s : values)
      if (text_of(*v) == s) return;
    std::string list;
    for (const char* s : values) {
      if (!list.empty()) list += '|';
      list += s;
    }
    fail(fmt::format("'{}' is '{}', not one of {}", key, printable(std::string(text_of(*v))), list));
  }

 private:
  const Obj& obj_;
  const std::string& name_;
  std::size_t run_;
  const std::string* metric_;
};

/// Checks run `i`'s own fields; returns its "metrics" (null when it has none), checked to be an object.
template <class Obj>
auto check_run(const Obj& r, const std::string& name, std::size_t i) {
  const Fields<Obj> run(r, name, i);
  run.string("scenario", true);
  run.string("engine", true);
  run.one_of("status", true, {"pass", "fail", "error", "skip"});
  run.string("verdict", false);
  run.boolean("as_expected", false);
  run.string("message", false);
  const auto* metrics = run.get("metrics", false);
  if (metrics && !metrics->is_object()) run.fail(fmt::format("'metrics' is {}, not an object", type_of(*metrics)));
  return metrics;
}

/// Checks metric `metric` of run `i`.
template <class Obj>
void check_metric(const Obj& m, const std::string& name, std::size_t i, const std::string& metric) {
  const Fields<Obj> f(m, name, i, &metric);
  f.one_of("tolerance_kind", true, {"rel", "abs"});
  f.number_or_null("tolerance", true);
  f.number_or_null("abs_error", true);
  f.number_or_null("rel_error", text_of(*field_of(m, "tolerance_kind")) == "rel");
  f.number_or_null("measured", true);
  f.number_or_null("expected", false);
  f.number("floor", false);
  f.boolean("informational", false);
  f.boolean("pass", false);
}

/// The checks of the top level, with the type of the document and of its "runs" (null: none).
template <class V>
void check_top(const V& top, const V* runs, const std::string& name) {
  if (!top.is_object())
    throw InputError(
        fmt::format("{}: is not a liftcheck results file (the top level is {}, not an object)", name, type_of(top)));
  if (!runs) throw InputError(fmt::format("{}: is not a liftcheck results file (no \"runs\")", name));
  if (!runs->is_array()) throw InputError(fmt::format("{}: 'runs' is {}, not an array", name, type_of(*runs)));
}

/// A value the checks and the diff read, as the parser gave it: its type and, for a scalar, its value.
struct Slot {
  json::value_t type = json::value_t::discarded;  ///< discarded: absent
  std::string text;                               ///< a string's value
  json scalar;                                    ///< a number's, a boolean's, null
  bool present() const { return type != json::value_t::discarded; }
  bool is_null() const { return type == json::value_t::null; }
  bool is_boolean() const { return type == json::value_t::boolean; }
  bool is_number() const {
    return type == json::value_t::number_integer || type == json::value_t::number_unsigned ||
           type == json::value_t::number_float;
  }
  bool is_string() const { return type == json::value_t::string; }
  bool is_array() const { return type == json::value_t::array; }
  bool is_object() const { return type == json::value_t::object; }
};
std::string_view text_of(const Slot& v) { return v.text; }

constexpr std::array<std::string_view, 7> kRunFields{"scenario",    "engine",  "status", "verdict",
                                                     "as_expected", "message", "metrics"};
constexpr std::array<std::string_view, 9> kMetricFields{
    "tolerance_kind", "tolerance", "abs_error", "rel_error", "measured", "expected", "floor", "informational", "pass"};

/// An object of which only the fields in `Names` are kept (its own type is the Slot's).
template <const auto& Names>
struct SlotObject : Slot {
  std::array<Slot, Names.size()> slots;
  Slot* slot(std::string_view key) {
    for (std::size_t i = 0; i < Names.size(); ++i)  // most keys differ in length or first letter
      if (key.size() == Names[i].size() && key[0] == Names[i][0] && key == Names[i]) return &slots[i];
    return nullptr;
  }
  const Slot* field(std::string_view key) const {
    const Slot* s = const_cast<SlotObject*>(this)->slot(key);
    return s && s->present() ? s : nullptr;
  }
  void reset(json::value_t t) {
    type = t;
    for (auto& s : slots) s.type = json::value_t::discarded;
  }
};
template <const auto& Names>
const Slot* field_of(const SlotObject<Names>& obj, const char* key) {
  return obj.field(key);
}

using RunSlots = SlotObject<kRunFields>;
using MetricSlots = SlotObject<kMetricFields>;

double number_in(const MetricSlots& m, const char* key) {
  const Slot* v = m.field(key);
  return v && v->is_number() ? v->scalar.get<double>() : INFINITY;
}

}  // namespace

void check_results(const json& j, const std::string& name) {
  check_top(j, j.is_object() ? field_of(j, "runs") : nullptr, name);
  std::size_t i = 0;
  for (const auto& r : j["runs"]) {
    if ((i & 0xFFFF) == 0xFFFF) throw_if_interrupted_by([&] { return fmt::format("while checking '{}'", name); });
    const json* metrics = check_run(r, name, i++);
    if (!metrics) continue;
    for (const auto& [metric, m] : metrics->get_ref<const json::object_t&>()) check_metric(m, name, i - 1, metric);
  }
}

namespace {

/// Reads a results file into the figures the diff compares (a ResultsIndex) in one pass of
/// nlohmann's SAX parser, without a document: it refuses what the full reader refuses, with the
/// same messages in the same order. The syntax, the nesting depth (64 levels) and a key repeated
/// in one object stop the parse at once; the checks of each run are made when it ends and the
/// first that fails is reported after the parse, then the top level's (as check_results does on
/// the document).
class IndexReader {
 public:
  IndexReader(const std::string& file, int max_depth, ResultsIndex& out)
      : file_(file), max_depth_(static_cast<std::size_t>(max_depth)), levels_(max_depth_), out_(out) {}
  bool null() { return scalar(json::value_t::null, json()); }
  bool boolean(bool v) { return scalar(json::value_t::boolean, json(v)); }
  bool number_integer(json::number_integer_t v) { return scalar(json::value_t::number_integer, json(v)); }
  bool number_unsigned(json::number_unsigned_t v) { return scalar(json::value_t::number_unsigned, json(v)); }
  bool number_float(json::number_float_t v, const std::string&) { return scalar(json::value_t::number_float, json(v)); }
  bool string(std::string& v) {
    if (Slot* s = value(json::value_t::string)) s->text.assign(v);
    return true;
  }
  bool binary(json::binary_t&) { return scalar(json::value_t::binary, json()); }
  bool start_object(std::size_t) { return open(json::value_t::object); }
  bool start_array(std::size_t) { return open(json::value_t::array); }
  bool end_object() { return close(); }
  bool end_array() { return close(); }
  bool key(std::string& k) {
    levels_[depth_ - 1].key.assign(k);
    return true;
  }
  template <class Exception>
  bool parse_error(std::size_t, const std::string&, const Exception& e) {
    throw e;
  }
  /// After the parse: the checks of the top level, then the first run's that failed.
  void finish() const {
    check_top<Slot>(top_, runs_.present() ? &runs_ : nullptr, file_);
    if (failed_) std::rethrow_exception(failed_);
  }

 private:
  /// What an open container is to the reader.
  enum class Role { other, top, runs, run, metrics, metric, settings };
  struct Level {
    bool array = false;
    Role role = Role::other;
    std::size_t count = 0;          ///< arrays: values begun
    std::string key;                ///< objects: the key being read
    std::vector<std::string> keys;  ///< objects: the keys seen (the first few)
    std::size_t n_keys = 0;
    std::unordered_set<std::string> many;  ///< all of them, once there are many
    bool use_many = false;
  };

  bool scalar(json::value_t type, json&& v) {
    if (Slot* s = value(type)) s->scalar = std::move(v);
    return true;
  }
  bool open(json::value_t type) {
    if (depth_ >= max_depth_) throw InputError(fmt::format("{}: JSON nested deeper than {} levels", file_, max_depth_));
    value(type);
    Level& l = levels_[depth_++];
    l.array = type == json::value_t::array;
    l.role = next_role_;
    l.count = l.n_keys = 0;
    if (l.use_many) l.many = {}, l.use_many = false;
    return true;
  }
  bool close() {
    if (levels_[--depth_].role == Role::run) end_run();
    return true;
  }
  /// A value begins (a scalar, or a container about to open): its key is checked, and the slot
  /// that keeps it, if any, is returned (`next_role_` says what a container will be).
  Slot* value(json::value_t type) {
    if ((++events_ & 0xFFFF) == 0)
      throw_if_interrupted_by([&] { return fmt::format("while reading '{}'", printable(file_, 200)); });
    next_role_ = Role::other;
    if (depth_ == 0) {
      top_.type = type;
      if (type == json::value_t::object) next_role_ = Role::top;
      return nullptr;
    }
    Level& p = levels_[depth_ - 1];
    if (p.array)
      ++p.count;
    else if (Slot* s = known(p)) {
      if (s->present()) twice(p.key);  // a field kept is its own record of the key
      s->type = type;
      if (p.role == Role::run && type == json::value_t::object && p.key == "metrics") next_role_ = Role::metrics;
      return s;
    } else
      take_key(p);
    if (p.role == Role::run && type == json::value_t::object && (p.key == "params" || p.key == "settings"))
      next_role_ = Role::settings;
    return in(p.role, p.key, type);
  }
  /// The slot that keeps the value of key `p.key` in object `p`, if it is kept.
  Slot* known(const Level& p) {
    if (p.role == Role::run) return run_.slot(p.key);
    if (p.role == Role::metric) return metrics_[n_metrics_ - 1].second.slot(p.key);
    return nullptr;
  }
  Slot* in(Role role, const std::string& key, json::value_t type) {
    const bool object = type == json::value_t::object;
    switch (role) {
      case Role::top:
        if (key != "runs") return nullptr;
        runs_.type = type;
        if (type == json::value_t::array) next_role_ = Role::runs;
        return nullptr;
      case Role::runs:
        run_.reset(type);
        n_metrics_ = n_settings_ = 0;
        if (object)
          next_role_ = Role::run;
        else
          end_run();
        return nullptr;
      case Role::run:  // a field not kept (known() has the kept ones)
        return nullptr;
      case Role::metrics:
        if (n_metrics_ == metrics_.size()) metrics_.emplace_back();
        metrics_[n_metrics_].first.assign(key);
        metrics_[n_metrics_++].second.reset(type);
        if (object) next_role_ = Role::metric;
        return nullptr;
      case Role::metric:
        return nullptr;
      case Role::settings:  // a parameter's or a setting's value, kept as a scalar
        if (object || type == json::value_t::array) return nullptr;
        if (n_settings_ == settings_.size()) settings_.emplace_back();
        settings_[n_settings_].first.assign(key);
        settings_[n_settings_].second.type = type;
        return &settings_[n_settings_++].second;
      case Role::other:
        break;
    }
    return nullptr;
  }
  /// The key of the value beginning in object `p`, refused when the object has it already.
  void take_key(Level& p) {
    if (p.use_many) {
      if (!p.many.insert(p.key).second) twice(p.key);
      return;
    }
    for (std::size_t k = 0; k < p.n_keys; ++k)
      if (p.keys[k] == p.key) twice(p.key);
    if (p.n_keys == 32) {
      p.many.insert(p.keys.begin(), p.keys.end());
      p.many.insert(p.key);
      p.use_many = true;
      return;
    }
    if (p.n_keys == p.keys.size())
      p.keys.push_back(p.key);
    else
      p.keys[p.n_keys].assign(p.key);
    ++p.n_keys;
  }
  [[noreturn]] void twice(const std::string& key) const {
    throw InputError(fmt::format("{}: {}: the key '{}' appears twice in one object (which one is meant?)", file_,
                                 where(), printable(key)));
  }
  /// "runs[3].metrics" for the innermost open object (as parse_json_text says it).
  std::string where() const {
    std::string w;
    for (std::size_t i = 0; i + 1 < depth_; ++i) {
      if (levels_[i].array) {
        w += fmt::format("[{}]", levels_[i].count - 1);
        continue;
      }
      if (!w.empty()) w += '.';
      w += printable(levels_[i].key, 60);
    }
    return w.empty() ? "the top level" : w;
  }
  /// A run has ended (the runs array is the innermost open level): checked, then its figures kept.
  void end_run() {
    if (failed_) return;
    const std::size_t i = levels_[depth_ - 1].count - 1;
    order_.resize(n_metrics_);
    std::iota(order_.begin(), order_.end(), std::size_t{0});
    std::sort(order_.begin(), order_.end(),
              [&](std::size_t a, std::size_t b) { return metrics_[a].first < metrics_[b].first; });
    try {
      if (check_run(run_, file_, i))
        for (const std::size_t k : order_) check_metric(metrics_[k].second, file_, i, metrics_[k].first);
    } catch (const InputError&) {
      failed_ = std::current_exception();
      return;
    }
    out_.runs.push_back(figures());
  }
  RunFigures figures() {
    RunFigures f;
    const Slot& status = *run_.field("status");
    const Slot *verdict = run_.field("verdict"), *message = run_.field("message"),
               *as_expected = run_.field("as_expected");
    f.scenario = run_.field("scenario")->text;
    f.engine = run_.field("engine")->text;
    f.verdict = verdict ? verdict->text : status.text;
    if (message) f.message = message->text;
    f.as_expected = as_expected ? as_expected->scalar.get<bool>() : status.text == "pass" || status.text == "skip";
    f.has_metrics = run_.field("metrics") != nullptr;
    std::vector<std::pair<std::string, std::string>> kv;
    for (std::size_t k = 0; k < n_settings_; ++k) {
      const Slot& v = settings_[k].second;
      kv.emplace_back(settings_[k].first, v.is_string() ? v.text : v.scalar.dump());
    }
    f.settings = interned_settings(std::move(kv), pool_);
    f.metrics.reserve(order_.size());
    for (const std::size_t k : order_) {
      const MetricSlots& m = metrics_[k].second;
      const Slot *floor = m.field("floor"), *informational = m.field("informational");
      const bool rel = m.field("tolerance_kind")->text == "rel";
      f.metrics.push_back({metrics_[k].first,
                           metric_ratio(compared_error_of(rel, number_in(m, "rel_error"), number_in(m, "abs_error")),
                                        number_in(m, "tolerance"), number_in(m, "abs_error"),
                                        floor ? floor->scalar.get<double>() : 0.0),
                           informational && informational->scalar.get<bool>(), m.field("measured")->scalar});
    }
    return f;
  }

  const std::string& file_;
  std::size_t max_depth_;
  std::vector<Level> levels_;
  std::size_t depth_ = 0;
  std::size_t events_ = 0;
  Role next_role_ = Role::other;
  Slot top_, runs_;
  RunSlots run_;
  std::vector<std::pair<std::string, MetricSlots>> metrics_;  ///< the current run's, by name
  std::size_t n_metrics_ = 0;
  std::vector<std::pair<std::string, Slot>> settings_;  ///< the current run's parameters and settings
  std::size_t n_settings_ = 0;
  SettingsPool pool_;
  std::vector<std::size_t> order_;  ///< metrics_ in name order
  std::exception_ptr failed_;
  ResultsIndex& out_;
};

}  // namespace

ResultsIndex parse_results_index(std::string_view text, const std::string& name) {
  ResultsIndex index;
  IndexReader reader(name, 64, index);
  try {
    json::sax_parse(text, &reader);
  } catch (const json::exception& e) {
    throw not_json_error(e, name);
  }
  reader.finish();
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

json parse_results(const std::string& text, const std::string& name) {
  json j = parse_json_text(text, name);
  check_results(j, name);
  expand_references(j, name);
  return j;
}

namespace {

constexpr char kShared[] = "shared_references";

/// The run's details.reference, or null when it has none.
json* reference_of(json& run) {
  if (!run.is_object() || !run.contains("details") || !run["details"].is_object()) return nullptr;
  json& d = run["details"];
  return d.contains("reference") ? &d["reference"] : nullptr;
}

}  // namespace

void share_references(json& results) {
  if (!results.contains("runs") || !results["runs"].is_array()) return;
  std::map<std::string, std::size_t> index;
  json shared = json::array();
  for (auto& run : results["runs"]) {
    json* ref = reference_of(run);
    if (!ref || !ref->is_array()) continue;
    const auto [it, added] = index.emplace(ref->dump(), shared.size());
    if (added) shared.push_back(std::move(*ref));
    *ref = json{{"shared", it->second}};
  }
  if (!shared.empty()) results[kShared] = std::move(shared);
}

namespace {

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

void thin_drawn_traces(json& results) {
  if (!results.contains("runs") || !results["runs"].is_array()) return;
  for (auto& run : results["runs"]) {
    if (!run.is_object() || !run.contains("details") || !run["details"].is_object()) continue;
    json& d = run["details"];
    for (const char* key : {"trace", "reference"})
      if (d.contains(key)) thin_rows(d[key]);
    if (d.contains("runs") && d["runs"].is_array())
      for (auto& r : d["runs"])
        if (r.is_object() && r.contains("trace")) thin_rows(r["trace"]);
    if (d.contains("after_contact") && d["after_contact"].is_object() && d["after_contact"].contains("reference"))
      thin_rows(d["after_contact"]["reference"]);
  }
}

void expand_references(json& results, const std::string& name) {
  if (!results.contains(kShared)) return;
  json shared = std::move(results[kShared]);
  results.erase(kShared);
  if (!shared.is_array()) throw InputError(fmt::format("{}: '{}' must be an array", name, kShared));
  std::size_t i = 0;
  for (auto& run : results["runs"]) {
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

json read_results(const std::string& path) {
  require_utf8(path, "results file name");
  return parse_results(read_text_file(path, kMaxResultsBytes, "results file"), printable(path, 200));
}

std::pair<json, json> read_results_pair(const std::string& base, const std::string& head) {
  // Read here (a blocking read is interrupted by a signal in this thread), parsed in two threads:
  // parsing is most of a diff's time, and both threads check for an interruption as they go.
  require_utf8(base, "results file name");
  require_utf8(head, "results file name");
  const std::string base_text = read_text_file(base, kMaxResultsBytes, "results file");
  const std::string head_text = read_text_file(head, kMaxResultsBytes, "results file");
  auto later = std::async(std::launch::async, [&] { return parse_results(head_text, printable(head, 200)); });
  json b;
  try {
    b = parse_results(base_text, printable(base, 200));
  } catch (...) {
    later.wait();
    throw;
  }
  return {std::move(b), later.get()};
}

}  // namespace liftcheck
