#include "input/params.hpp"

#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "input/suggest.hpp"

namespace liftcheck {

namespace {

std::string trim(const std::string& s) {
  const auto b = s.find_first_not_of(" \t");
  const auto e = s.find_last_not_of(" \t");
  return b == std::string::npos ? std::string() : s.substr(b, e - b + 1);
}

/// A bound as a user reads it: 1e+04 rather than 10000.000000.
std::string bound(double v) { return fmt::format("{:g}", v); }

/// "> 0 and <= 10", ">= 1", "<= 5": the valid range of a number.
std::string range_text(const ParamSpec& s) {
  std::string lo, hi;
  if (std::isfinite(s.min)) lo = fmt::format("{} {}", s.min_exclusive ? ">" : ">=", bound(s.min));
  if (std::isfinite(s.max)) hi = fmt::format("<= {}", bound(s.max));
  if (lo.empty()) return hi.empty() ? "finite" : hi;
  return hi.empty() ? lo : lo + " and " + hi;
}

/// Text as one finite double: the whole text (spaces around it aside) must be the number.
double parse_number(const std::string& key, const std::string& text, const std::string& what = "") {
  const std::string t = trim(text);
  double v = 0.0;
  const char* first = t.data();
  const char* last = t.data() + t.size();
  if (!t.empty() && *first == '+') ++first;
  const auto [ptr, ec] = std::from_chars(first, last, v);
  const std::string where =
      what.empty() ? fmt::format("parameter '{}'", key) : fmt::format("parameter '{}' ({})", key, what);
  if (!t.empty() && ec == std::errc::result_out_of_range && ptr == last)
    throw InputError(fmt::format("{} needs a finite number, got '{}': too large or too small in magnitude for a double",
                                 where, text));
  if (t.empty() || ec != std::errc() || ptr != last)
    throw InputError(fmt::format("{} needs a finite number, got '{}'", where, text));
  if (!std::isfinite(v)) throw InputError(fmt::format("{} needs a finite number, got '{}' (not finite)", where, text));
  return v;
}

bool in_range(const ParamSpec& s, double v) {
  const bool low = s.min_exclusive ? !(v > s.min) : !(v >= s.min);
  return !low && v <= s.max;
}

void check_range(const ParamSpec& s, double v, const std::string& text) {
  if (!in_range(s, v))
    throw InputError(fmt::format("parameter '{}' must be {}{}, got '{}'", s.key, range_text(s),
                                 s.unit.empty() || s.unit == "1" ? "" : " " + s.unit, trim(text)));
}

ParamValue parse_value(const ParamSpec& s, const std::string& text) {
  switch (s.kind) {
    case ParamKind::kNumber: {
      const double v = parse_number(s.key, text);
      check_range(s, v, text);
      return v;
    }
    case ParamKind::kInteger: {
      const double v = parse_number(s.key, text);
      if (v != std::floor(v))
        throw InputError(fmt::format("parameter '{}' needs a whole number, got '{}'", s.key, text));
      check_range(s, v, text);
      return v;
    }
    case ParamKind::kVec2: {
      std::vector<std::string> parts;
      std::size_t from = 0;
      for (std::size_t comma; (comma = text.find(',', from)) != std::string::npos; from = comma + 1)
        parts.push_back(text.substr(from, comma - from));
      parts.push_back(text.substr(from));
      if (parts.size() != 2)
        throw InputError(fmt::format("parameter '{}' needs a 2-D point 'x,y' (two numbers), got '{}' ({} {})", s.key,
                                     text, parts.size(), parts.size() == 1 ? "value" : "values"));
      const double x = parse_number(s.key, parts[0], "x");  // x first: its error is the one reported
      const Eigen::Vector2d v(x, parse_number(s.key, parts[1], "y"));
      for (int i = 0; i < 2; ++i)
        if (!in_range(s, v[i]))
          throw InputError(fmt::format("parameter '{}' needs coordinates {}{}, got '{}'", s.key, range_text(s),
                                       s.unit.empty() ? "" : " " + s.unit, text));
      return v;
    }
    case ParamKind::kChoice: {
      const std::string t = trim(text);
      for (const auto& c : s.choices)
        if (c == t) return t;
      throw InputError(fmt::format("parameter '{}' must be one of {}, got '{}'{}", s.key, fmt::join(s.choices, "|"),
                                   text, did_you_mean(t, s.choices)));
    }
  }
  throw InputError("unreachable parameter kind");
}

}  // namespace

ParamValue parse_param(const ParamSpec& spec, const std::string& text) { return parse_value(spec, text); }

nlohmann::json ParamSpec::to_json() const {
  static const char* kinds[] = {"number", "integer", "vec2", "choice"};
  nlohmann::json j{
      {"key", key}, {"kind", kinds[static_cast<int>(kind)]}, {"default", default_text}, {"unit", unit}, {"help", help}};
  if (std::isfinite(min)) j["min"] = min, j["min_exclusive"] = min_exclusive;
  if (std::isfinite(max)) j["max"] = max;
  if (!choices.empty()) j["choices"] = choices;
  return j;
}

Params Params::resolve(const std::vector<ParamSpec>& specs, const Overrides& overrides, const std::string& scenario) {
  Params p;
  for (const auto& s : specs) p.values_[s.key] = parse_value(s, s.default_text);
  for (const auto& [key, text] : overrides) {
    const ParamSpec* spec = nullptr;
    for (const auto& s : specs)
      if (s.key == key) spec = &s;
    if (!spec) {
      std::vector<std::string> keys;
      for (const auto& s : specs) keys.push_back(s.key);
      throw InputError(
          fmt::format("unknown parameter '{}' for scenario '{}'{}", key, scenario, did_you_mean(key, keys)));
    }
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
    if (const double* d = std::get_if<double>(&v))
      j[k] = *d;
    else if (const auto* e = std::get_if<Eigen::Vector2d>(&v))
      j[k] = {(*e)[0], (*e)[1]};
    else
      j[k] = std::get<std::string>(v);
  }
  return j;
}

Params Params::from_json(const nlohmann::json& values) {
  Params p;
  for (const auto& [k, v] : values.items()) {
    if (v.is_number())
      p.values_[k] = v.get<double>();
    else if (v.is_string())
      p.values_[k] = v.get<std::string>();
    else if (v.is_array() && v.size() == 2 && v[0].is_number() && v[1].is_number())
      p.values_[k] = Eigen::Vector2d(v[0].get<double>(), v[1].get<double>());
    else
      throw std::invalid_argument("parameter '" + k + "': not a value Params::to_json writes");
  }
  return p;
}

std::pair<std::string, std::string> split_assignment(const std::string& arg) {
  const auto eq = arg.find('=');
  if (eq == std::string::npos || trim(arg.substr(0, eq)).empty())
    throw InputError(fmt::format("--set needs KEY=VALUE, got '{}'", arg));
  return {trim(arg.substr(0, eq)), arg.substr(eq + 1)};
}

}  // namespace liftcheck
