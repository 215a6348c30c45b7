#include "input/results_diff.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <map>
#include <string_view>
#include <vector>

#include "input/interrupt.hpp"
#include "input/record_view.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck {

namespace {

using json = nlohmann::json;

/// A run's key: its scenario and configuration, views into the index.
using RunKey = std::pair<std::string_view, std::string_view>;

/// A run of one file, with a hash of its key.
struct Entry {
  std::uint64_t hash;
  RunKey key;
  const RunFigures* run;
};

/// (hash, key): an order in which two files are walked side by side to pair their runs, cheap to
/// sort (the findings are put in key order afterwards).
bool before(const Entry& a, const Entry& b) {
  if (a.hash != b.hash) return a.hash < b.hash;
  return a.key < b.key;
}

/// The runs in (hash, key) order, one per key: a later record of the same run wins, as it always did.
std::vector<Entry> paired_order(const ResultsIndex& results) {
  std::vector<Entry> v;
  v.reserve(results.runs.size());
  for (const auto& r : results.runs) {
    const std::uint64_t a = std::hash<std::string_view>()(r.scenario);
    v.push_back({a ^ (std::hash<std::string_view>()(r.engine) + 0x9e3779b97f4a7c15ULL + (a << 6) + (a >> 2)),
                 {r.scenario, r.engine},
                 &r});
  }
  // Equal keys keep the file's order (the records are in one array); the last is kept.
  std::sort(v.begin(), v.end(),
            [](const Entry& a, const Entry& b) { return before(a, b) || (!before(b, a) && a.run < b.run); });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < v.size(); ++i)
    if (i + 1 == v.size() || before(v[i], v[i + 1])) v[kept++] = v[i];
  v.resize(kept);
  return v;
}

/// The findings of a diff, each with its run's key, in the order found.
struct Findings {
  std::vector<std::pair<RunKey, json>> regressions, fixed, worse, better;
  std::vector<RunKey> added, removed;
};

/// Findings of one kind in key order (a run's several metrics in name order) into `out`.
void put_in_key_order(std::vector<std::pair<RunKey, json>>& found, json& out) {
  std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& f : found) out.push_back(std::move(f.second));
}
void put_in_key_order(std::vector<RunKey>& found, json& out);

json id_of(const RunKey& key) { return {{"scenario", std::string(key.first)}, {"engine", std::string(key.second)}}; }

json merged(json a, const json& b) {
  a.update(b);
  return a;
}

void put_in_key_order(std::vector<RunKey>& found, json& out) {
  std::sort(found.begin(), found.end());
  for (const auto& key : found) out.push_back(id_of(key));
}

/// The metric of that name, or null.
const MetricFigures* metric_named(const std::vector<MetricFigures>& metrics, const std::string& name) {
  const auto it = std::lower_bound(metrics.begin(), metrics.end(), name,
                                   [](const MetricFigures& m, const std::string& n) { return m.name < n; });
  return it != metrics.end() && it->name == name ? &*it : nullptr;
}

/// The parameters and settings in which two records of a run differ: "key a -> b" (a key one
/// lacks: "(none)"), so a change is not read as the engine's when the run itself changed.
json settings_differ(const RunFigures& br, const RunFigures& hr) {
  json out = json::array();
  if (!br.settings || !hr.settings || *br.settings == *hr.settings) return out;
  const auto pairs = [](const std::string& text) {
    std::vector<std::pair<std::string, std::string>> kv;
    for (std::size_t at = 0, end; (end = text.find('\x1e', at)) != std::string::npos; at = end + 1) {
      const std::size_t sep = text.find('\x1f', at);
      kv.emplace_back(text.substr(at, sep - at), text.substr(sep + 1, end - sep - 1));
    }
    return kv;
  };
  const auto bs = pairs(*br.settings), hs = pairs(*hr.settings);
  auto b = bs.begin(), h = hs.begin();
  const auto add = [&](const std::string& key, const std::string& from, const std::string& to) {
    if (out.size() < 20) out.push_back(key + " " + from + " -> " + to);
  };
  while (b != bs.end() || h != hs.end()) {
    if (h == hs.end() || (b != bs.end() && b->first < h->first)) {
      add(b->first, b->second, "(none)"), ++b;
    } else if (b == bs.end() || h->first < b->first) {
      add(h->first, "(none)", h->second), ++h;
    } else {
      if (b->second != h->second) add(b->first, b->second, h->second);
      ++b, ++h;
    }
  }
  return out;
}

