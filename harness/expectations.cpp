#include "harness/expectations.hpp"

#include <nlohmann/json.hpp>

#include "liftcheck_expectations.hpp"

namespace liftcheck {

const std::vector<KnownFailure>& known_run_failures() {
  static const std::vector<KnownFailure> all = [] {
    std::vector<KnownFailure> v;
    const nlohmann::json j = nlohmann::json::parse(kExpectationsJson);
    for (const auto& e : j.value("runs", nlohmann::json::array()))
      for (const auto& engine : e.at("engines"))
        v.push_back({e.at("scenario"), engine, e.at("metrics").get<std::vector<std::string>>(), e.at("reason"), e.at("measured")});
    return v;
  }();
  return all;
}

const KnownFailure* find_known_failure(const std::string& scenario, const std::string& engine) {
  for (const KnownFailure& k : known_run_failures())
    if (k.scenario == scenario && k.engine == engine) return &k;
  return nullptr;
}

}  // namespace liftcheck
