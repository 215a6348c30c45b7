#include "reports/plots.hpp"

#include "scenarios/sweep_catalogue.hpp"
#include "input/vehicle.hpp"
#include "scenarios/details.hpp"
#include "reports/scene_build.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fcntl.h>
#include <fmt/format.h>
#include <functional>
#include <fstream>
#include <map>
#include <set>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>
#include <unistd.h>

namespace liftcheck {

namespace {

using json = nlohmann::json;

/// Each configuration's colour, from the results' context (EngineInfo::color).
std::map<std::string, std::string> colors_of(const SuiteResults& results) {
  std::map<std::string, std::string> out;
  for (const auto& e : results.context.engines)
    if (!e.color.empty()) out[e.name] = e.color;
  return out;
}

std::string safe(const std::string& s) {
  std::string o;
  for (char c : s) o += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  return o;
}

}  // namespace

/// A string as gnuplot data: single-quoted (no backslash escapes, no backquote command substitution,
/// no macros inside), a quote doubled, control characters (which would end the command) as spaces.
std::string gnuplot_quote(const std::string& s) {
  std::string o = "'";
  for (char c : s) {
    if (c == '\'')
      o += "''";
    else if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      o += ' ';
    else
      o += c;
  }
  return o + "'";
}

namespace {

struct Script {
  std::ostringstream gp;
  int blocks = 0;
  std::string block(const std::vector<std::vector<double>>& rows) {
    const std::string name = fmt::format("$D{}", blocks++);
    gp << name << " << EOD\n";
    for (const auto& r : rows) {
      for (std::size_t i = 0; i < r.size(); ++i)
        gp << (i ? " " : "") << (std::isfinite(r[i]) ? fmt::format("{:.10g}", r[i]) : "NaN");
      gp << "\n";
    }
    gp << "EOD\n";
    return name;
  }
  /// `svg` is a file name inside the plots folder, where gnuplot runs. A plot of `entries` lines
  /// keeps its key below the data, four entries a row, and grows by its rows, so the data take
  /// the plot's whole width however many configurations it draws.
  void begin(const std::string& svg, const std::string& title, int w = 760, int h = 440, int entries = 0) {
    const int key_rows = (entries + 3) / 4;
    gp << fmt::format("reset\nset terminal svg size {},{} dynamic font 'DejaVu Sans,12' background '#ffffff'\n", w,
                      h + 16 * key_rows)
       << fmt::format("set output {}\nset title {} font ',11'\nset grid lc rgb '#dddddd'\n", gnuplot_quote(svg),
                      gnuplot_quote(title))
       << (entries > 0 ? "set key below center horizontal maxcols 4 font ',9' noenhanced\n"
                       : "set key outside right top noenhanced\n");
  }
};

/// "plots/x.svg" -> "x.svg": gnuplot runs in the plots folder, so no path of the user's is in the script.
std::string file_name(const std::string& rel) { return std::filesystem::path(rel).filename().string(); }

/// Runs gnuplot on `dir`/plots.gp with `dir` as its working folder, its output in `dir`/gnuplot.log:
/// no shell, the argument vector fixed ("gnuplot plots.gp"), the folder handed over as data.
void run_gnuplot(const std::filesystem::path& dir) {
  const std::string log = (dir / "gnuplot.log").string();
  const int out_fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
  if (out_fd < 0) throw std::runtime_error(fmt::format("cannot write '{}': {}", log, std::strerror(errno)));
  const int null_fd = ::open("/dev/null", O_RDONLY | O_CLOEXEC);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_addchdir_np(&fa, dir.c_str());
  if (null_fd >= 0) posix_spawn_file_actions_adddup2(&fa, null_fd, STDIN_FILENO);
  posix_spawn_file_actions_adddup2(&fa, out_fd, STDOUT_FILENO);
  posix_spawn_file_actions_adddup2(&fa, out_fd, STDERR_FILENO);
  char arg0[] = "gnuplot", arg1[] = "plots.gp";
  char* argv[] = {arg0, arg1, nullptr};
  pid_t pid = -1;
  const int rc = posix_spawnp(&pid, "gnuplot", &fa, nullptr, argv, environ);
  posix_spawn_file_actions_destroy(&fa);
  ::close(out_fd);
  if (null_fd >= 0) ::close(null_fd);
  if (rc != 0) throw std::runtime_error(fmt::format("cannot run gnuplot: {}", std::strerror(rc)));
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0)
    if (errno != EINTR) throw std::runtime_error(fmt::format("waiting for gnuplot: {}", std::strerror(errno)));
  if (WIFSIGNALED(status))
    throw std::runtime_error(fmt::format("gnuplot killed by signal {}; see {}", WTERMSIG(status), log));
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0)
    throw std::runtime_error(fmt::format("gnuplot exited with status {}; see {}", WEXITSTATUS(status), log));
}