/// The id of a run's finding, with the settings that differ between its two records if any.
json id_with(const RunKey& key, const RunFigures& br, const RunFigures& hr) {
  json id = id_of(key);
  if (json d = settings_differ(br, hr); !d.empty()) id["settings_differ"] = std::move(d);
  return id;
}

/// The worse and better metrics of one run present in both files.
void compare_metrics(const RunKey& key, const RunFigures& br, const RunFigures& hr, const DiffDef& def,
                     Findings& found) {
  if (!br.has_metrics || !hr.has_metrics) return;
  for (const MetricFigures& hm : hr.metrics) {
    const MetricFigures* bm = metric_named(br.metrics, hm.name);
    if (!bm || hm.informational) continue;
    const double rb = bm->ratio, rh = hm.ratio;
    const bool worse = rh > def.floor && rh > def.growth * rb,
               better = !worse && rb > def.floor && rb > def.growth * rh;
    if (!worse && !better) continue;
    (worse ? found.worse : found.better)
        .emplace_back(key, merged(id_with(key, br, hr), {{"metric", hm.name},
                                                         {"base_ratio", rb},
                                                         {"head_ratio", rh},
                                                         {"base_measured", bm->measured},
                                                         {"head_measured", hm.measured}}));
  }
}

}  // namespace

std::shared_ptr<const std::string> interned_settings(std::vector<std::pair<std::string, std::string>> pairs,
                                                     SettingsPool& pool) {
  std::sort(pairs.begin(), pairs.end());
  std::string text;
  for (const auto& [key, value] : pairs) text += key + '\x1f' + value + '\x1e';
  auto& shared = pool[text];
  if (!shared) shared = std::make_shared<const std::string>(text);
  return shared;
}

ResultsIndex index_of(const json& results) {
  ResultsIndex index;
  SettingsPool pool;
  const json& runs = results.at("runs");
  index.runs.reserve(runs.size());
  for (const auto& r : runs) {
    RunFigures f;
    f.scenario = r.at("scenario").get<std::string>();
    f.engine = r.at("engine").get<std::string>();
    f.verdict = RecordView(r).verdict();
    f.message = r.value("message", "");
    f.as_expected = record_as_expected(r);
    const auto ms = r.find("metrics");
    f.has_metrics = ms != r.end() && ms->is_object();
    if (f.has_metrics)
      for (const auto& [name, m] : ms->get_ref<const json::object_t&>())  // in name order
        f.metrics.push_back({name, MetricView(m).ratio(), !MetricView(m).counted(), MetricView(m).raw("measured")});
    std::vector<std::pair<std::string, std::string>> kv;
    for (const char* group : {"params", "settings"})
      if (const auto g = r.find(group); g != r.end() && g->is_object())
        for (const auto& [key, v] : g->items())
          if (!v.is_structured()) kv.emplace_back(key, v.is_string() ? v.get<std::string>() : v.dump());
    f.settings = interned_settings(std::move(kv), pool);
    index.runs.push_back(std::move(f));
  }
  return index;
}

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
      for (const char* k : kBaselineMetricFields)
        if (m.contains(k)) kept[k] = m[k];
      metrics[name] = kept;
    }
    runs.push_back({{"scenario", r["scenario"]},
                    {"engine", r["engine"]},
                    {"params", r["params"]},
                    {"settings", r["settings"]},
                    {"status", r["status"]},
                    {"verdict", r.value("verdict", r["status"].get<std::string>())},
                    {"as_expected", record_as_expected(r)},
                    {"message", r["message"]},
                    {"metrics", metrics}});
  }
  return {{"liftcheck_baseline", 1}, {"context", {{"liftcheck", results["context"]["liftcheck"]}}}, {"runs", runs}};
}

