#include "input/json_in.hpp"

#include <cmath>
#include <fmt/format.h>

#include "input/trace.hpp"  // printable

namespace liftcheck {

using json = nlohmann::json;

const char* json_type_of(const json& v) {
  if (v.is_null()) return "null";
  if (v.is_boolean()) return "a boolean";
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return "a binary value";
}

std::string scalar_text(const json& v) { return v.is_string() ? v.get<std::string>() : v.dump(); }

JsonIn::JsonIn(const json& j, const std::string& file, std::string where)
    : j_(&j), file_(&file), where_(std::move(where)) {
  if (!j.is_object()) fail(fmt::format("is {}, not an object", json_type_of(j)));
}

void JsonIn::fail(const std::string& problem) const {
  const std::string where = where_.empty() ? "" : printable(where_, 160) + ": ";  // the top level: none
  throw InputError(
      fmt::format("{}: {}{}{}", *file_, where, problem, who_.empty() ? "" : " (" + printable(who_, 160) + ")"));
}

std::string JsonIn::type_problem(const char* key, const json& v, const char* want) const {
  return fmt::format("'{}' is {}, not {}", printable(key, 60), json_type_of(v), want);
}

bool JsonIn::has(const char* key) const { return j_->contains(key); }

const json* JsonIn::get(const char* key, bool required) const {
  const auto it = j_->find(key);
  if (it != j_->end()) return &*it;
  if (required) fail(fmt::format("missing '{}'", printable(key, 60)));
  return nullptr;
}

std::string JsonIn::str(const char* key) const {
  const json& v = *get(key);
  if (!v.is_string()) fail(type_problem(key, v, "a string"));
  return v.get<std::string>();
}

std::string JsonIn::str_or(const char* key, const std::string& none) const { return has(key) ? str(key) : none; }

double JsonIn::num(const char* key) const {
  const json& v = *get(key);
  if (!v.is_number()) fail(type_problem(key, v, "a number"));
  return v.get<double>();
}

double JsonIn::num_or(const char* key, double none) const { return has(key) ? num(key) : none; }

double JsonIn::num_or_null(const char* key) const {
  const json& v = *get(key);
  if (v.is_null()) return NAN;
  if (!v.is_number()) fail(type_problem(key, v, "a number or null"));
  return v.get<double>();
}

double JsonIn::opt_num_or_null(const char* key) const { return has(key) ? num_or_null(key) : NAN; }

int JsonIn::integer(const char* key) const {
  const json& v = *get(key);
  if (!v.is_number_integer()) fail(type_problem(key, v, "a whole number"));
  const auto n = v.get<long long>();
  if (n < -2147483647LL || n > 2147483647LL) fail(fmt::format("'{}' is {}, out of range", key, n));
  return static_cast<int>(n);
}

int JsonIn::integer_or(const char* key, int none) const { return has(key) ? integer(key) : none; }

bool JsonIn::boolean(const char* key) const {
  const json& v = *get(key);
  if (!v.is_boolean()) fail(type_problem(key, v, "a boolean"));
  return v.get<bool>();
}

bool JsonIn::boolean_or(const char* key, bool none) const { return has(key) ? boolean(key) : none; }

std::size_t JsonIn::one_of(const char* key, std::initializer_list<const char*> values) const {
  const std::string s = str(key);
  std::size_t i = 0;
  for (const char* v : values) {
    if (s == v) return i;
    ++i;
  }
  fail(fmt::format("'{}' is '{}', not one of {}", key, printable(s), fmt::join(values, "|")));
}

JsonIn JsonIn::obj(const char* key) const {
  const json& v = *get(key);
  if (!v.is_object()) fail(type_problem(key, v, "an object"));
  JsonIn in(v, *file_, where_.empty() ? std::string(key) : where_ + "." + key);
  in.who_ = who_;
  return in;
}

std::optional<JsonIn> JsonIn::opt_obj(const char* key) const {
  if (!has(key) || (*j_)[key].is_null()) return std::nullopt;
  return obj(key);
}

const json& JsonIn::arr(const char* key) const {
  const json& v = *get(key);
  if (!v.is_array()) fail(type_problem(key, v, "an array"));
  return v;
}

const json& JsonIn::arr_or_empty(const char* key) const {
  static const json empty = json::array();
  return has(key) ? arr(key) : empty;
}

std::vector<std::string> JsonIn::strings(const char* key) const {
  std::vector<std::string> out;
  for (const auto& v : arr(key)) {
    if (!v.is_string()) fail(fmt::format("'{}' must be an array of strings", key));
    out.push_back(v.get<std::string>());
  }
  return out;
}

std::vector<std::string> JsonIn::strings_or_empty(const char* key) const {
  return has(key) ? strings(key) : std::vector<std::string>{};
}

std::vector<double> JsonIn::numbers(const char* key) const {
  std::vector<double> out;
  for (const auto& v : arr(key)) {
    if (!v.is_number()) fail(fmt::format("'{}' must be an array of numbers", key));
    out.push_back(v.get<double>());
  }
  return out;
}

std::map<std::string, double> JsonIn::number_map(const char* key, bool required) const {
  std::map<std::string, double> out;
  const json* v = get(key, required);
  if (!v) return out;
  if (!v->is_object()) fail(type_problem(key, *v, "an object"));
  for (const auto& [k, x] : v->items()) {
    if (!x.is_number() && !x.is_null()) fail(fmt::format("'{}.{}' is {}, not a number", key, k, json_type_of(x)));
    out[k] = x.is_null() ? NAN : x.get<double>();
  }
  return out;
}

std::vector<std::pair<std::string, std::string>> JsonIn::text_pairs(const char* key, bool required) const {
  std::vector<std::pair<std::string, std::string>> out;
  const json* v = get(key, required);
  if (!v) return out;
  if (!v->is_object()) fail(type_problem(key, *v, "an object"));
  for (const auto& [k, x] : v->items()) {
    if (x.is_structured()) fail(fmt::format("'{}.{}' is {}, not a value", key, k, json_type_of(x)));
    out.emplace_back(k, scalar_text(x));
  }
  return out;
}

JsonIn JsonIn::element(const char* key, std::size_t i) const {
  JsonIn in(arr(key).at(i), *file_, fmt::format("{}{}{}[{}]", where_, where_.empty() ? "" : ".", key, i));
  in.who_ = who_;
  return in;
}

}  // namespace liftcheck
