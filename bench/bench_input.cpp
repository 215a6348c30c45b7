// Reading results files back: `liftcheck diff` of two results files of N runs each (the index of
// each, read with the depth and duplicate-key checks and the field checks, then the diff itself).
// Linear in N (the pairing sorts N hashes).
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>
#include <fcntl.h>
#include <spawn.h>
#include <string>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

#include "input/results_codec.hpp"
#include "input/results_file.hpp"
#include "input/results_diff.hpp"

namespace {

/// A results file of `n` runs, one metric each, as liftcheck writes them (no details): each run
/// encoded by the codec, in the document the codec writes around them. The runs are encoded one by
/// one and joined (a document of a million runs held whole would take 7 GB), so the document's
/// summary, which no reader reads back, is written for its n passing runs by hand.
std::string results_file_text(long n) {
  liftcheck::Metric m{.name = std::string("front_radius"),
                      .unit = std::string("m"),
                      .expected = 1.0,
                      .measured = 1.0000001,
                      .abs_error = 1e-7,
                      .rel_error = 1e-7,
                      .tolerance = 1e-6,
                      .kind = liftcheck::TolKind::kRelative};
  m.pass = m.passes_by_figures();
  liftcheck::SuiteResults frame;
  frame.context.version = "0";
  nlohmann::json doc = liftcheck::encode_results(frame);
  doc["summary"]["total"] = n;
  doc["summary"]["pass"] = n;
  std::string runs;
  for (long i = 0; i < n; ++i) {
    liftcheck::RunResult r;
    r.scenario = fmt::format("s{}", i), r.engine = "ode", r.status = liftcheck::Status::kPass;
    r.metrics = {m};
    r.judge();
    runs += (i ? "," : "") + liftcheck::encode_run(r).dump();
  }
  std::string text = doc.dump();
  const std::string empty = R"("runs":[])";
  return text.replace(text.find(empty), empty.size(), R"("runs":[)" + runs + "]");
}

void BM_DiffResults(benchmark::State& state) {
  const std::string text = results_file_text(state.range(0));
  for (auto _ : state) {
    // What `diff` reads: the index of each file (every check, no document).
    const liftcheck::ResultsIndex base = liftcheck::parse_results_index(text, "base.json"),
                                  head = liftcheck::parse_results_index(text, "head.json");
    benchmark::DoNotOptimize(liftcheck::diff_results(base, head));
  }
  state.SetComplexityN(state.range(0));
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations()) * 2 * static_cast<int64_t>(text.size()));
}
BENCHMARK(BM_DiffResults)->Arg(10000)->Arg(100000)->Unit(benchmark::kMillisecond)->Complexity(benchmark::oN);
BENCHMARK(BM_DiffResults)->Arg(1000000)->Iterations(1)->Unit(benchmark::kMillisecond);

/// The command itself, as a user runs it: `liftcheck diff A B` of two results files of N runs, in a
/// process of its own (reading, parsing both in parallel, checking, comparing, printing, exiting).
/// Counters: `cpu_s` its user + system CPU time, `wall_s` its wall-clock time (the benchmark's time).
void BM_DiffCommand(benchmark::State& state) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / fmt::format("liftcheck-bench-diff-{}", getpid());
  std::filesystem::create_directories(dir);
  const std::string a = (dir / "a.json").string(), b = (dir / "b.json").string();
  {
    const std::string text = results_file_text(state.range(0));
    std::ofstream(a) << text;
    std::ofstream(b) << text;
  }
  double cpu_s = 0.0;
  for (auto _ : state) {
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, "/dev/null", O_WRONLY, 0);
    std::string exe = LIFTCHECK_EXE, cmd = "diff";
    char* argv[] = {exe.data(), cmd.data(), const_cast<char*>(a.c_str()), const_cast<char*>(b.c_str()), nullptr};
    rusage before{}, after{};
    getrusage(RUSAGE_CHILDREN, &before);
    const auto t0 = std::chrono::steady_clock::now();
    pid_t pid = -1;
    int status = -1;
    if (posix_spawn(&pid, exe.c_str(), &fa, nullptr, argv, environ) == 0) waitpid(pid, &status, 0);
    posix_spawn_file_actions_destroy(&fa);
    state.SetIterationTime(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    getrusage(RUSAGE_CHILDREN, &after);
    const auto secs = [](const timeval& t) {
      return static_cast<double>(t.tv_sec) + 1e-6 * static_cast<double>(t.tv_usec);
    };
    cpu_s = secs(after.ru_utime) - secs(before.ru_utime) + secs(after.ru_stime) - secs(before.ru_stime);
    if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) state.SkipWithError("liftcheck diff did not exit 0");
  }
  state.counters["cpu_s"] = cpu_s;
  state.counters["bytes_per_file"] = static_cast<double>(std::filesystem::file_size(a));
  std::filesystem::remove_all(dir);
}
BENCHMARK(BM_DiffCommand)->Arg(1000000)->Iterations(1)->UseManualTime()->Unit(benchmark::kMillisecond);

}  // namespace