json diff_results(const ResultsIndex& base, const ResultsIndex& head, const DiffDef& def) {
  const auto b = paired_order(base), h = paired_order(head);
  Findings found;
  std::size_t at = 0;  // in b
  for (std::size_t i = 0; i < h.size(); ++i) {
    if (((i + 1) & 0xFFFF) == 0) throw_if_interrupted("while comparing the results");
    const Entry& he = h[i];
    for (; at < b.size() && before(b[at], he); ++at) found.removed.push_back(b[at].key);
    if (at == b.size() || before(he, b[at])) {
      found.added.push_back(he.key);
      continue;
    }
    const RunFigures &br = *b[at++].run, &hr = *he.run;
    if (br.as_expected && !hr.as_expected)
      found.regressions.emplace_back(
          he.key, merged(id_with(he.key, br, hr), {{"from", br.verdict}, {"to", hr.verdict}, {"message", hr.message}}));
    else if (!br.as_expected && hr.as_expected)
      found.fixed.emplace_back(he.key, merged(id_with(he.key, br, hr), {{"from", br.verdict}, {"to", hr.verdict}}));
    compare_metrics(he.key, br, hr, def, found);
  }
  for (; at < b.size(); ++at) found.removed.push_back(b[at].key);
  json d{{"regressions", json::array()}, {"fixed", json::array()}, {"worse", json::array()},
         {"better", json::array()},      {"added", json::array()}, {"removed", json::array()}};
  put_in_key_order(found.regressions, d["regressions"]);
  put_in_key_order(found.fixed, d["fixed"]);
  put_in_key_order(found.worse, d["worse"]);
  put_in_key_order(found.better, d["better"]);
  put_in_key_order(found.added, d["added"]);
  put_in_key_order(found.removed, d["removed"]);
  return d;
}

json diff_results(const json& base, const json& head, const DiffDef& def) {
  return diff_results(index_of(base), index_of(head), def);
}

namespace {

/// A measured value as a reader wants it: a number to 4 significant figures, else as written.
std::string figure(const json& v) { return v.is_number() ? fmt::format("{:.4g}", v.get<double>()) : v.dump(); }

/// " [settings differ: iterations 20 -> 5, ...]" when the two records of the run were not made alike.
std::string differ_text(const json& r) {
  if (!r.contains("settings_differ")) return "";
  std::vector<std::string> items;
  for (const auto& s : r["settings_differ"]) items.push_back(printable(s.get<std::string>(), 120));
  return fmt::format(" [settings differ: {}]", fmt::join(items, ", "));
}

}  // namespace

std::string diff_text(const json& d) {
  // Names and messages come from the files: one line each, whatever they hold.
  const auto name = [](const json& v) { return printable(v.get<std::string>(), 200); };
  std::string t;
  for (const auto& r : d["regressions"])
    t += fmt::format("REGRESSION {} on {}: {} -> {} ({}){}\n", name(r["scenario"]), name(r["engine"]), name(r["from"]),
                     name(r["to"]), printable(r["message"].get<std::string>(), 1000), differ_text(r));
  for (const auto& r : d["fixed"])
    t += fmt::format("fixed      {} on {}: {} -> {}{}\n", name(r["scenario"]), name(r["engine"]), name(r["from"]),
                     name(r["to"]), differ_text(r));
  for (const char* kind : {"worse", "better"})
    for (const auto& r : d[kind])
      t += fmt::format("{:<10} {} on {}: {} measured {} (was {}), {:.3g} of tolerance (was {:.3g}){}\n", kind,
                       name(r["scenario"]), name(r["engine"]), name(r["metric"]), figure(r["head_measured"]),
                       figure(r["base_measured"]), r["head_ratio"].get<double>(), r["base_ratio"].get<double>(),
                       differ_text(r));
  for (const char* kind : {"added", "removed"})
    for (const auto& r : d[kind]) t += fmt::format("{:<10} {} on {}\n", kind, name(r["scenario"]), name(r["engine"]));
  t += fmt::format("{} regressions, {} fixed, {} metrics worse, {} better, {} runs added, {} removed\n",
                   d["regressions"].size(), d["fixed"].size(), d["worse"].size(), d["better"].size(), d["added"].size(),
                   d["removed"].size());
  return t;
}

}  // namespace liftcheck
