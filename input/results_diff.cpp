#include "input/results_diff.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <map>
#include <string_view>
#include <vector>

#include "input/interrupt.hpp"
#include "input/json_in.hpp"
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
  std::vector<std::pair<RunKey, DiffFinding>> regressions, fixed, worse, better, moved;
  std::vector<RunKey> added, removed;
};

/// Findings of one kind in key order (a run's several metrics in name order) into `out`.
void put_in_key_order(std::vector<std::pair<RunKey, DiffFinding>>& found, std::vector<DiffFinding>& out) {
  std::stable_sort(found.begin(), found.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  for (auto& f : found) out.push_back(std::move(f.second));
}

DiffFinding id_of(const RunKey& key) {
  DiffFinding f;
  f.scenario = std::string(key.first);
  f.engine = std::string(key.second);
  return f;
}

void put_in_key_order(std::vector<RunKey>& found, std::vector<DiffFinding>& out) {
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
std::vector<std::string> settings_differ(const RunFigures& br, const RunFigures& hr) {
  std::vector<std::string> out;
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
DiffFinding id_with(const RunKey& key, const RunFigures& br, const RunFigures& hr) {
  DiffFinding id = id_of(key);
  id.settings_differ = settings_differ(br, hr);
  return id;
}

/// Two figures the same to the bit (two NaNs, null in a file, alike).
bool same(double a, double b) { return a == b || (std::isnan(a) && std::isnan(b)); }

/// The worse, better and moved metrics of one run present in both files.
void compare_metrics(const RunKey& key, const RunFigures& br, const RunFigures& hr, const DiffDef& def,
                     Findings& found) {
  for (const MetricFigures& hm : hr.metrics) {
    const MetricFigures* bm = metric_named(br.metrics, hm.name);
    if (!bm || hm.informational) continue;
    const double rb = bm->ratio, rh = hm.ratio;
    if (same(bm->error, hm.error) && same(rb, rh) && bm->measured == hm.measured) continue;
    const bool worse = rh > def.floor && rh > def.growth * rb,
               better = !worse && rb > def.floor && rb > def.growth * rh;
    DiffFinding f = id_with(key, br, hr);
    f.metric = hm.name;
    f.base_ratio = rb, f.head_ratio = rh;
    f.base_measured = bm->measured, f.head_measured = hm.measured;
    f.sweep = hr.point;
    (worse ? found.worse : better ? found.better : found.moved).emplace_back(key, std::move(f));
  }
}

/// A pair of records of one run or point: a change of whether it is as expected, its metrics.
void compare_pair(const RunKey& key, const RunFigures& br, const RunFigures& hr, const DiffDef& def, Findings& found) {
  if (br.as_expected != hr.as_expected) {
    DiffFinding f = id_with(key, br, hr);
    f.from = br.verdict, f.to = hr.verdict, f.sweep = hr.point;
    if (br.as_expected) f.message = hr.message;
    (br.as_expected ? found.regressions : found.fixed).emplace_back(key, std::move(f));
  }
  compare_metrics(key, br, hr, def, found);
}

/// The points of both files paired by key (a point's key names it whole: its sweep, configuration
/// and value), compared as runs are; their findings keyed by the point's key.
void compare_points(const ResultsIndex& base, const ResultsIndex& head, const DiffDef& def, Findings& found) {
  std::map<std::string_view, const RunFigures*> b;
  for (const RunFigures& p : base.points) b[p.point] = &p;
  for (const RunFigures& hp : head.points) {
    const RunKey key{hp.point, hp.engine};
    const auto it = b.find(hp.point);
    if (it == b.end()) continue;  // a point the baseline does not hold (a sweep added): nothing to compare
    compare_pair(key, *it->second, hp, def, found);
  }
}

/// "collision", "no collision", "an error": a case's outcome.
std::string outcome_text(const std::optional<bool>& hit) {
  return !hit ? "an error" : *hit ? "collision" : "no collision";
}

/// Each case of the outcome grid whose outcome changed: a moved figure.
void compare_outcomes(const ResultsIndex& base, const ResultsIndex& head, Findings& found) {
  for (const auto& [key, hit] : head.outcomes) {
    const auto it = base.outcomes.find(key);
    if (it == base.outcomes.end() || it->second == hit) continue;
    DiffFinding f;
    f.scenario = "outcome grid";
    f.engine = key.substr(0, key.find('/'));
    f.sweep = key;
    f.metric = "outcome";
    f.from = outcome_text(it->second), f.to = outcome_text(hit);
    found.moved.emplace_back(RunKey{it->first, f.engine}, std::move(f));
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

RunFigures figures_of(const RunResult& r, SettingsPool& pool) {
  RunFigures f;
  f.scenario = r.scenario;
  f.engine = r.engine;
  f.verdict = to_string(r.verdict());
  f.message = r.message;
  f.as_expected = r.as_expected();
  std::vector<const Metric*> by_name;
  for (const Metric& m : r.metrics) by_name.push_back(&m);
  std::sort(by_name.begin(), by_name.end(), [](const Metric* a, const Metric* b) { return a->name < b->name; });
  for (const Metric* m : by_name)
    f.metrics.push_back({m->name, m->ratio(), m->compared_error(), m->informational, finite_or_null(m->measured)});
  std::vector<std::pair<std::string, std::string>> kv;
  const json params = r.params.to_json();
  for (const auto& [key, v] : params.items())
    if (!v.is_structured()) kv.emplace_back(key, scalar_text(v));
  for (const auto& [key, v] : r.settings) kv.emplace_back(key, v);
  f.settings = interned_settings(std::move(kv), pool);
  return f;
}

ResultsIndex index_of(const SuiteResults& results) {
  ResultsIndex index;
  SettingsPool pool;
  index.runs.reserve(results.runs.size());
  for (const RunResult& r : results.runs) index.runs.push_back(figures_of(r, pool));
  for (const auto& [key, p] : results.points) {
    index.points.push_back(figures_of(p, pool));
    index.points.back().point = key;
  }
  index.outcomes = results.outcomes ? outcome_flags(*results.outcomes) : results.baseline_outcomes;
  return index;
}

ResultsDiff diff_results(const ResultsIndex& base, const ResultsIndex& head, const DiffDef& def) {
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
    compare_pair(he.key, *b[at++].run, *he.run, def, found);
  }
  for (; at < b.size(); ++at) found.removed.push_back(b[at].key);
  compare_points(base, head, def, found);
  compare_outcomes(base, head, found);
  ResultsDiff d;
  put_in_key_order(found.regressions, d.regressions);
  put_in_key_order(found.fixed, d.fixed);
  put_in_key_order(found.worse, d.worse);
  put_in_key_order(found.better, d.better);
  put_in_key_order(found.moved, d.moved);
  put_in_key_order(found.added, d.added);
  put_in_key_order(found.removed, d.removed);
  return d;
}

namespace {

/// A measured value as a reader wants it: a number to 4 significant figures, else as written.
std::string figure(const json& v) { return v.is_number() ? fmt::format("{:.4g}", v.get<double>()) : v.dump(); }

/// " [settings differ: iterations 20 -> 5, ...]" when the two records of the run were not made alike.
std::string differ_text(const DiffFinding& r) {
  if (r.settings_differ.empty()) return "";
  std::vector<std::string> items;
  for (const auto& s : r.settings_differ) items.push_back(printable(s, 120));
  return fmt::format(" [settings differ: {}]", fmt::join(items, ", "));
}

}  // namespace

std::string finding_name(const DiffFinding& f) {
  return f.sweep.empty() ? fmt::format("{} on {}", printable(f.scenario, 200), printable(f.engine, 200))
                         : printable(f.sweep, 300);
}

std::string diff_text(const ResultsDiff& d) {
  // Names and messages come from the files: one line each, whatever they hold.
  const auto name = [](const std::string& v) { return printable(v, 200); };
  std::string t;
  for (const auto& r : d.regressions)
    t += fmt::format("REGRESSION {}: {} -> {} ({}){}\n", finding_name(r), name(r.from), name(r.to),
                     printable(r.message, 1000), differ_text(r));
  for (const auto& r : d.fixed)
    t += fmt::format("fixed      {}: {} -> {}{}\n", finding_name(r), name(r.from), name(r.to), differ_text(r));
  const auto metric_lines = [&](const char* kind, const std::vector<DiffFinding>& list) {
    for (const auto& r : list)
      t += r.metric == "outcome"
               ? fmt::format("{:<10} {}: {} (was {})\n", kind, name(r.sweep), r.to, r.from)
               : fmt::format("{:<10} {}: {} measured {} (was {}), {:.3g} of tolerance (was {:.3g}){}\n", kind,
                             finding_name(r), name(r.metric), figure(r.head_measured), figure(r.base_measured),
                             r.head_ratio, r.base_ratio, differ_text(r));
  };
  metric_lines("worse", d.worse);
  metric_lines("better", d.better);
  metric_lines("moved", d.moved);
  for (const auto& r : d.added) t += fmt::format("{:<10} {} on {}\n", "added", name(r.scenario), name(r.engine));
  for (const auto& r : d.removed) t += fmt::format("{:<10} {} on {}\n", "removed", name(r.scenario), name(r.engine));
  t += fmt::format("{} regressions, {} fixed, {} metrics worse, {} better, {} moved, {} runs added, {} removed\n",
                   d.regressions.size(), d.fixed.size(), d.worse.size(), d.better.size(), d.moved.size(),
                   d.added.size(), d.removed.size());
  return t;
}

}  // namespace liftcheck
