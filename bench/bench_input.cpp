// Reading results files back: `liftcheck diff` of two results files of N runs each (parse with the
// depth and duplicate-key checks, field checks, the diff itself). Linear in N.
#include <benchmark/benchmark.h>

#include <fmt/format.h>
#include <string>

#include "input/results_file.hpp"
#include "input/results_diff.hpp"

namespace {

/// A results file of `n` runs, one metric each, as liftcheck writes them (no details).
std::string results_text(long n) {
  std::string t = R"({"context": {"liftcheck": {"version": "0"}}, "runs": [)";
  for (long i = 0; i < n; ++i)
    t += fmt::format(R"({}{{"scenario": "s{}", "engine": "ode", "status": "pass", "verdict": "pass", "as_expected": true, "message": "", )"
                     R"("metrics": {{"front_radius": {{"expected": 1.0, "measured": 1.0000001, "abs_error": 1e-7, "rel_error": 1e-7, )"
                     R"("tolerance": 1e-6, "tolerance_kind": "rel", "unit": "m", "pass": true}}}}}})",
                     i ? "," : "", i);
  return t + "]}";
}

void BM_DiffResults(benchmark::State& state) {
  const std::string text = results_text(state.range(0));
  for (auto _ : state) {
    const nlohmann::json base = liftcheck::parse_results(text, "base.json"), head = liftcheck::parse_results(text, "head.json");
    benchmark::DoNotOptimize(liftcheck::diff_results(base, head));
  }
  state.SetComplexityN(state.range(0));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * 2 * static_cast<int64_t>(text.size()));
}
BENCHMARK(BM_DiffResults)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);
BENCHMARK(BM_DiffResults)->Arg(1000000)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace
