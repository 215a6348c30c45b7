#include "input/results_diff.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>

#include "input/interrupt.hpp"

namespace liftcheck {

namespace {

using json = nlohmann::json;

std::map<std::pair<std::string, std::string>, const json*> index_runs(const json& results) {
  std::map<std::pair<std::string, std::string>, const json*> m;
  for (const auto& r : results.at("runs")) m[{r.at("scenario").get<std::string>(), r.at("engine").get<std::string>()}] = &r;
  return m;
}

json merged(json a, const json& b) {
  a.update(b);
  return a;
}

/// A record's verdict ("known failure", ...), or its status in files written before verdicts.
std::string verdict_of(const json& r) { return r.value("verdict", r["status"].get<std::string>()); }

/// A number of a record; null (how a NaN or infinite value is written) or absent reads as infinite.
double number_of(const json& m, const char* key) {
  const auto it = m.find(key);
  return it != m.end() && it->is_number() ? it->get<double>() : INFINITY;
}

/// Error of a metric as a fraction of its tolerance (input/results_file.cpp checks these fields
/// of a file read back).
double ratio(const json& m) {
  const double err = number_of(m, m.value("tolerance_kind", "abs") == "rel" ? "rel_error" : "abs_error");
  const double tol = number_of(m, "tolerance");
  double r = tol > 0 ? err / tol : (err > 0 ? INFINITY : 0.0);
  if (m.value("floor", 0.0) > 0.0) r = std::min(r, number_of(m, "abs_error") / m["floor"].get<double>());
  return r;
}

}  // namespace

bool record_as_expected(const json& r) {
  if (r.contains("as_expected")) return r["as_expected"].get<bool>();
  return r["status"] == "pass" || r["status"] == "skip";
}

json baseline_json(const json& results) {
  json runs = json::array();
  for (const auto& r : results["runs"]) {
    json metrics = json::object();
    for (const auto& [name, m] : r["metrics"].items()) {
      json kept = json::object();
      for (const char* k : {"expected", "measured", "abs_error", "rel_error", "tolerance", "tolerance_kind", "floor", "pass", "informational"})
        if (m.contains(k)) kept[k] = m[k];
      metrics[name] = kept;
    }
    runs.push_back({{"scenario", r["scenario"]}, {"engine", r["engine"]}, {"params", r["params"]}, {"settings", r["settings"]},
                    {"status", r["status"]}, {"verdict", r.value("verdict", r["status"].get<std::string>())},
                    {"as_expected", record_as_expected(r)}, {"message", r["message"]}, {"metrics", metrics}});
  }
  return {{"liftcheck_baseline", 1}, {"context", {{"liftcheck", results["context"]["liftcheck"]}}}, {"runs", runs}};
}

json diff_results(const json& base, const json& head, const DiffDef& def) {
  json d{{"regressions", json::array()}, {"fixed", json::array()}, {"worse", json::array()},
         {"better", json::array()}, {"added", json::array()}, {"removed", json::array()}};
  const auto b = index_runs(base), h = index_runs(head);
  std::size_t compared = 0;
  for (const auto& [key, hr] : h) {
    if ((++compared & 0xFFFF) == 0) throw_if_interrupted("while comparing the results");
    const auto it = b.find(key);
    const json id{{"scenario", key.first}, {"engine", key.second}};
    if (it == b.end()) {
      d["added"].push_back(id);
      continue;
    }
    const json& br = *it->second;
    if (record_as_expected(br) && !record_as_expected(*hr))
      d["regressions"].push_back(merged(id, {{"from", verdict_of(br)}, {"to", verdict_of(*hr)}, {"message", hr->value("message", "")}}));
    else if (!record_as_expected(br) && record_as_expected(*hr))
      d["fixed"].push_back(merged(id, {{"from", verdict_of(br)}, {"to", verdict_of(*hr)}}));
    if (!br.contains("metrics") || !hr->contains("metrics") || !br["metrics"].is_object() || !(*hr)["metrics"].is_object()) continue;
    for (const auto& [name, hm] : (*hr)["metrics"].items()) {
      if (!br["metrics"].contains(name) || hm.value("informational", false)) continue;
      const json& bm = br["metrics"][name];
      const double rb = ratio(bm), rh = ratio(hm);
      const json entry = merged(id, {{"metric", name}, {"base_ratio", rb}, {"head_ratio", rh},
                                     {"base_measured", bm.value("measured", json())}, {"head_measured", hm.value("measured", json())}});
      if (rh > def.floor && rh > def.growth * rb) d["worse"].push_back(entry);
      else if (rb > def.floor && rb > def.growth * rh) d["better"].push_back(entry);
    }
  }
  for (const auto& [key, br] : b)
    if (!h.count(key)) d["removed"].push_back({{"scenario", key.first}, {"engine", key.second}});
  return d;
}

std::string diff_text(const json& d) {
  std::string t;
  for (const auto& r : d["regressions"])
    t += fmt::format("REGRESSION {} on {}: {} -> {} ({})\n", r["scenario"].get<std::string>(), r["engine"].get<std::string>(),
                     r["from"].get<std::string>(), r["to"].get<std::string>(), r["message"].get<std::string>());
  for (const auto& r : d["fixed"])
    t += fmt::format("fixed      {} on {}: {} -> {}\n", r["scenario"].get<std::string>(), r["engine"].get<std::string>(),
                     r["from"].get<std::string>(), r["to"].get<std::string>());
  for (const char* kind : {"worse", "better"})
    for (const auto& r : d[kind])
      t += fmt::format("{:<10} {} on {}: {} measured {} (was {}), {:.3g} of tolerance (was {:.3g})\n", kind, r["scenario"].get<std::string>(),
                       r["engine"].get<std::string>(), r["metric"].get<std::string>(), r["head_measured"].dump(), r["base_measured"].dump(),
                       r["head_ratio"].get<double>(), r["base_ratio"].get<double>());
  for (const char* kind : {"added", "removed"})
    for (const auto& r : d[kind])
      t += fmt::format("{:<10} {} on {}\n", kind, r["scenario"].get<std::string>(), r["engine"].get<std::string>());
  t += fmt::format("{} regressions, {} fixed, {} metrics worse, {} better, {} runs added, {} removed\n", d["regressions"].size(),
                   d["fixed"].size(), d["worse"].size(), d["better"].size(), d["added"].size(), d["removed"].size());
  return t;
}

}  // namespace liftcheck