using ColorOf = std::function<std::string(const std::string&)>;

/// `S` written to `dir`/plots.gp and run by gnuplot there; the script and log are removed when it succeeds.
void run_script(const Script& S, const std::filesystem::path& dir) {
  const auto script = dir / "plots.gp";
  {
    std::ofstream f(script);
    f << S.gp.str();
    f.close();
    if (!f) throw std::runtime_error(fmt::format("cannot write '{}': {}", script.string(), std::strerror(errno)));
  }
  run_gnuplot(dir);
  // The script holds every plotted number (3 MB): kept only when gnuplot fails, with its log.
  std::error_code ec;
  std::filesystem::remove(script, ec);
  std::filesystem::remove(dir / "gnuplot.log", ec);
}

/// Distance at each sample of `trace` from `ref` at the same time (linear between the reference's
/// samples, its last row beyond its end: the two may be kept at different strides): the front-axle
/// centre (x, y) for a car, c_M for the disks. Rows {t, distance}, floored at 1e-16 for a log scale.
std::vector<std::vector<double>> error_rows(const json& trace, const json& ref) {
  std::vector<std::vector<double>> rows;
  if (ref.empty()) return rows;
  std::size_t j = 0;
  for (const auto& row : trace) {
    const double t = row[0].get<double>();
    while (j + 1 < ref.size() && ref[j + 1][0].get<double>() <= t) ++j;
    const bool car = row.size() >= 6;
    const int ix = car ? 3 : 1, iy = car ? 4 : 2;
    double rx = ref[j][ix].get<double>(), ry = ref[j][iy].get<double>();
    if (j + 1 < ref.size()) {
      const double t0 = ref[j][0].get<double>(), t1 = ref[j + 1][0].get<double>();
      const double w = t1 > t0 ? std::clamp((t - t0) / (t1 - t0), 0.0, 1.0) : 0.0;
      rx += w * (ref[j + 1][ix].get<double>() - rx);
      ry += w * (ref[j + 1][iy].get<double>() - ry);
    }
    rows.push_back({t, std::max(std::hypot(row[ix].get<double>() - rx, row[iy].get<double>() - ry), 1e-16)});
  }
  return rows;
}

/// A plot per scenario of its runs' errors against time: each engine's distance from the exact
/// lift (log scale), where paths drawn over each other would hide errors of 1e-7 and 1e-2 alike.
void plot_runs(Script& S, std::vector<PlotFile>& files, const SuiteResults& results, const ColorOf& color_of) {
  for (const std::string& sc : results.scenario_order()) {
    const RunResult* first = nullptr;
    std::string cmd, label = "the exact lift (4.1)";
    int entries = 0;
    for (const RunResult& r : results.runs) {
      if (r.scenario != sc) continue;
      if (!first) first = &r;
      const json& d = r.details;
      if (!d.is_object() || !d.contains(detail_key::kTrace) || !d.contains(detail_key::kReference) ||
          d[detail_key::kTrace].empty())
        continue;
      cmd += fmt::format("{} u 1:2 w l lw 1.8 lc rgb {} t {} noenhanced, ",
                         S.block(error_rows(d[detail_key::kTrace], render::own_reference(d))),
                         gnuplot_quote(color_of(r.engine)), gnuplot_quote(r.engine));
      ++entries;
      if (d.contains(detail_key::kReferenceLabel)) label = d[detail_key::kReferenceLabel].get<std::string>();
    }
    if (cmd.empty()) continue;
    const bool disks = first->vehicle == Vehicle::kDisks;
    const std::string file = fmt::format("plots/{}-error.svg", safe(sc));
    S.begin(file_name(file),
            sc + (disks ? ": c_M against the exact lift (21), after contact the exact response"
                        : ": front-axle centre against " + label),
            760, 440, entries);
    S.gp << "set xlabel 'time [s]'\nset ylabel 'distance [m]'\nset logscale y\nset format y '10^{%T}'\n";
    S.gp << "plot " << cmd.substr(0, cmd.size() - 2) << "\n";
    files.push_back({sc, file,
                     disks ? "each engine's c_M against the exact lift at the same time, after its first contact "
                             "against the exact inelastic response from that contact (log scale)"
                           : "each engine's front-axle centre against " + label + " at the same time (log scale)"});
  }
}

