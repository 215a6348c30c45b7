// Render and encode an 720 x 540 snapshot (target: 30 ms or less), and its parts. Each checks its
// result: an 720 x 540 frame that is not blank, a PNG file whose header says 720 x 540.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <string>

#include "engines/engine.hpp"
#include "harness/runner.hpp"
#include "reports/gl_render.hpp"
#include "reports/scene_build.hpp"

using namespace liftcheck;

namespace {

const RunResult& circle_run() {
  static const RunResult run = run_scenario(*find_scenario("car.circle"), *find_engine("analytic"));
  return run;
}

render::Scene end_scene() {
  for (auto& s : render::snapshots_for(circle_run(), render::color_from_hex(find_engine("analytic")->color)))
    if (s.tag == "end") return s.scene;
  return {};
}

/// Empty when the frame is 720 x 540 and shows something (not every pixel the same).
std::string frame_problem(const render::Image& img) {
  if (img.width != 720 || img.height != 540 || img.rgba.size() != 720u * 540u * 4u)
    return fmt::format("the frame is {} x {} ({} bytes)", img.width, img.height, img.rgba.size());
  const std::uint8_t* first = img.pixel(0, 0);
  for (int y = 0; y < img.height; ++y)
    for (int x = 0; x < img.width; ++x)
      if (!std::equal(first, first + 4, img.pixel(x, y))) return "";
  return "the frame is blank";
}

/// Empty when `path` is a PNG file whose IHDR chunk says 720 x 540 and that holds image data.
std::string png_problem(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  std::string head(24, '\0');
  if (!in.read(head.data(), head.size())) return "no PNG written";
  const auto be32 = [&](int at) {
    return (std::uint32_t(std::uint8_t(head[at])) << 24) | (std::uint32_t(std::uint8_t(head[at + 1])) << 16) |
           (std::uint32_t(std::uint8_t(head[at + 2])) << 8) | std::uint32_t(std::uint8_t(head[at + 3]));
  };
  if (head.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 || head.compare(12, 4, "IHDR") != 0) return "not a PNG file";
  if (be32(16) != 720 || be32(20) != 540) return fmt::format("the PNG is {} x {}", be32(16), be32(20));
  if (std::filesystem::file_size(path) < 1000)
    return fmt::format("the PNG has only {} bytes", std::filesystem::file_size(path));
  return "";
}

void BM_Render720x540(benchmark::State& state) {
  render::Renderer r;
  const render::Scene scene = end_scene();
  r.render(scene);  // context creation and shader compilation happen once
  for (auto _ : state) benchmark::DoNotOptimize(r.render(scene));
  if (const std::string p = frame_problem(r.render(scene)); !p.empty()) state.SkipWithError(p.c_str());
}
BENCHMARK(BM_Render720x540)->Unit(benchmark::kMillisecond);

void BM_EncodePng720x540(benchmark::State& state) {
  render::Renderer r;
  const render::Image img = r.render(end_scene());
  const auto path = std::filesystem::temp_directory_path() / "liftcheck_bench.png";
  for (auto _ : state) render::write_png(path, img);
  const std::string p = png_problem(path);
  if (!p.empty())
    state.SkipWithError(p.c_str());
  else
    state.counters["png_bytes"] = static_cast<double>(std::filesystem::file_size(path));
  std::filesystem::remove(path);
}
BENCHMARK(BM_EncodePng720x540)->Unit(benchmark::kMillisecond);

void BM_RenderAndEncode720x540(benchmark::State& state) {
  render::Renderer r;
  const render::Scene scene = end_scene();
  r.render(scene);
  const auto path = std::filesystem::temp_directory_path() / "liftcheck_bench.png";
  for (auto _ : state) render::write_png(path, r.render(scene));
  std::string p = frame_problem(r.render(scene));
  if (p.empty()) p = png_problem(path);
  if (!p.empty())
    state.SkipWithError(p.c_str());
  else
    state.counters["png_bytes"] = static_cast<double>(std::filesystem::file_size(path));
  std::filesystem::remove(path);
}
BENCHMARK(BM_RenderAndEncode720x540)->Unit(benchmark::kMillisecond);

}  // namespace
