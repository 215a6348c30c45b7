#include "input/results_diff.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <map>
#include <string_view>
#include <unordered_map>
#include <vector>

#include "input/interrupt.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck {

namespace {

using json = nlohmann::json;

/// A run's key: its scenario and configuration, views into the document.
using RunKey = std::pair<std::string_view, std::string_view>;

struct RunKeyHash {
  std::size_t operator()(const RunKey& k) const {
    const std::size_t a = std::hash<std::string_view>()(k.first);
    return a ^ (std::hash<std::string_view>()(k.second) + 0x9e3779b97f4a7c15ULL + (a << 6) + (a >> 2));
  }
};

RunKey key_of(const json& r) {
  return {r.at("scenario").get_ref<const std::string&>(), r.at("engine").get_ref<const std::string&>()};
}

/// The runs by key (a later record of the same run wins, as it always did), hashed: a diff of a
/// million runs is linear in them.
std::unordered_map<RunKey, const json*, RunKeyHash> index_runs(const json& results) {
  const json& runs = results.at("runs");
  std::unordered_map<RunKey, const json*, RunKeyHash> m;
  m.reserve(runs.size());
  for (const auto& r : runs) m[key_of(r)] = &r;
  return m;
}

/// The same, in key order (the order of the diff's findings).
std::vector<std::pair<RunKey, const json*>> sorted_runs(const std::unordered_map<RunKey, const json*, RunKeyHash>& index) {
  std::vector<std::pair<RunKey, const json*>> v(index.begin(), index.end());
  std::sort(v.begin(), v.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  return v;
}

json id_of(const RunKey& key) { return {{"scenario", std::string(key.first)}, {"engine", std::string(key.second)}}; }

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
  for (const auto& [key, hr] : sorted_runs(h)) {
    if ((++compared & 0xFFFF) == 0) throw_if_interrupted("while comparing the results");
    const auto it = b.find(key);
    if (it == b.end()) {
      d["added"].push_back(id_of(key));
      continue;
    }
    const json& br = *it->second;
    const bool was = record_as_expected(br), is = record_as_expected(*hr);
    if (was && !is)
      d["regressions"].push_back(merged(id_of(key), {{"from", verdict_of(br)}, {"to", verdict_of(*hr)}, {"message", hr->value("message", "")}}));
    else if (!was && is)
      d["fixed"].push_back(merged(id_of(key), {{"from", verdict_of(br)}, {"to", verdict_of(*hr)}}));
    const auto bms = br.find("metrics"), hms = hr->find("metrics");
    if (bms == br.end() || hms == hr->end() || !bms->is_object() || !hms->is_object()) continue;
    for (const auto& [name, hm] : hms->get_ref<const json::object_t&>()) {
      const auto bm = bms->find(name);
      if (bm == bms->end() || hm.value("informational", false)) continue;
      const double rb = ratio(*bm), rh = ratio(hm);
      const bool worse = rh > def.floor && rh > def.growth * rb, better = !worse && rb > def.floor && rb > def.growth * rh;
      if (!worse && !better) continue;
      d[worse ? "worse" : "better"].push_back(merged(id_of(key), {{"metric", name}, {"base_ratio", rb}, {"head_ratio", rh},
                                                                  {"base_measured", bm->value("measured", json())},
                                                                  {"head_measured", hm.value("measured", json())}}));
    }
  }
  for (const auto& [key, br] : sorted_runs(b))
    if (!h.count(key)) d["removed"].push_back(id_of(key));
  return d;
}

std::string diff_text(const json& d) {
  // Names and messages come from the files: one line each, whatever they hold.
  const auto name = [](const json& v) { return printable(v.get<std::string>(), 200); };
  std::string t;
  for (const auto& r : d["regressions"])
    t += fmt::format("REGRESSION {} on {}: {} -> {} ({})\n", name(r["scenario"]), name(r["engine"]),
                     name(r["from"]), name(r["to"]), printable(r["message"].get<std::string>(), 1000));
  for (const auto& r : d["fixed"])
    t += fmt::format("fixed      {} on {}: {} -> {}\n", name(r["scenario"]), name(r["engine"]),
                     name(r["from"]), name(r["to"]));
  for (const char* kind : {"worse", "better"})
    for (const auto& r : d[kind])
      t += fmt::format("{:<10} {} on {}: {} measured {} (was {}), {:.3g} of tolerance (was {:.3g})\n", kind, name(r["scenario"]),
                       name(r["engine"]), name(r["metric"]), r["head_measured"].dump(), r["base_measured"].dump(),
                       r["head_ratio"].get<double>(), r["base_ratio"].get<double>());
  for (const char* kind : {"added", "removed"})
    for (const auto& r : d[kind])
      t += fmt::format("{:<10} {} on {}\n", kind, name(r["scenario"]), name(r["engine"]));
  t += fmt::format("{} regressions, {} fixed, {} metrics worse, {} better, {} runs added, {} removed\n", d["regressions"].size(),
                   d["fixed"].size(), d["worse"].size(), d["better"].size(), d["added"].size(), d["removed"].size());
  return t;
}

}  // namespace liftcheck
