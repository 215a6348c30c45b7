#include "reports/report.hpp"

#include <chrono>
#include <fmt/format.h>
#include <malloc.h>
#include <mutex>
#include <set>
#include <thread>

#include "input/atomic_file.hpp"
#include "reports/gl_render.hpp"
#include "reports/html.hpp"
#include "reports/plots.hpp"
#include "reports/scene_build.hpp"

namespace liftcheck {

namespace {

using json = nlohmann::json;

std::string file_safe(const std::string& s) {
  std::string o;
  for (char c : s) o += std::isalnum(static_cast<unsigned char>(c)) || c == '-' ? c : '_';
  return o;
}

double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

/// Renders every run's snapshots and frame strip into out/snapshots in def.threads threads, and
/// lists them (in run order), the problems and the GL version in `report`.
void write_snapshots(const SuiteResults& results, const std::filesystem::path& out, const ReportDef& def,
                     ReportInfo& report) {
  const std::vector<RunResult>& runs = results.runs;
  std::vector<std::vector<ReportFile>> shots(runs.size()), strips(runs.size());
  std::vector<std::string> errors;
  std::string gl_version;
  std::mutex mu;
  bool out_of_memory = false;
  std::map<std::string, render::Color> ink;  // each configuration's colour, from the context
  for (const auto& e : results.context.engines) ink[e.name] = render::color_from_hex(e.color);
  const auto ink_of = [&](const RunResult& r) {
    const auto it = ink.find(r.engine);
    return it == ink.end() ? render::colors::kUnknown : it->second;
  };
  // The start is the scenario's: every configuration starts from the same pose (to a few mm where
  // the car settles on its wheels), so it is drawn once, from the scenario's first run with a trace.
  std::set<std::string> seen;
  std::vector<bool> draw_start(runs.size(), false);
  for (std::size_t i = 0; i < runs.size(); ++i) {
    const nlohmann::json& d = runs[i].details;
    const auto tr = d.find("trace");
    const bool traced = tr != d.end() && tr->is_array() && tr->size() >= 2;
    draw_start[i] = traced && seen.insert(runs[i].scenario).second;
  }
  const int threads = std::max(1, def.threads);  // 0 or fewer: one thread (a stride of 0 never ends)
  const auto draw = [&](int id) {
    render::Renderer renderer;
    for (std::size_t i = id; i < runs.size(); i += static_cast<std::size_t>(threads)) {
      const RunResult& r = runs[i];
      const std::string base = fmt::format("snapshots/{}__{}", file_safe(r.scenario), file_safe(r.engine));
      try {
        for (const auto& s : render::snapshots_for(r, ink_of(r))) {
          if (s.tag == "start" && !draw_start[i]) continue;
          const std::string file = fmt::format("{}__{}.png", base, s.tag);
          render::Image img = renderer.render(s.scene);
          for (const auto& in : s.insets) render::paste(img, renderer.render(in.scene), in.x_px, in.y_px);
          render::write_png(out / file, img);
          shots[i].push_back({"", r.scenario, r.engine, s.tag, file, s.caption, s.caption});
        }
        const render::Strip st = render::strip_for(r, ink_of(r));
        if (!st.frames.empty()) {
          std::vector<render::Image> frames;
          for (const auto& f : st.frames) frames.push_back(renderer.render(f));
          const std::string file = base + "__strip.png";
          render::write_png(out / file, render::tile(frames, st.per_row));
          strips[i].push_back({"", r.scenario, r.engine, "strip", file, st.caption, "frame strip"});
        }
        // glibc keeps the freed images of each thread in its arena: returned here, the renderer's
        // peak stays near its live heap (docs/performance.md) instead of growing by an arena a thread.
        malloc_trim(0);
      } catch (const std::bad_alloc&) {
        throw;  // the renderer's limit: the report stops (below)
      } catch (const std::exception& e) {
        std::lock_guard<std::mutex> lock(mu);
        errors.push_back(fmt::format("snapshots of {} on {}: {}", r.scenario, r.engine, e.what()));
      }
    }
    std::lock_guard<std::mutex> lock(mu);
    if (gl_version.empty()) gl_version = renderer.gl_version();
  };
  // An allocation that fails under the renderer's memory limit ends every thread's work and the
  // report, said once (write_report throws std::bad_alloc).
  const auto worker = [&](int id) {
    try {
      draw(id);
    } catch (const std::bad_alloc&) {
      std::lock_guard<std::mutex> lock(mu);
      out_of_memory = true;
    }
  };
  std::vector<std::thread> pool;
  for (int id = 0; id < threads; ++id) pool.emplace_back(worker, id);
  for (auto& t : pool) t.join();
  if (out_of_memory) throw std::bad_alloc();
  for (std::size_t i = 0; i < runs.size(); ++i) {
    for (auto& s : shots[i]) report.snapshots.push_back(std::move(s));
    for (auto& s : strips[i]) report.strips.push_back(std::move(s));
  }
  for (auto& e : errors) report.errors.push_back(std::move(e));
  report.gl_version = gl_version;
}

}  // namespace

void write_report(SuiteResults& results, const std::filesystem::path& out, const ReportDef& def) {
  const auto t0 = std::chrono::steady_clock::now();
  ReportInfo report;
  std::filesystem::create_directories(out / "snapshots");

  if (def.snapshots) write_snapshots(results, out, def, report);
  report.snapshots_s = seconds_since(t0);

  const auto tp = std::chrono::steady_clock::now();
  if (def.plots) {
    try {
      for (const auto& p : write_plots(results, out))
        report.plots.push_back({p.group, "", "", "", p.file, p.caption, p.caption});
    } catch (const std::bad_alloc&) {
      throw;  // past the renderer's memory limit: the whole report stops
    } catch (const std::exception& e) {
      report.errors.push_back(fmt::format("plots: {}", e.what()));
    }
  }
  report.plots_s = seconds_since(tp);
  report.report_s = seconds_since(t0);
  results.report = report;

  for (const auto& sc : results.scenario_order())
    write_file_atomic(out / scenario_page(sc), scenario_html(results, sc));
  results.report->report_s = seconds_since(t0);
  write_file_atomic(out / "index.html", index_html(results));
}

}  // namespace liftcheck