/// The outcome sweep: a panel per path of N over (a, b), the reference's outcomes and where an
/// engine disagrees.
void plot_outcomes(Script& S, const OutcomeSweep& sw, const std::string& file) {
  S.begin(file_name(file), "", 1100, 420);
  S.gp << fmt::format(
      "set multiplot layout 1,{} title {}\nset xlabel 'a'\nset ylabel 'b'\nset xrange [-1.5:3.5]\nset yrange "
      "[-1.5:1.5]\nset key bottom right font ',9'\n",
      sw.grid_path.size(), gnuplot_quote(sw.title));
  const OutcomeEngine* first = sw.engines.empty() ? nullptr : &sw.engines[0];
  for (const auto& path : sw.grid_path) {
    std::vector<std::vector<double>> hit, miss, nearb, dis;
    if (first)
      for (const auto& c : first->cases) {
        if (c.path != path) continue;
        (c.reference ? hit : miss).push_back({c.a, c.b});
        if (c.near_boundary) nearb.push_back({c.a, c.b});
      }
    for (const auto& e : sw.engines)
      for (const auto& c : e.cases)
        if (c.path == path && (!c.engine || c.reference != *c.engine)) dis.push_back({c.a, c.b});
    hit.push_back({NAN, NAN}), miss.push_back({NAN, NAN}), nearb.push_back({NAN, NAN}), dis.push_back({NAN, NAN});
    const std::string bh = S.block(hit), bm = S.block(miss), bn = S.block(nearb), bd = S.block(dis);
    S.gp << fmt::format(
        "set title {}\nplot {} u 1:2 w p pt 7 ps 1.3 lc rgb '#d62728' t 'collision', "
        "{} u 1:2 w p pt 7 ps 1.3 lc rgb '#2ca02c' t 'no collision', "
        "{} u 1:2 w p pt 6 ps 2.6 lc rgb '#000000' t 'near boundary', "
        "{} u 1:2 w p pt 2 ps 2.2 lw 2 lc rgb '#9467bd' t 'an engine disagrees'\n",
        gnuplot_quote("N on a " + path), bh, bm, bn, bd);
  }
  S.gp << "unset multiplot\n";
}

/// The points of one configuration in a sweep, as the sweep's plot kind draws them: (x, a) and,
/// for a sweep of values, (x, b) for its second metric; (x, exact) for a sweep of sizes.
struct SweepRows {
  std::vector<std::vector<double>> a, b, exact;
};
SweepRows sweep_rows(const Sweep& sw, const SweepEngine& e) {
  SweepRows rows;
  const bool values = sw.plot_kind == "values", holonomy = sw.plot_kind == "sizes";
  const auto rel_error = [](const SweepPoint& pt, const std::string& field) {
    const auto it = pt.metrics.find(recorded_field(field).name);
    return it == pt.metrics.end() ? NAN : it->second.rel_error;
  };
  const auto detail = [](const SweepPoint& pt, const char* key) {
    const auto it = pt.details.find(key);
    return it != pt.details.end() && it->second.is_number() ? it->second.get<double>() : NAN;
  };
  for (const SweepPoint& pt : e.points) {
    const double x = pt.x;
    if (values) {  // the error of each value, not the value: every engine's radius would overlap
      const double f = rel_error(pt, sw.record[0]), r = rel_error(pt, sw.record[1]);
      // An exact zero (the reference itself) has no place on a log axis: drawn at 1e-16 it
      // would stretch the axis over eight empty decades.
      if (f > 0) rows.a.push_back({x, f});
      if (r > 0) rows.b.push_back({x, r});
    } else if (holonomy) {
      const double ex = detail(pt, detail_key::kHolonomySize), me = detail(pt, detail_key::kMeasuredSize);
      if (std::isfinite(ex)) rows.exact.push_back({x, ex});
      if (std::isfinite(me)) rows.a.push_back({x, me});
    } else {
      const double err = rel_error(pt, sw.record[0]);
      if (err > 0) rows.a.push_back({x, std::max(err, 1e-16)});
    }
  }
  return rows;
}

/// One parameter sweep, plotted as its catalogue entry says; false when it has nothing to plot.
bool plot_sweep(Script& S, const Sweep& sw, const std::string& file, const ColorOf& color_of) {
  const std::string before = S.gp.str();  // the script so far: this plot's header goes after it
  std::string cmd;
  int entries = 0;
  // The sweep says how it is plotted (its catalogue entry): measured values over exact curves,
  // measured against exact sizes, or relative errors.
  const bool values = sw.plot_kind == "values", holonomy = sw.plot_kind == "sizes";
  S.gp << fmt::format("set xlabel {}\nset ylabel {}\n", gnuplot_quote(sw.x_label.empty() ? sw.param : sw.x_label),
                      gnuplot_quote(sw.y_label));
  S.gp << (holonomy ? "set logscale xy\nset format y '10^{%T}'\n" : "set logscale y\nset format y '10^{%T}'\n");
  if (sw.log_x) S.gp << "set logscale x\n";
  int shade = 0;
  if (!values)
    for (const auto& [expr, title] : sw.curves)
      cmd += fmt::format("{} w l lw 6 lc rgb '{}' t {}, ", expr, shade++ == 0 ? "#c8c8c8" : "#e0e0e0",
                         gnuplot_quote(title));
  if (sw.marker)
    S.gp << fmt::format(
        "set arrow from {0}, graph 0 to {0}, graph 1 nohead lc rgb '#cc0000' dt 2\nset label {1} at {0}, graph 0.95 "
        "offset 0.5,0 tc rgb '#cc0000'\n",
        sw.marker->first, gnuplot_quote(sw.marker->second));
  bool exact_done = false;
  for (const SweepEngine& e : sw.engines) {
    SweepRows rows = sweep_rows(sw, e);
    if (rows.a.empty()) continue;
    rows.a.push_back({NAN, NAN});
    if (holonomy && !exact_done && !rows.exact.empty()) {
      cmd += fmt::format("{} u 1:2 w l lw 6 lc rgb '#c8c8c8' t 'exact holonomy', ", S.block(rows.exact));
      exact_done = true;
    }
    std::string title = e.engine;
    if (holonomy && e.fit && std::isfinite(e.fit->slope)) title += fmt::format(" (slope {:.2f})", e.fit->slope);
    cmd += fmt::format("{} u 1:2 w lp pt 7 lw 1.5 lc rgb {} t {} noenhanced, ", S.block(rows.a),
                       gnuplot_quote(color_of(e.engine)), gnuplot_quote(title + (values ? " front" : "")));
    ++entries;
    if (!rows.b.empty()) {
      cmd += fmt::format("{} u 1:2 w lp pt 5 lw 1.5 dt 2 lc rgb {} t {} noenhanced, ", S.block(rows.b),
                         gnuplot_quote(color_of(e.engine)), gnuplot_quote(e.engine + " rear"));
      ++entries;
    }
  }
  // The header goes before the plot's body: its size depends on its key's entries.
  Script head;
  if (!cmd.empty()) head.begin(file_name(file), sw.title, 760, 440, entries + shade + (exact_done ? 1 : 0));
  const std::string body = cmd.empty() ? "" : S.gp.str().substr(before.size());
  S.gp.str(before + head.gp.str() + body);
  S.gp.seekp(0, std::ios::end);
  if (cmd.empty()) return false;
  S.gp << "plot " << cmd.substr(0, cmd.size() - 2) << "\n";
  return true;
}

/// A speed-accuracy map: a panel per scenario, error against cost, a curve per configuration and
/// knob (dt solid, iterations dashed), the Pareto front over the configurations ringed.
void plot_map(Script& S, std::vector<PlotFile>& files, const SpeedMap& map, const ColorOf& color_of) {
  const std::string file = fmt::format("plots/map-{}.svg", safe(map.name));
  S.begin(file_name(file), "", 1200, 520);
  S.gp << fmt::format(
      "set multiplot layout 1,{} title {} font ',11'\nset logscale xy\nset format x '10^{{%T}}'\nset format y "
      "'10^{{%T}}'\n"
      "set xlabel 'wall-clock cost [s per simulated s]'\nset key below font ',8' maxrows 4\n",
      map.panels.size(), gnuplot_quote(map.title));
  for (const MapPanel& panel : map.panels) {
    std::string cmd;
    std::vector<std::vector<double>> front;
    for (const MapCurve& c : panel.curves) {
      for (const char* knob : {kMapDefault, kMapDt, kMapIterations}) {
        std::vector<std::vector<double>> rows;
        for (const MapPoint& p : c.points)
          if (p.knob == knob && std::isfinite(p.error) && std::isfinite(p.cost_s_per_s)) {
            rows.push_back({p.cost_s_per_s, std::max(p.error, 1e-16)});
            if (p.pareto) front.push_back(rows.back());
          }
        if (rows.empty()) continue;
        const std::string style = std::string(knob) == kMapIterations ? "w lp pt 6 dt 2"
                                  : std::string(knob) == kMapDt       ? "w lp pt 7"
                                                                      : "w p pt 9 ps 1.6";
        cmd += fmt::format(
            "{} u 1:2 {} lw 1.5 lc rgb {} t {} noenhanced, ", S.block(rows), style, gnuplot_quote(color_of(c.engine)),
            gnuplot_quote(c.engine + (std::string(knob) == kMapDefault ? "" : fmt::format(" ({})", knob))));
      }
    }
    std::sort(front.begin(), front.end());
    if (!front.empty())
      cmd += fmt::format("{} u 1:2 w lp pt 6 ps 2.4 lw 1 dt 3 lc rgb '#000000' t 'Pareto front', ", S.block(front));
    if (cmd.empty()) continue;
    S.gp << fmt::format("set title {}\nset ylabel {}\nplot {}\n", gnuplot_quote(panel.scenario),
                        gnuplot_quote(panel.error_label), cmd.substr(0, cmd.size() - 2));
  }
  S.gp << "unset multiplot\n";
  files.push_back({"sweeps", file, map.title});
}

}  // namespace

std::vector<PlotFile> write_plots(const SuiteResults& results, const std::filesystem::path& out) {
  std::filesystem::create_directories(out / "plots");
  Script S;
  std::vector<PlotFile> files;
  const std::map<std::string, std::string> colors = colors_of(results);
  const ColorOf color_of = [&](const std::string& engine) {
    const auto it = colors.find(engine);
    return it == colors.end() ? std::string("#808080") : it->second;
  };
  plot_runs(S, files, results, color_of);
  for (const Sweep& sw : results.sweeps) {
    const std::string file = fmt::format("plots/sweep-{}.svg", safe(sw.name));
    if (plot_sweep(S, sw, file, color_of)) files.push_back({"sweeps", file, sw.title});
  }
  if (results.outcomes) {
    const std::string file = fmt::format("plots/sweep-{}.svg", safe(results.outcomes->name));
    plot_outcomes(S, *results.outcomes, file);
    files.push_back({"sweeps", file, results.outcomes->title});
  }
  for (const SpeedMap& map : results.maps) plot_map(S, files, map, color_of);

  run_script(S, out / "plots");
  return files;
}

void write_tune_plot(const json& tune, const std::filesystem::path& out) {
  std::filesystem::create_directories(out / "plots");
  Script S;
  S.begin("tune.svg",
          fmt::format("{} on {}: the runs of the search", tune.value("scenario", ""), tune.value("engine", "")));
  std::vector<std::vector<double>> pass, fail, dflt, answer;
  const auto& walked = tune["walked"];
  for (size_t i = 0; i < walked.size(); ++i) {
    const json& st = walked[i];
    if (!st["cost_ms_per_s"].is_number()) continue;
    const double worst = st["worst_ratio"].is_number() ? std::max(st["worst_ratio"].get<double>(), 1e-6) : 1e6;
    const std::vector<double> row{st["cost_ms_per_s"].get<double>(), worst};
    (st["pass"].get<bool>() ? pass : fail).push_back(row);
    if (i == 0) dflt.push_back(row);
    if (tune["answer"].is_number() && tune["answer"].get<size_t>() == i) answer.push_back(row);
  }
  S.gp << "set logscale xy\nset xlabel 'cost [ms of the engine per simulated s]'\n"
          "set ylabel 'worst error / its tolerance'\nset key below\n";
  std::string cmd = "1 w l lw 1 dt 2 lc rgb '#555555' t 'tolerance', ";
  if (!pass.empty()) cmd += S.block(pass) + " u 1:2 w p pt 7 ps 1.2 lc rgb '#2ca02c' t 'passes', ";
  if (!fail.empty()) cmd += S.block(fail) + " u 1:2 w p pt 6 ps 1.2 lc rgb '#d62728' t 'fails', ";
  if (!dflt.empty()) cmd += S.block(dflt) + " u 1:2 w p pt 4 ps 2.2 lw 2 lc rgb '#000000' t 'defaults', ";
  if (!answer.empty()) cmd += S.block(answer) + " u 1:2 w p pt 8 ps 2.4 lw 2 lc rgb '#1f77b4' t 'cheapest pass', ";
  S.gp << "plot " << cmd.substr(0, cmd.size() - 2) << "\n";
  run_script(S, out / "plots");
}

}  // namespace liftcheck
