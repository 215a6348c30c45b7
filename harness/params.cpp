#include "harness/params.hpp"

#include <charconv>
#include <cmath>
#include <fmt/format.h>

namespace liftcheck {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

double parse_number(const std::string& key, const std::string& text) {
  const std::string t = trim(text);
  double v = 0.0;
  const char* first = t.data();
  const char* last = t.data() + t.size();
  if (!t.empty() && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (t.empty() || ec != std::errc() || ptr != last || !std::isfinite(v))
    throw InputError(fmt::format("parameter '{}' needs a finite number, got '{}'", key, text));
  return v;
}

void check_range(const ParamSpec& s, double v) {
  const bool low = s.min_exclusive ? !(v > s.min) : !(v >= s.min);
  if (low)
    throw InputError(fmt::format("parameter '{}' must be {} {} (got {})", s.key,
                                 s.min_exclusive ? ">" : ">=", s.min, v));
  if (!(v <= s.max)) throw InputError(fmt::format("parameter '{}' must be <= {} (got {})", s.key, s.max, v));
}

ParamValue parse_value(const ParamSpec& s, const std::string& text) {
  switch (s.kind) {
    case ParamKind::kNumber: {
      const double v = parse_number(s.key, text);
      check_range(s, v);
      return v;
    }
    case ParamKind::kInteger: {
      const double v = parse_number(s.key, text);
      if (v != std::floor(v)) throw InputError(fmt::format("parameter '{}' needs a whole number, got '{}'", s.key, text));
      check_range(s, v);
      return v;
    }
    case ParamKind::kVec2: {
      const auto comma = text.find(',');
      if (comma == std::string::npos || text.find(',', comma + 1) != std::string::npos)
        throw InputError(fmt::format("parameter '{}' needs two numbers 'x,y', got '{}'", s.key, text));
      return Eigen::Vector2d(parse_number(s.key, text.substr(0, comma)), parse_number(s.key, text.substr(comma + 1)));
    }
    case ParamKind::kChoice: {
      const std::string t = trim(text);
      for (const auto& c : s.choices)
        if (c == t) return t;
      throw InputError(fmt::format("parameter '{}' must be one of {}, got '{}'", s.key, fmt::join(s.choices, "|"), text));
    }
  }
  throw InputError("unreachable parameter kind");
}

}  // namespace

nlohmann::json ParamSpec::to_json() const {
  static const char* kinds[] = {"number", "integer", "vec2", "choice"};
  nlohmann::json j{{"key", key}, {"kind", kinds[static_cast<int>(kind)]}, {"default", default_text},
                   {"unit", unit}, {"help", help}};
  if (std::isfinite(min)) j["min"] = min, j["min_exclusive"] = min_exclusive;
  if (std::isfinite(max)) j["max"] = max;
  if (!choices.empty()) j["choices"] = choices;
  return j;
}

Params Params::resolve(const std::vector<ParamSpec>& specs,
                       const Overrides& overrides,
                       const std::string& scenario) {
  Params p;
  for (const auto& s : specs) p.values_[s.key] = parse_value(s, s.default_text);
  for (const auto& [key, text] : overrides) {
    const ParamSpec* spec = nullptr;
    for (const auto& s : specs)
      if (s.key == key) spec = &s;
    if (!spec) throw InputError(fmt::format("unknown parameter '{}' for scenario '{}'", key, scenario));
    p.values_[key] = parse_value(*spec, text);
  }
  return p;
}

double Params::num(const std::string& key) const { return std::get<double>(values_.at(key)); }
Eigen::Vector2d Params::vec(const std::string& key) const { return std::get<Eigen::Vector2d>(values_.at(key)); }
const std::string& Params::str(const std::string& key) const { return std::get<std::string>(values_.at(key)); }

nlohmann::json Params::to_json() const {
  nlohmann::json j = nlohmann::json::object();
  for (const auto& [k, v] : values_) {
    if (const double* d = std::get_if<double>(&v)) j[k] = *d;
    else if (const auto* e = std::get_if<Eigen::Vector2d>(&v)) j[k] = {(*e)[0], (*e)[1]};
    else j[k] = std::get<std::string>(v);
  }
  return j;
}

std::pair<std::string, std::string> split_assignment(const std::string& arg) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos || eq == 0)
    throw InputError(fmt::format("--set needs KEY=VALUE, got '{}'", arg));
  return {trim(arg.substr(0, eq)), arg.substr(eq + 1)};
}

}  // namespace liftcheck
