// The sweeps, the outcome grid and the speed-accuracy map as JSON (results.json "sweeps", "maps").
#include <fmt/format.h>

#include "input/results_codec.hpp"

namespace liftcheck {

using json = nlohmann::json;

namespace {

json encode_gate(const Gate& g) {
  json j{{"pass", g.pass},
         {"problems", g.problems},
         {"points_pass", g.points_pass},
         {"points_known_failure", g.points_known_failure},
         {"points_error", g.points_error},
         {"points_unexpected", g.points_unexpected}};
  if (g.slope_band) j["slope_band"] = {g.slope_band->first, g.slope_band->second};
  return j;
}

Gate decode_gate(const JsonIn& in) {
  Gate g;
  g.pass = in.boolean("pass");
  g.problems = in.strings("problems");
  if (g.pass != g.problems.empty()) in.fail(fmt::format("'pass' is {} with {} problems", g.pass, g.problems.size()));
  g.points_pass = in.integer_or("points_pass", 0);
  g.points_known_failure = in.integer_or("points_known_failure", 0);
  g.points_error = in.integer_or("points_error", 0);
  g.points_unexpected = in.integer_or("points_unexpected", 0);
  if (in.has("slope_band")) {
    const auto band = in.numbers("slope_band");
    if (band.size() != 2) in.fail("'slope_band' must be two numbers");
    g.slope_band = {band[0], band[1]};
  }
  return g;
}

json encode_point(const SweepPoint& p, const std::vector<std::string>& record) {
  json errors = json::object();
  for (const auto& [k, v] : p.errors) errors[k] = finite_or_null(v);
  json j{{"x", p.x},
         {"status", to_string(p.status)},
         {"message", p.message},
         {"failed", p.failed},
         {"errors", errors},
         {"worst_ratio", finite_or_null(p.worst_ratio)}};
  // Every field the sweep records, null where the point has none.
  for (const auto& field : record) j[field] = json();
  for (const auto& [name, f] : p.metrics)
    j["metric:" + name] = {{"expected", finite_or_null(f.expected)},
                           {"measured", finite_or_null(f.measured)},
                           {"rel_error", finite_or_null(f.rel_error)},
                           {"abs_error", finite_or_null(f.abs_error)},
                           {"pass", f.pass}};
  for (const auto& [key, v] : p.details) j["detail:" + key] = v;
  if (p.fitted) j["fitted"] = true;
  if (!p.known_failure.empty()) j["known_failure"] = p.known_failure;
  return j;
}

SweepPoint decode_point(const JsonIn& in, const std::vector<std::string>& record) {
  SweepPoint p;
  p.x = in.num("x");
  p.status = static_cast<Status>(in.one_of("status", {"pass", "fail", "error", "skip"}));
  p.message = in.str("message");
  p.failed = in.strings("failed");
  p.errors = in.number_map("errors");
  p.worst_ratio = in.opt_num_or_null("worst_ratio");
  for (const auto& key : record) {
    if (!in.has(key.c_str())) in.fail(fmt::format("missing '{}', which the sweep records", key));
    const json& v = *in.get(key.c_str());
    if (key.rfind("metric:", 0) == 0) {
      if (v.is_null()) continue;  // not measured at this point
      const JsonIn m = in.obj(key.c_str());
      p.metrics[key.substr(7)] = {m.opt_num_or_null("expected"), m.opt_num_or_null("measured"),
                                  m.opt_num_or_null("rel_error"), m.opt_num_or_null("abs_error"), m.boolean("pass")};
    } else {
      p.details[key.substr(7)] = v;
    }
  }
  p.fitted = in.boolean_or("fitted", false);
  p.known_failure = in.str_or("known_failure", "");
  return p;
}

}  // namespace

json encode_sweep(const Sweep& s) {
  json engines = json::array();
  for (const auto& e : s.engines) {
    json points = json::array();
    for (const auto& p : e.points) points.push_back(encode_point(p, s.record));
    json entry{{"engine", e.engine}, {"points", points}, {"gate", encode_gate(e.gate)}};
    if (e.fit) {
      entry["fit"] = {{"slope", finite_or_null(e.fit->slope)}, {"points", e.fit->points}};
      if (!e.fit->known_failure.empty()) entry["fit"]["known_failure"] = e.fit->known_failure;
    }
    engines.push_back(entry);
  }
  json curves = json::array();
  for (const auto& [expr, title] : s.curves) curves.push_back({{"expr", expr}, {"title", title}});
  json fixed = json::array();
  for (const auto& [k, v] : s.fixed) fixed.push_back({k, v});
  json j{{"name", s.name},
         {"title", s.title},
         {"scenario", s.scenario},
         {"param", s.param},
         {"fixed", fixed},
         {"record", s.record},
         {"engines", engines},
         {"unswept", s.unswept},
         {"plot",
          {{"kind", s.plot_kind},
           {"x_label", s.x_label},
           {"y_label", s.y_label},
           {"log_x", s.log_x},
           {"curves", curves}}}};
  if (s.marker) j["marker"] = {{"x", s.marker->first}, {"label", s.marker->second}};
  for (const auto& t : s.times_x) j["times_x"].push_back({{"key", t.key}, {"per_x", t.per_x}, {"min", t.min}});
  return j;
}

Sweep decode_sweep(const JsonIn& in) {
  Sweep s;
  s.name = in.str("name");
  s.title = in.str("title");
  s.scenario = in.str("scenario");
  s.param = in.str("param");
  for (const auto& f : in.arr("fixed")) {
    if (!f.is_array() || f.size() != 2 || !f[0].is_string() || !f[1].is_string())
      in.fail("'fixed' must hold [KEY, VALUE] pairs of strings");
    s.fixed.emplace_back(f[0].get<std::string>(), f[1].get<std::string>());
  }
  s.record = in.strings("record");
  s.unswept = in.strings_or_empty("unswept");
  const JsonIn plot = in.obj("plot");
  s.plot_kind = plot.str("kind");
  s.x_label = plot.str("x_label");
  s.y_label = plot.str("y_label");
  s.log_x = plot.boolean("log_x");
  for (std::size_t i = 0; i < plot.arr("curves").size(); ++i) {
    const JsonIn c = plot.element("curves", i);
    s.curves.emplace_back(c.str("expr"), c.str("title"));
  }
  if (const auto m = in.opt_obj("marker")) s.marker = {m->num("x"), m->str("label")};
  for (std::size_t i = 0; i < in.arr_or_empty("times_x").size(); ++i) {
    const JsonIn t = in.element("times_x", i);
    s.times_x.push_back({t.str("key"), t.num("per_x"), t.num("min")});
  }
  for (std::size_t i = 0; i < in.arr("engines").size(); ++i) {
    const JsonIn e = in.element("engines", i);
    SweepEngine se;
    se.engine = e.str("engine");
    for (std::size_t k = 0; k < e.arr("points").size(); ++k)
      se.points.push_back(decode_point(e.element("points", k), s.record));
    if (const auto f = e.opt_obj("fit"))
      se.fit = SweepFit{f->opt_num_or_null("slope"), f->integer("points"), f->str_or("known_failure", "")};
    se.gate = decode_gate(e.obj("gate"));
    s.engines.push_back(std::move(se));
  }
  return s;
}

namespace {

json encode_case(const OutcomeCase& c) {
  json errors = json::object();
  for (const auto& [k, v] : c.errors) errors[k] = finite_or_null(v);
  json j{{"a", c.a},
         {"b", c.b},
         {"path", c.path},
         {"T_s", c.T_s},
         {"reference", c.reference},
         {"engine", c.engine ? json(*c.engine) : json()},
         {"status", to_string(c.status)}};
  if (!c.engine) return j["message"] = c.message, j;
  j.update({{"reference_t_contact_s", finite_or_null(c.reference_t_contact_s)},
            {"t_error_steps", finite_or_null(c.t_error_steps)},
            {"reference_min_distance", c.reference_min_distance},
            {"near_boundary", c.near_boundary},
            {"errors", errors},
            {"known_failure", c.known_failure}});
  return j;
}

OutcomeCase decode_case(const JsonIn& in) {
  OutcomeCase c;
  c.a = in.num("a"), c.b = in.num("b"), c.T_s = in.num("T_s");
  c.path = in.str("path");
  c.reference = in.boolean("reference");
  c.status = static_cast<Status>(in.one_of("status", {"pass", "fail", "error", "skip"}));
  if (in.get("engine")->is_null()) {
    c.message = in.str("message");
    return c;
  }
  c.engine = in.boolean("engine");
  c.reference_t_contact_s = in.num_or_null("reference_t_contact_s");
  c.t_error_steps = in.num_or_null("t_error_steps");
  c.reference_min_distance = in.num("reference_min_distance");
  c.near_boundary = in.boolean("near_boundary");
  c.errors = in.number_map("errors");
  c.known_failure = in.boolean("known_failure");
  return c;
}

}  // namespace

json encode_outcomes(const OutcomeSweep& o) {
  json engines = json::array();
  for (const auto& e : o.engines) {
    json cases = json::array();
    for (const auto& c : e.cases) cases.push_back(encode_case(c));
    engines.push_back({{"engine", e.engine},
                       {"confusion",
                        {{"both_collide", e.both_collide},
                         {"neither", e.neither},
                         {"engine_only", e.engine_only},
                         {"reference_only", e.reference_only}}},
                       {"errors", e.errors},
                       {"runs_out_of_tolerance", e.runs_out_of_tolerance},
                       {"runs_known_failure", e.runs_known_failure},
                       {"known_failure", e.known_failure.empty() ? json() : json(e.known_failure)},
                       {"near_boundary_cases", e.near_boundary_cases},
                       {"unexplained_disagreements", e.unexplained_disagreements},
                       {"worst_t_error_steps", e.worst_t_error_steps},
                       {"cases", cases},
                       {"gate", encode_gate(e.gate)}});
  }
  json fixed = json::object();
  for (const auto& [k, v] : o.fixed) fixed[k] = v;
  return {{"name", o.name},
          {"kind", "outcomes"},
          {"title", o.title},
          {"scenario", o.scenario},
          {"grid", {{"a", o.grid_a}, {"b", o.grid_b}, {"path", o.grid_path}}},
          {"fixed", fixed},
          {"horizon",
           {{"T_max_s", o.T_max_s}, {"clearance_m", o.clearance_m}, {"after_s", o.after_s}, {"T_min_s", o.T_min_s}}},
          {"near_boundary_m", o.near_boundary_m},
          {"engines", engines}};
}

OutcomeSweep decode_outcomes(const JsonIn& in) {
  OutcomeSweep o;
  o.name = in.str("name"), o.title = in.str("title"), o.scenario = in.str("scenario");
  const JsonIn grid = in.obj("grid");
  o.grid_a = grid.numbers("a"), o.grid_b = grid.numbers("b"), o.grid_path = grid.strings("path");
  o.fixed = in.text_pairs("fixed");
  const JsonIn h = in.obj("horizon");
  o.T_max_s = h.num("T_max_s"), o.clearance_m = h.num("clearance_m"), o.after_s = h.num("after_s");
  o.T_min_s = h.num("T_min_s");
  o.near_boundary_m = in.num("near_boundary_m");
  for (std::size_t i = 0; i < in.arr("engines").size(); ++i) {
    const JsonIn e = in.element("engines", i);
    OutcomeEngine oe;
    oe.engine = e.str("engine");
    const JsonIn c = e.obj("confusion");
    oe.both_collide = c.integer("both_collide"), oe.neither = c.integer("neither");
    oe.engine_only = c.integer("engine_only"), oe.reference_only = c.integer("reference_only");
    oe.errors = e.integer("errors");
    oe.runs_out_of_tolerance = e.integer("runs_out_of_tolerance");
    oe.runs_known_failure = e.integer("runs_known_failure");
    oe.known_failure = e.get("known_failure")->is_null() ? "" : e.str("known_failure");
    oe.near_boundary_cases = e.integer("near_boundary_cases");
    oe.unexplained_disagreements = e.integer("unexplained_disagreements");
    oe.worst_t_error_steps = e.num("worst_t_error_steps");
    for (std::size_t k = 0; k < e.arr("cases").size(); ++k) oe.cases.push_back(decode_case(e.element("cases", k)));
    oe.gate = decode_gate(e.obj("gate"));
    o.engines.push_back(std::move(oe));
  }
  return o;
}

json encode_map(const SpeedMap& m) {
  json panels = json::array();
  for (const auto& p : m.panels) {
    json curves = json::array();
    for (const auto& c : p.curves) {
      json points = json::array();
      for (const auto& pt : c.points)
        points.push_back({{"knob", pt.knob},
                          {"value", pt.value},
                          {"status", to_string(pt.status)},
                          {"message", pt.message},
                          {"error", finite_or_null(pt.error)},
                          {"wall_s", pt.wall_s},
                          {"simulated_s", pt.simulated_s},
                          {"cost_s_per_s", finite_or_null(pt.cost_s_per_s)},
                          {"pareto", pt.pareto},
                          {"passes", pt.passes}});
      curves.push_back({{"engine", c.engine}, {"points", points}});
    }
    panels.push_back({{"scenario", p.scenario},
                      {"error_metrics", p.error_metrics},
                      {"error_label", p.error_label},
                      {"curves", curves}});
  }
  return {{"name", m.name},  {"kind", "map"}, {"title", m.title}, {"dt_s", m.dt_s}, {"iterations", m.iterations},
          {"panels", panels}};
}

SpeedMap decode_map(const JsonIn& in) {
  SpeedMap m;
  m.name = in.str("name"), m.title = in.str("title");
  m.dt_s = in.numbers("dt_s");
  for (double n : in.numbers("iterations")) m.iterations.push_back(static_cast<int>(n));
  for (std::size_t i = 0; i < in.arr("panels").size(); ++i) {
    const JsonIn p = in.element("panels", i);
    MapPanel panel{p.str("scenario"), p.str("error_label"), p.strings("error_metrics"), {}};
    for (std::size_t k = 0; k < p.arr("curves").size(); ++k) {
      const JsonIn c = p.element("curves", k);
      MapCurve curve{c.str("engine"), {}};
      for (std::size_t q = 0; q < c.arr("points").size(); ++q) {
        const JsonIn pt = c.element("points", q);
        curve.points.push_back({pt.str("knob"), pt.num("value"),
                                static_cast<Status>(pt.one_of("status", {"pass", "fail", "error", "skip"})),
                                pt.str("message"), pt.num_or_null("error"), pt.num("wall_s"), pt.num("simulated_s"),
                                pt.num_or_null("cost_s_per_s"), pt.boolean("pareto"), pt.boolean("passes")});
      }
      panel.curves.push_back(std::move(curve));
    }
    m.panels.push_back(std::move(panel));
  }
  return m;
}

}  // namespace liftcheck
