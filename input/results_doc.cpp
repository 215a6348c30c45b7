// results.json as a whole: the scenarios, the report's files, the baseline's diff, the simulated
// budget, and the document that holds them with the runs, sweeps and maps.
#include <cmath>
#include <fmt/format.h>

#include "input/results_codec.hpp"
#include "input/standing.hpp"

namespace liftcheck {

using json = nlohmann::json;

json encode_scenario(const ScenarioInfo& s) {
  json params = json::array();
  for (const auto& p : s.params) {
    json j{{"key", p.key}, {"kind", p.kind}, {"default", p.default_text}, {"unit", p.unit}, {"help", p.help}};
    if (std::isfinite(p.min)) j["min"] = p.min, j["min_exclusive"] = p.min_exclusive;
    if (std::isfinite(p.max)) j["max"] = p.max;
    params.push_back(j);
  }
  json metrics = json::array();
  for (const auto& m : s.metrics)
    metrics.push_back({{"name", m.name},
                       {"unit", m.unit},
                       {"tolerance_kind", to_string(m.kind)},
                       {"tolerance", m.tolerance},
                       {"floor", m.floor},
                       {"help", m.help},
                       {"reference_only", m.reference_only}});
  return {{"name", s.name},
          {"vehicle", s.vehicle},
          {"summary", s.summary},
          {"equations", s.equations},
          {"params", params},
          {"metrics", metrics},
          {"needs", s.needs},
          {"negative_control", s.negative_control},
          {"headline",
           {{"metrics", s.headline_metrics},
            {"label", s.headline_label},
            {"unit", s.headline_unit},
            {"scale", s.headline_scale},
            {"per_step", s.headline_per_step}}}};
}

ScenarioInfo decode_scenario(const JsonIn& in) {
  ScenarioInfo s;
  s.name = in.str("name");
  const auto v = parse_vehicle(in.str("vehicle"));
  if (!v) in.fail("'vehicle' must be \"car\" or \"disks\"");
  s.vehicle = *v;
  s.summary = in.str("summary");
  s.equations = in.str("equations");
  for (std::size_t i = 0; i < in.arr("params").size(); ++i) {
    const JsonIn p = in.element("params", i);
    s.params.push_back({p.str("key"), p.str("kind"), p.str("default"), p.str("unit"), p.str("help"),
                        p.has("min") ? p.num("min") : NAN, p.has("max") ? p.num("max") : NAN,
                        p.boolean_or("min_exclusive", false)});
  }
  for (std::size_t i = 0; i < in.arr("metrics").size(); ++i) {
    const JsonIn m = in.element("metrics", i);
    s.metrics.push_back({m.str("name"), m.str("unit"), m.str("help"),
                         m.one_of("tolerance_kind", {"rel", "abs"}) == 0 ? TolKind::kRelative : TolKind::kAbsolute,
                         m.number_map("tolerance"), m.number_map("floor"), m.boolean("reference_only")});
  }
  s.needs = in.strings("needs");
  s.negative_control = in.boolean("negative_control");
  const JsonIn h = in.obj("headline");
  s.headline_metrics = h.strings("metrics");
  s.headline_label = h.str("label");
  s.headline_unit = h.str("unit");
  s.headline_scale = h.num("scale");
  s.headline_per_step = h.boolean("per_step");
  return s;
}

namespace {

json encode_files(const std::vector<ReportFile>& files) {
  json out = json::array();
  for (const auto& f : files) {
    json j{{"file", f.file}, {"caption", f.caption}, {"alt", f.alt}};
    if (!f.group.empty()) j["group"] = f.group;
    if (!f.scenario.empty()) j["scenario"] = f.scenario, j["engine"] = f.engine;
    if (!f.tag.empty()) j["tag"] = f.tag;
    out.push_back(j);
  }
  return out;
}

std::vector<ReportFile> decode_files(const JsonIn& in, const char* key) {
  std::vector<ReportFile> out;
  for (std::size_t i = 0; i < in.arr(key).size(); ++i) {
    const JsonIn f = in.element(key, i);
    out.push_back({f.str_or("group", ""), f.str_or("scenario", ""), f.str_or("engine", ""), f.str_or("tag", ""),
                   f.str("file"), f.str("caption"), f.str_or("alt", f.str("caption"))});
  }
  return out;
}

json encode_finding(const DiffFinding& f) {
  json j{{"scenario", f.scenario}, {"engine", f.engine}};
  if (!f.sweep.empty()) j["sweep"] = f.sweep;
  if (!f.settings_differ.empty()) j["settings_differ"] = f.settings_differ;
  if (!f.metric.empty())
    j.update({{"metric", f.metric},
              {"base_ratio", finite_or_null(f.base_ratio)},
              {"head_ratio", finite_or_null(f.head_ratio)},
              {"base_measured", f.base_measured},
              {"head_measured", f.head_measured}});
  if (!f.from.empty()) j["from"] = f.from, j["to"] = f.to;
  if (!f.message.empty()) j["message"] = f.message;
  return j;
}

DiffFinding decode_finding(const JsonIn& in) {
  DiffFinding f;
  f.scenario = in.str("scenario");
  f.engine = in.str("engine");
  f.sweep = in.str_or("sweep", "");
  f.settings_differ = in.strings_or_empty("settings_differ");
  f.metric = in.str_or("metric", "");
  if (!f.metric.empty()) {
    f.base_ratio = in.num_or_null("base_ratio");
    f.head_ratio = in.num_or_null("head_ratio");
    f.base_measured = *in.get("base_measured");
    f.head_measured = *in.get("head_measured");
  }
  f.from = in.str_or("from", "");
  f.to = in.str_or("to", "");
  f.message = in.str_or("message", "");
  return f;
}

/// The finding lists of a diff, by their names in the file.
template <class D, class F>
void each_list(D& d, F&& f) {
  f("regressions", d.regressions), f("fixed", d.fixed), f("worse", d.worse), f("better", d.better);
  f("moved", d.moved), f("added", d.added), f("removed", d.removed);
}

}  // namespace

json encode_report(const ReportInfo& r) {
  return {{"snapshots", encode_files(r.snapshots)},
          {"strips", encode_files(r.strips)},
          {"plots", encode_files(r.plots)},
          {"errors", r.errors},
          {"gl_version", r.gl_version},
          {"snapshots_s", r.snapshots_s},
          {"plots_s", r.plots_s},
          {"report_s", r.report_s}};
}

ReportInfo decode_report(const JsonIn& in) {
  ReportInfo r;
  r.snapshots = decode_files(in, "snapshots");
  r.strips = decode_files(in, "strips");
  r.plots = decode_files(in, "plots");
  r.errors = in.strings("errors");
  r.gl_version = in.str_or("gl_version", "");
  r.snapshots_s = in.num_or("snapshots_s", 0.0);
  r.plots_s = in.num_or("plots_s", 0.0);
  r.report_s = in.num("report_s");
  return r;
}

json encode_diff(const ResultsDiff& d) {
  json j = json::object();
  each_list(d, [&](const char* name, const std::vector<DiffFinding>& list) {
    j[name] = json::array();
    for (const auto& f : list) j[name].push_back(encode_finding(f));
  });
  return j;
}

ResultsDiff decode_diff(const JsonIn& in) {
  ResultsDiff d;
  each_list(d, [&](const char* name, std::vector<DiffFinding>& list) {
    for (std::size_t i = 0; i < in.arr_or_empty(name).size(); ++i) list.push_back(decode_finding(in.element(name, i)));
  });
  return d;
}

json encode_simulated(const SimulatedBudget& s) {
  json by_config = json::object();
  for (const auto& [config, parts] : s.by_configuration)
    by_config[config] = {{"by_part", parts}, {"total_s", s.configuration_total_s.at(config)}};
  return {{"total_s", s.total_s}, {"by_part", s.by_part}, {"by_configuration", by_config}};
}

SimulatedBudget decode_simulated(const JsonIn& in) {
  SimulatedBudget s;
  s.total_s = in.num("total_s");
  s.by_part = in.number_map("by_part");
  const JsonIn c = in.obj("by_configuration");
  for (const auto& [config, v] : c.value().items()) {
    const JsonIn one = c.obj(config.c_str());
    s.by_configuration[config] = one.number_map("by_part");
    s.configuration_total_s[config] = one.num("total_s");
  }
  return s;
}

}  // namespace liftcheck
