#include "input/results_file.hpp"

#include <fmt/format.h>
#include <fstream>
#include <future>
#include <sstream>

#include "input/interrupt.hpp"
#include "input/params.hpp"
#include "input/read_file.hpp"
#include "input/trace.hpp"

namespace liftcheck {

namespace {

using json = nlohmann::json;

const char* type_of(const json& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean";
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return "a binary value";
}

/// Checks the fields of one JSON object, naming `where` ("runs[3].metrics.radius") in errors.
class Fields {
 public:
  Fields(const json& obj, std::string name, std::string where) : obj_(obj), name_(std::move(name)), where_(std::move(where)) {
    if (!obj_.is_object()) fail(fmt::format("is {}, not an object", type_of(obj_)));
  }
  [[noreturn]] void fail(const std::string& problem) const {
    throw InputError(fmt::format("{}: {}: {}", name_, printable(where_, 160), problem));
  }
  const json* get(const char* key, bool required) const {
    const auto it = obj_.find(key);
    if (it == obj_.end()) {
      if (required) fail(fmt::format("missing '{}'", key));
      return nullptr;
    }
    return &*it;
  }
  void want(const char* key, bool required, bool (*ok)(const json&), const char* what) const {
    if (const json* v = get(key, required); v && !ok(*v)) fail(fmt::format("'{}' is {}, not {}", key, type_of(*v), what));
  }
  void string(const char* key, bool required) const { want(key, required, [](const json& v) { return v.is_string(); }, "a string"); }
  void boolean(const char* key, bool required) const { want(key, required, [](const json& v) { return v.is_boolean(); }, "a boolean"); }
  void number(const char* key, bool required) const { want(key, required, [](const json& v) { return v.is_number(); }, "a number"); }
  /// A number, or null (liftcheck writes a NaN or an infinite error as null).
  void number_or_null(const char* key, bool required) const {
    want(key, required, [](const json& v) { return v.is_number() || v.is_null(); }, "a number or null");
  }
  void one_of(const char* key, bool required, std::initializer_list<const char*> values) const {
    const json* v = get(key, required);
    if (!v) return;
    if (!v->is_string()) fail(fmt::format("'{}' is {}, not a string", key, type_of(*v)));
    for (const char* s : values)
      if (*v == s) return;
    std::string list;
    for (const char* s : values) {
      if (!list.empty()) list += '|';
      list += s;
    }
    fail(fmt::format("'{}' is '{}', not one of {}", key, printable(v->get<std::string>()), list));
  }

 private:
  const json& obj_;
  std::string name_, where_;
};

}  // namespace

void check_results(const json& j, const std::string& name) {
  if (!j.is_object()) throw InputError(fmt::format("{}: is not a liftcheck results file (the top level is {}, not an object)", name, type_of(j)));
  if (!j.contains("runs")) throw InputError(fmt::format("{}: is not a liftcheck results file (no \"runs\")", name));
  if (!j["runs"].is_array()) throw InputError(fmt::format("{}: 'runs' is {}, not an array", name, type_of(j["runs"])));
  std::size_t i = 0;
  for (const auto& r : j["runs"]) {
    if ((i & 0xFFFF) == 0xFFFF) throw_if_interrupted_by([&] { return fmt::format("while checking '{}'", name); });
    const std::string where = fmt::format("runs[{}]", i++);
    const Fields run(r, name, where);
    run.string("scenario", true);
    run.string("engine", true);
    run.one_of("status", true, {"pass", "fail", "error", "skip"});
    run.string("verdict", false);
    run.boolean("as_expected", false);
    run.string("message", false);
    const json* metrics = run.get("metrics", false);
    if (!metrics) continue;
    if (!metrics->is_object()) run.fail(fmt::format("'metrics' is {}, not an object", type_of(*metrics)));
    for (const auto& [metric, m] : metrics->items()) {
      const Fields f(m, name, fmt::format("{}.metrics.{}", where, metric));
      f.one_of("tolerance_kind", true, {"rel", "abs"});
      f.number_or_null("tolerance", true);
      f.number_or_null("abs_error", true);
      f.number_or_null("rel_error", m["tolerance_kind"] == "rel");
      f.number_or_null("measured", true);
      f.number_or_null("expected", false);
      f.number("floor", false);
      f.boolean("informational", false);
      f.boolean("pass", false);
    }
  }
}

json parse_results(const std::string& text, const std::string& name) {
  json j = parse_json_text(text, name);
  check_results(j, name);
  return j;
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
