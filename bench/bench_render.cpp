// Render and encode an 800 x 600 snapshot (target: 30 ms or less), and its parts.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "engines/engine.hpp"
#include "harness/runner.hpp"
#include "reports/gl_render.hpp"
#include "reports/scene_build.hpp"

using namespace liftcheck;

namespace {

const nlohmann::json& circle_run() {
  static const nlohmann::json run = run_scenario(*find_scenario("car.circle"), *find_engine("analytic")).to_json();
  return run;
}

render::Scene end_scene() {
  for (auto& s : render::snapshots_for(circle_run(), render::color_from_hex(find_engine("analytic")->color)))
    if (s.tag == "end") return s.scene;
  return {};
}

void BM_Render800x600(benchmark::State& state) {
  render::Renderer r;
  const render::Scene scene = end_scene();
  r.render(scene);  // context creation and shader compilation happen once
  for (auto _ : state) benchmark::DoNotOptimize(r.render(scene));
}
BENCHMARK(BM_Render800x600)->Unit(benchmark::kMillisecond);

void BM_EncodePng800x600(benchmark::State& state) {
  render::Renderer r;
  const render::Image img = r.render(end_scene());
  const auto path = std::filesystem::temp_directory_path() / "liftcheck_bench.png";
  for (auto _ : state) render::write_png(path, img);
  std::filesystem::remove(path);
}
BENCHMARK(BM_EncodePng800x600)->Unit(benchmark::kMillisecond);

void BM_RenderAndEncode800x600(benchmark::State& state) {
  render::Renderer r;
  const render::Scene scene = end_scene();
  r.render(scene);
  const auto path = std::filesystem::temp_directory_path() / "liftcheck_bench.png";
  for (auto _ : state) render::write_png(path, r.render(scene));
  std::filesystem::remove(path);
}
BENCHMARK(BM_RenderAndEncode800x600)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
