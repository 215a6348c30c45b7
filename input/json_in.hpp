// Decoding a JSON object into typed fields, each read checked for presence and type: a field that
// is missing or of another type is an InputError naming the file, where in it, and the problem
// ("results.json: runs[3].metrics.radius: missing 'rel_error'"). The one place that reads a
// document by key (input/results_codec.hpp uses it).
#pragma once

#include <map>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "input/params.hpp"  // InputError

namespace liftcheck {

/// "a number", "a string", ... for messages.
const char* json_type_of(const nlohmann::json& v);

class JsonIn {
 public:
  /// `file` names the document, `where` the object in it ("runs[3]"); `who` names what the object
  /// is at the end of a message ("car.circle on ode"), once known.
  JsonIn(const nlohmann::json& j, const std::string& file, std::string where);

  [[noreturn]] void fail(const std::string& problem) const;
  /// Names what the object is in its messages from now on.
  void name_it(std::string who) { who_ = std::move(who); }
  const std::string& where() const { return where_; }
  const nlohmann::json& value() const { return *j_; }

  bool has(const char* key) const;
  /// The field; missing: fail, or null when `required` is false.
  const nlohmann::json* get(const char* key, bool required = true) const;
  std::string str(const char* key) const;
  std::string str_or(const char* key, const std::string& none) const;
  double num(const char* key) const;
  double num_or(const char* key, double none) const;
  /// A number or null (liftcheck writes a NaN or infinite figure as null): NaN for null.
  double num_or_null(const char* key) const;
  /// The same, and NaN when absent.
  double opt_num_or_null(const char* key) const;
  int integer(const char* key) const;
  int integer_or(const char* key, int none) const;
  bool boolean(const char* key) const;
  bool boolean_or(const char* key, bool none) const;
  /// A field that must be one of `values`; its index.
  std::size_t one_of(const char* key, std::initializer_list<const char*> values) const;
  JsonIn obj(const char* key) const;
  std::optional<JsonIn> opt_obj(const char* key) const;
  const nlohmann::json& arr(const char* key) const;
  const nlohmann::json& arr_or_empty(const char* key) const;
  std::vector<std::string> strings(const char* key) const;
  std::vector<std::string> strings_or_empty(const char* key) const;
  std::vector<double> numbers(const char* key) const;
  /// An object of numbers (or nulls, as NaN).
  std::map<std::string, double> number_map(const char* key, bool required = true) const;
  /// An object of strings (or of scalars, as their text), in key order.
  std::vector<std::pair<std::string, std::string>> text_pairs(const char* key, bool required = true) const;
  /// An element of array field `key` as an object.
  JsonIn element(const char* key, std::size_t i) const;

 private:
  std::string type_problem(const char* key, const nlohmann::json& v, const char* want) const;
  const nlohmann::json* j_;
  const std::string* file_;
  std::string where_, who_;
};

/// A scalar as text: a string's value, a number's shortest JSON.
std::string scalar_text(const nlohmann::json& v);
/// A double as results.json writes it: a number, or null when it is not finite.
inline nlohmann::json finite_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

}  // namespace liftcheck
