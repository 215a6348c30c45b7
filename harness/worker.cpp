// The worker process (`liftcheck worker`): reads a request a line, runs its item, writes its record.
#include "harness/worker_pool.hpp"

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fmt/format.h>
#include <iostream>
#include <memory>
#include <csignal>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <unistd.h>

#include "harness/external.hpp"
#include "harness/results.hpp"
#include "input/results_codec.hpp"
#include "input/results_file.hpp"  // thin_drawn_traces
#include "harness/runner.hpp"
#include "input/trace.hpp"

namespace liftcheck {

RunResult error_record(const SuiteItem& item, const std::string& message) {
  RunResult r = error_result(item.scenario->name, item.engine->name, item.scenario->vehicle, message);
  r.negative_control = item.scenario->negative_control;
  r.judge();
  return r;
}

namespace {

/// The memory limit in force in this worker (MiB; 0: none).
double g_memory_limit_mib = 0.0;

/// Test hook (tests/cli_test.sh): LIFTCHECK_TEST_ALLOCATE=SCENARIO makes that scenario's run allocate
/// without bound, to show that the limit turns it into an error record. Only under a limit: without
/// one it does nothing, so it can never take memory from the machine.
void test_hook_allocate(const SuiteItem& item) {
  const char* which = std::getenv("LIFTCHECK_TEST_ALLOCATE");
  if (!which || item.scenario->name != which || !(g_memory_limit_mib > 0.0)) return;
  std::vector<std::unique_ptr<char[]>> blocks;
  for (;;) {
    blocks.emplace_back(new char[std::size_t{16} << 20]);
    std::memset(blocks.back().get(), 1, std::size_t{16} << 20);
  }
}

std::string out_of_memory() {
  return fmt::format(
      "out of memory: the run needed more than its limit of {:g} MiB of address space (--memory-limit), stopped",
      g_memory_limit_mib);
}

}  // namespace

#if defined(__SANITIZE_ADDRESS__)
#define LIFTCHECK_ASAN 1
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define LIFTCHECK_ASAN 1
#endif
#endif

void set_memory_limit(double mib) {
#ifdef LIFTCHECK_ASAN
  // AddressSanitizer maps terabytes of shadow memory: under any RLIMIT_AS its first allocation fails.
  // The sanitized build (make sanitize) runs without the limit.
  (void)mib;
#else
  if (!(mib > 0.0) || !std::isfinite(mib)) return;
  rlimit r{};
  if (getrlimit(RLIMIT_AS, &r) != 0) return;
  const double bytes = mib * 1048576.0;
  r.rlim_cur =
      r.rlim_max == RLIM_INFINITY || bytes < static_cast<double>(r.rlim_max) ? static_cast<rlim_t>(bytes) : r.rlim_max;
  if (setrlimit(RLIMIT_AS, &r) == 0)
    g_memory_limit_mib = static_cast<double>(r.rlim_cur) / 1048576.0;  // a lower hard limit holds
#endif
}

namespace {

/// The record of a run whose drive later runs judge too, with theirs in its `shared` list.
RunResult shared_drive_record(const SuiteItem& item) {
  std::vector<ResolvedRun> runs{*item.run};
  runs.insert(runs.end(), item.drive_judges.begin(), item.drive_judges.end());
  std::vector<RunResult> records = run_shared_drive(runs);
  RunResult r = std::move(records.front());
  for (size_t i = 1; i < records.size(); ++i) r.shared.push_back(std::move(records[i]));
  return r;
}

/// What results.json keeps of a record: a run's drawn traces thinned, a point's dropped.
void keep_for_results(const SuiteItem& item, RunResult& r) {
  if (item.kind == SuiteItem::kPoint) return trim_to_point(r);
  if (item.full_traces) return;
  thin_drawn_traces(r.details);
  for (RunResult& s : r.shared) thin_drawn_traces(s.details);
}

}  // namespace

RunResult run_item(const SuiteItem& item) {
  RunResult r;
  try {
    test_hook_allocate(item);
    if (!item.run) throw InputError(item.resolve_error);  // its error record, as the run would give it
    r = item.drive_judges.empty() ? run_scenario(*item.run) : shared_drive_record(item);
  } catch (const std::bad_alloc&) {
    r = error_record(item, g_memory_limit_mib > 0.0 ? out_of_memory() : "out of memory (std::bad_alloc)");
  } catch (const std::exception& err) {  // values rejected by the scenario (a defect at the defaults): reported per run
    r = error_record(item, err.what());
    r.input_error = dynamic_cast<const InputError*>(&err) != nullptr;  // `run` turns it into a usage error (exit 2)
  }
  keep_for_results(item, r);
  return r;
}

nlohmann::json item_request(const SuiteItem& item) {
  nlohmann::json j{{"kind", item.kind == SuiteItem::kRun ? "run" : "point"},
                   {"scenario", item.scenario->name},
                   {"engine", item.engine->name}};
  if (item.run)
    j["run"] = resolved_values(*item.run);
  else
    j["resolve_error"] = item.resolve_error;
  if (!item.drive_judges.empty()) {
    j["drive_judges"] = nlohmann::json::array();
    for (const ResolvedRun& judge : item.drive_judges)
      j["drive_judges"].push_back({{"scenario", judge.scenario->name}, {"run", resolved_values(judge)}});
  }
  if (item.owned) j["trace_file"] = item.trace_file;
  if (item.full_traces) j["full_traces"] = true;
  return j;
}

namespace {

/// The item's CPU-time limit, counted by the worker itself from the moment it starts the item:
/// neither the worker's start-up nor the time it waited for a core counts, so a verdict does not
/// depend on --jobs or on what else the machine runs. SIGXCPU-like: SIGPROF ends the worker.
void arm_cpu_limit(double seconds) {
  itimerval t{};
  if (seconds > 0.0 && std::isfinite(seconds)) {
    const double whole = std::floor(seconds);
    t.it_value.tv_sec = static_cast<time_t>(std::min(whole, 1e9));
    t.it_value.tv_usec = static_cast<suseconds_t>((seconds - whole) * 1e6);
    if (t.it_value.tv_sec == 0 && t.it_value.tv_usec == 0) t.it_value.tv_usec = 1;
  }
  setitimer(ITIMER_PROF, &t, nullptr);
}

}  // namespace

SuiteItem item_from_request(const nlohmann::json& j) {
  SuiteItem it;
  it.kind = j.at("kind") == "run" ? SuiteItem::kRun : SuiteItem::kPoint;
  it.scenario = find_scenario(j.at("scenario").get<std::string>());
  if (!it.scenario) throw InputError(fmt::format("worker: unknown scenario '{}'", j.at("scenario").get<std::string>()));
  const std::string engine = j.at("engine");
  if (j.contains("trace_file")) {
    it.trace_file = j.at("trace_file");
    it.owned = std::make_shared<const EngineInfo>(
        replay_engine(engine, *it.scenario, read_trace(it.trace_file, it.scenario->vehicle)));
    it.engine = it.owned.get();
  } else {
    it.engine = find_engine(engine);
    if (!it.engine) throw InputError(fmt::format("worker: unknown configuration '{}'", engine));
  }
  if (j.contains("run"))
    it.run = resolved_from_values(*it.scenario, *it.engine, j.at("run"));
  else
    it.resolve_error = j.at("resolve_error").get<std::string>();
  for (const auto& judge : j.value("drive_judges", nlohmann::json::array())) {
    const std::string name = judge.at("scenario");
    const Scenario* s = find_scenario(name);
    if (!s || !s->shared_drive || !it.scenario->shared_drive ||
        s->shared_drive->name != it.scenario->shared_drive->name)
      throw InputError(fmt::format("worker: '{}' does not judge the drive of '{}'", name, it.scenario->name));
    it.drive_judges.push_back(resolved_from_values(*s, *it.engine, judge.at("run")));
  }
  it.key = j.value("key", "");
  it.full_traces = j.value("full_traces", false);
  return it;
}

int worker_main() {
  // Ends with liftcheck: a worker whose parent was killed must not run on (a hung engine never would stop).
  prctl(PR_SET_PDEATHSIG, SIGKILL);
  if (getppid() == 1) return 3;
  // Records go to the original stdout; anything an engine prints there goes to stderr instead.
  const int records_fd = ::dup(STDOUT_FILENO);
  ::dup2(STDERR_FILENO, STDOUT_FILENO);
  std::string line;
  while (std::getline(std::cin, line)) {
    if (line.empty()) continue;
    const nlohmann::json request = nlohmann::json::parse(line);
    const SuiteItem it = item_from_request(request);
    set_memory_limit(request.value("memory_limit_mib", 0.0));
    arm_cpu_limit(request.value("cpu_limit_s", 0.0));
    const std::string text = encode_run(run_item(it), RecordForm::kPipe).dump() + "\n";
    arm_cpu_limit(0.0);
    if (!write_all(records_fd, text)) return 3;
  }
  return 0;
}

bool write_all(int fd, const std::string& text) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t put = ::write(fd, text.data() + done, text.size() - done);
    if (put < 0 && errno == EINTR) continue;
    if (put <= 0) return false;
    done += static_cast<size_t>(put);
  }
  return true;
}

}  // namespace liftcheck
