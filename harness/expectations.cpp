#include "harness/expectations.hpp"

#include <cmath>
#include <fmt/format.h>
#include <stdexcept>

#include "liftcheck_expectations.hpp"

namespace liftcheck {

Ceilings parse_ceilings(const nlohmann::json& metrics, const std::string& where) {
  if (!metrics.is_object() || metrics.empty())
    throw std::logic_error(fmt::format(
        "harness/expectations.json: {}: \"metrics\" must map each failing metric to its error ceiling", where));
  Ceilings c;
  for (const auto& [name, v] : metrics.items()) {
    if (!v.is_number() || !(v.get<double>() > 0.0) || !std::isfinite(v.get<double>()))
      throw std::logic_error(
          fmt::format("harness/expectations.json: {}: the ceiling of '{}' must be a positive number", where, name));
    c[name] = v.get<double>();
  }
  return c;
}

bool Evidence::holds(double from_now, double to_now, double tolerance, double to_tolerance) const {
  const auto near = [](double now, double recorded, double tol) {
    if (recorded <= tol) return now <= tol;
    return now <= kReproduce * recorded && now >= recorded / kReproduce;
  };
  const bool moved = to < from ? to_now * kMove <= from_now : to_now >= kMove * from_now;
  return std::isfinite(from_now) && std::isfinite(to_now) && from_now > tolerance && near(from_now, from, tolerance) &&
         near(to_now, to, to_tolerance) && moved;
}

bool Evidence::holds_from_error(bool errs_now, double to_now, double tolerance) const {
  const bool near = to <= tolerance ? to_now <= tolerance : to_now <= kReproduce * to && to_now >= to / kReproduce;
  return errs_now && std::isfinite(to_now) && near;
}

std::string Evidence::change_text() const {
  std::string s;
  for (const auto& [k, v] : change) s += (s.empty() ? "" : ", ") + k + "=" + v;
  return s;
}

std::vector<Evidence> parse_evidence(const nlohmann::json& listing, const std::string& where) {
  std::vector<Evidence> v;
  const auto fail = [&](const std::string& what) {
    return std::logic_error(fmt::format("harness/expectations.json: {}: \"evidence\" {}", where, what));
  };
  const nlohmann::json list = listing.value("evidence", nlohmann::json::array());
  if (!list.is_array()) throw fail("must be a list of experiments");
  for (const auto& e : list) {
    Evidence ev;
    if (!e.is_object() || !e.contains("change") || !e.at("change").is_object() || e.at("change").empty())
      throw fail("needs \"change\": {KEY: VALUE} (what --set changes)");
    for (const auto& [key, value] : e.at("change").items()) {
      if (!value.is_string()) throw fail(fmt::format("values are text, as given to --set ('{}')", key));
      ev.change.emplace_back(key, value.get<std::string>());
    }
    if (!e.contains("metric") || !e.at("metric").is_string()) throw fail("needs the \"metric\" whose figure moves");
    ev.metric = e.at("metric");
    ev.from_error = e.contains("from") && e.at("from") == "error";
    for (const char* k : {"from", "to"})
      if (!(ev.from_error && std::string(k) == "from") &&
          (!e.contains(k) || !e.at(k).is_number() || !(e.at(k).get<double>() >= 0.0)))
        throw fail(fmt::format(
            "needs \"{}\": the compared error measured (\"from\": \"error\" for a run that ends in one)", k));
    ev.from = ev.from_error ? NAN : e.at("from").get<double>(), ev.to = e.at("to");
    if (ev.from == ev.to) throw fail("records no move (\"from\" equals \"to\")");
    ev.x = e.value("x", 0.0);
    v.push_back(std::move(ev));
  }
  return v;
}

const std::vector<KnownFailure>& known_run_failures() {
  static const std::vector<KnownFailure> all = [] {
    std::vector<KnownFailure> v;
    const nlohmann::json j = nlohmann::json::parse(kExpectationsJson);
    for (const auto& e : j.value("runs", nlohmann::json::array()))
      for (const auto& engine : e.at("engines")) {
        const std::string where =
            fmt::format("{} on {}", e.at("scenario").get<std::string>(), engine.get<std::string>());
        std::vector<std::pair<std::string, std::string>> params;
        const nlohmann::json changed = e.value("params", nlohmann::json::object());
        for (const auto& [key, value] : changed.items()) {
          if (!value.is_string())
            throw std::logic_error(fmt::format(
                "harness/expectations.json: {}: \"params\" values are text, as given to --set ('{}')", where, key));
          params.emplace_back(key, value.get<std::string>());
        }
        if (e.contains("error")) {
          if (!e.at("error").is_string() || e.at("error").get<std::string>().empty() || e.contains("metrics"))
            throw std::logic_error(
                fmt::format("harness/expectations.json: {}: \"error\" is the start of the error message, given instead "
                            "of \"metrics\"",
                            where));
          v.push_back({e.at("scenario"),
                       engine,
                       params,
                       {},
                       e.at("reason"),
                       e.at("measured"),
                       e.at("error").get<std::string>(),
                       parse_evidence(e, where)});
          continue;
        }
        v.push_back({e.at("scenario"),
                     engine,
                     params,
                     parse_ceilings(e.at("metrics"), where),
                     e.at("reason"),
                     e.at("measured"),
                     {},
                     parse_evidence(e, where)});
      }
    return v;
  }();
  return all;
}

const std::vector<ListedReason>& listed_reasons() {
  static const std::vector<ListedReason> all = [] {
    std::vector<ListedReason> v;
    const nlohmann::json j = nlohmann::json::parse(kExpectationsJson);
    const auto tried = [](const nlohmann::json& e) { return e.value("cause_not_shown", std::string()); };
    const auto control = [](const nlohmann::json& e, const std::string& where) {
      const nlohmann::json c = e.value("negative_control", nlohmann::json(false));
      if (!c.is_boolean())
        throw std::logic_error(
            fmt::format("harness/expectations.json: {}: \"negative_control\" is true or false", where));
      return c.get<bool>();
    };
    for (const auto& e : j.value("runs", nlohmann::json::array()))
      for (const auto& engine : e.at("engines")) {
        std::vector<std::pair<std::string, std::string>> params;
        const nlohmann::json given = e.value("params", nlohmann::json::object());
        for (const auto& [key, value] : given.items()) params.emplace_back(key, value.get<std::string>());
        const std::string where =
            fmt::format("{} on {}", e.at("scenario").get<std::string>(), engine.get<std::string>());
        v.push_back({e.at("scenario"), false, engine, params, e.at("reason"), parse_evidence(e, where), tried(e),
                     control(e, where)});
      }
    for (const auto& e : j.value("sweep_points", nlohmann::json::array()))
      for (const auto& engine : e.at("engines")) {
        const std::string sweep = e.at("sweep");
        const std::string where = fmt::format("sweep {} on {}", sweep, engine.get<std::string>());
        v.push_back({sweep, true, engine, {}, e.at("reason"), parse_evidence(e, where), tried(e), control(e, where)});
      }
    return v;
  }();
  return all;
}

const KnownFailure* find_known_failure(const std::string& scenario, const std::string& engine) {
  for (const KnownFailure& k : known_run_failures())
    if (k.scenario == scenario && k.engine == engine && k.params.empty()) return &k;
  return nullptr;
}

std::vector<const KnownFailure*> known_failures_of(const std::string& scenario, const std::string& engine) {
  std::vector<const KnownFailure*> v;
  for (const KnownFailure& k : known_run_failures())
    if (k.scenario == scenario && k.engine == engine) v.push_back(&k);
  return v;
}

}  // namespace liftcheck
