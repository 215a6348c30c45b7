#include "cli/suite_output.hpp"

#include <cstdlib>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <fcntl.h>
#include <system_error>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <iostream>
#include <cmath>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include "cli/baseline.hpp"
#include "cli/interrupts.hpp"
#include "harness/suite_plan.hpp"
#include "harness/suite_results.hpp"
#include "harness/worker_pool.hpp"  // set_memory_limit
#include "input/atomic_file.hpp"
#include "input/results_codec.hpp"
#include "input/results_file.hpp"
#include "input/standing.hpp"
#include "input/params.hpp"  // InputError
#include "input/trace.hpp"   // printable
#include "reports/ci.hpp"
#include "reports/report.hpp"

namespace liftcheck::cli {

namespace {

/// Sweeps are a gate: each engine's entry in each sweep passes or names its problems.
void print_failed_gates(const SuiteResults& results) {
  for (const GateRef& g : gates_of(results))
    if (!g.gate->pass)
      std::cout << fmt::format("FAIL   sweep {} on {}: {}\n", g.sweep, printable(g.engine, 200),
                               printable(fmt::format("{}", fmt::join(g.gate->problems, "; ")), 1000));
}

/// Where summary.md points for the report: LIFTCHECK_REPORT_URL when set; on a CI run the run's
/// page, whose artifacts hold the report (GITHUB_SERVER_URL/GITHUB_REPOSITORY/actions/runs/
/// GITHUB_RUN_ID); otherwise the report beside it. A pull-request comment needs an absolute link.
std::string report_link() {
  const auto env = [](const char* k) {
    const char* v = std::getenv(k);
    return std::string(v ? v : "");
  };
  if (!env("LIFTCHECK_REPORT_URL").empty()) return env("LIFTCHECK_REPORT_URL");
  if (!env("GITHUB_SERVER_URL").empty() && !env("GITHUB_REPOSITORY").empty() && !env("GITHUB_RUN_ID").empty())
    return fmt::format("{}/{}/actions/runs/{}", env("GITHUB_SERVER_URL"), env("GITHUB_REPOSITORY"),
                       env("GITHUB_RUN_ID"));
  return "index.html";
}

/// The renderer's exit status when an allocation failed under its limit.
constexpr int kRendererOutOfMemory = 4;

/// The renderer's end as a report error: past its memory limit, or how its process ended.
std::string renderer_problem(int status, double limit_mib) {
  if (WIFEXITED(status) && WEXITSTATUS(status) == kRendererOutOfMemory)
    return fmt::format(
        "report: the renderer needed more than its limit of {:g} MiB of address space (--report-memory-limit), "
        "stopped; "
        "the runs' results are written, the report is not",
        limit_mib);
  const std::string how = WIFSIGNALED(status)
                              ? fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)))
                              : fmt::format("exited with status {}", WEXITSTATUS(status));
  return fmt::format(
      "report: the renderer's process {} (its limit: {:g} MiB of address space); the runs' results are written, the "
      "report is not whole",
      how, limit_mib);
}

/// The renderer's side of the fork: its address space limited, the report written, its index of
/// files sent back on `fd`. Never returns.
[[noreturn]] void render_in_child(SuiteResults& results, const std::filesystem::path& out, const ReportDef& def,
                                  double limit_mib, int fd) {
  int status = 0;
  try {
    set_memory_limit(limit_mib);  // as a worker's (none under AddressSanitizer, whose shadow memory needs terabytes)
    write_report(results, out, def);
    const std::string text = encode_report(*results.report).dump();
    for (std::size_t done = 0; done < text.size();) {
      const ssize_t put = ::write(fd, text.data() + done, text.size() - done);
      if (put < 0 && errno == EINTR) continue;
      if (put <= 0) break;
      done += static_cast<std::size_t>(put);
    }
  } catch (const std::bad_alloc&) {
    status = kRendererOutOfMemory;
  } catch (const std::system_error& e) {
    // A thread whose stack cannot be mapped under the limit is the same shortage.
    const bool memory =
        e.code() == std::errc::resource_unavailable_try_again || e.code() == std::errc::not_enough_memory;
    if (!memory) std::cerr << "liftcheck: report: " << e.what() << "\n";
    status = memory ? kRendererOutOfMemory : 3;
  } catch (const std::exception& e) {
    std::cerr << "liftcheck: report: " << e.what() << "\n";
    status = 3;
  }
  std::cout.flush();
  std::fflush(nullptr);
  ::_exit(status);
}

/// The report rendered in a child process (fork) under its memory limit: a renderer that crashes
/// or runs out of memory takes only the child, and the runs' results are written anyway, with the
/// renderer's end as a report error.
void write_report_isolated(SuiteResults& results, const std::filesystem::path& out, const ReportDef& def,
                           double limit_mib) {
  int fds[2];
  if (::pipe2(fds, O_CLOEXEC) != 0)
    throw std::runtime_error(fmt::format("cannot create a pipe for the report: {}", std::strerror(errno)));
  std::cout.flush();
  std::fflush(nullptr);
  const pid_t pid = ::fork();
  if (pid < 0) throw std::runtime_error(fmt::format("cannot start the report's process: {}", std::strerror(errno)));
  if (pid == 0) {
    ::close(fds[0]);
    render_in_child(results, out, def, limit_mib, fds[1]);
  }
  ::close(fds[1]);
  std::string text;
  char buf[65536];
  for (;;) {
    const ssize_t got = ::read(fds[0], buf, sizeof buf);
    if (got > 0) {
      text.append(buf, static_cast<std::size_t>(got));
      if (text.size() > (std::size_t{256} << 20)) break;  // bounded: the report's own index of files
      continue;
    }
    if (got < 0 && errno == EINTR) {
      if (pending_signal()) ::kill(pid, SIGKILL);
      continue;
    }
    break;
  }
  ::close(fds[0]);
  int status = 0;
  while (::waitpid(pid, &status, 0) < 0 && errno == EINTR) {}
  throw_if_interrupted("while rendering the report");
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0) {
    const nlohmann::json report = nlohmann::json::parse(text, nullptr, false);
    try {
      static const std::string kName = "the renderer's index of files";
      if (!report.is_discarded()) return void(results.report = decode_report(JsonIn(report, kName, "report")));
    } catch (const InputError&) {}
  }
  results.report = ReportInfo{};
  results.report->errors.push_back(renderer_problem(status, limit_mib));
}

/// summary.md's and the console's pointer to the report: only to an index.html that was written.
bool index_written(const std::filesystem::path& dir) {
  std::error_code ec;
  return std::filesystem::is_regular_file(dir / "index.html", ec);
}

/// The report, junit.xml, summary.md and results.json into the staged folder, which is then
/// swapped in. A baseline to rewrite is written beside its place first and renamed in last, so
/// each failure says truthfully what was written.
void write_outputs(SuiteResults& results, const OutputOptions& o, StagedOutput& staged) {
  const std::filesystem::path out = staged.stage();
  for (RunResult& r : results.runs) thin_drawn_traces(r.details);  // the report draws what results.json keeps
  try {
    if (o.report) {
      ReportDef def;
      def.snapshots = o.snapshots;
      def.threads = o.threads;
      write_report_isolated(results, out, def, o.report_memory_limit_mib);
      const ReportInfo& rep = *results.report;
      std::cout << fmt::format(
          "report {:.2f} s ({} snapshots, {} strips, {} plots){}\n", rep.report_s, rep.snapshots.size(),
          rep.strips.size(), rep.plots.size(),
          rep.errors.empty() ? ""
                             : fmt::format("; {} problems{}", rep.errors.size(),
                                           index_written(out) ? ", see index.html" : ", its pages are not written"));
    }
    write_file_atomic(out / "junit.xml", junit_xml(results));
    write_file_atomic(out / "summary.md",
                      summary_markdown(results, o.report && index_written(out) ? report_link() : ""));
    write_file_atomic(out / "results.json", results_text(results));
    throw_if_interrupted("while writing the outputs");
    const std::string pending = o.baseline_path + ".new";
    if (o.update_baseline) {
      try {
        write_file_atomic(pending, encode_baseline(results).dump(1) + "\n");
      } catch (const std::runtime_error& e) {
        throw InputError(fmt::format("{}; nothing is written (--out is as it was, the baseline too)", e.what()));
      }
    }
    try {
      staged.publish();
    } catch (...) {
      if (o.update_baseline) std::remove(pending.c_str());
      throw;
    }
    if (o.update_baseline) {
      if (std::rename(pending.c_str(), o.baseline_path.c_str()) != 0 && (std::remove(pending.c_str()), true))
        throw InputError(fmt::format(
            "cannot write the baseline '{}': {}; the output folder '{}' is written, the baseline is as it was",
            printable(o.baseline_path, 200), std::strerror(errno), printable(staged.final_path().string(), 200)));
      std::cout << "baseline written: " << printable(o.baseline_path, 200) << "\n";
    }
  } catch (const Interrupted&) {
    throw;
  } catch (const std::runtime_error& err) {
    throw InputError(err.what());
  }
}

/// The simulated seconds the suite stepped, in all and per configuration, by kind of part.
void print_simulated(const SuiteResults& results) {
  const SimulatedBudget& sim = results.simulated;
  if (sim.by_part.empty()) return;
  const auto kinds = [](const std::map<std::string, double>& by_part) {
    std::map<std::string, double> k;
    for (const auto& [part, s] : by_part) k[part.substr(0, part.find('/'))] += s;
    std::string out;
    for (const auto& [kind, s] : k) out += fmt::format("{}{} {:.1f}", out.empty() ? "" : ", ", kind, s);
    return out;
  };
  std::cout << fmt::format("simulated time: {:.1f} s in all ({})\n", sim.total_s, kinds(sim.by_part));
  for (const auto& [config, parts] : sim.by_configuration)
    std::cout << fmt::format("  {:<18} {:8.1f} s  ({})\n", printable(config, 200), sim.configuration_total_s.at(config),
                             kinds(parts));
}

/// Each configuration's standing, as every output states it (input/standing.hpp).
void print_standings(const SuiteResults& results) {
  for (const Standing& s : standings(results)) {
    std::string line = fmt::format("  {:<18} {}", printable(s.engine, 60), s.counts_text());
    if (s.worst) line += "; worst " + s.worst_text();
    std::cout << printable(line, 118) << "\n";
  }
}

/// The last lines: every run not as expected, the verdict counts and where the results are.
void print_summary(const SuiteResults& results, const OutputOptions& o, const StagedOutput& staged) {
  print_simulated(results);
  print_standings(results);
  const Summary sum = summarize(results);
  std::cout << fmt::format(
      "{}: {} runs, {} sweep gates: {} unexpected ({} pass, {} known, {} unexpected pass, {} fail, {} error, "
      "{} skip; {} gates failed)\n{}\n",
      results.shard ? fmt::format("shard {}/{}", results.shard->index, results.shard->total) : "validate", sum.total,
      sum.sweep_gates, sum.unexpected(), sum.pass, sum.known, sum.unexpected_pass, sum.fail, sum.error, sum.skip,
      sum.sweep_gates_failed,
      printable(o.report && index_written(staged.final_path())
                    ? "report: " + (staged.final_path() / "index.html").string()
                    : "results: " + (staged.final_path() / "results.json").string(),
                300));
}

}  // namespace

void add_report_memory_option(CLI::App* cmd, OutputOptions& o) {
  cmd->add_option(
         "--report-memory-limit", o.report_memory_limit_mib,
         "limit of the report renderer's address space in MiB: past it the report is an error, the results are written")
      ->capture_default_str()
      ->check([](const std::string& v) {
        double mib = 0.0;
        try {
          mib = std::stod(v);
        } catch (const std::exception&) {}
        return mib >= 64.0 && std::isfinite(mib) ? std::string()
                                                 : fmt::format("--report-memory-limit {} must be at least 64 MiB", v);
      });
}

void add_worse_factor_option(CLI::App* cmd, OutputOptions& o) {
  cmd->add_option("--worse-factor", o.worse_factor,
                  "with --baseline: a counted metric whose error grows by more than this factor is worse and exits 1 "
                  "(every change is listed as moved)")
      ->capture_default_str()
      ->check([](const std::string& v) {
        double f = 0.0;
        try {
          f = std::stod(v);
        } catch (const std::exception&) {}
        return f > 1.0 && std::isfinite(f) ? std::string() : fmt::format("--worse-factor {} must be above 1", v);
      });
}

namespace {

/// The report's problems, a line each; their number.
int print_report_problems(const SuiteResults& results, const OutputOptions& o) {
  if (!o.report || !results.report) return 0;
  for (const auto& e : results.report->errors) std::cout << "REPORT " << printable(e, 1000) << "\n";
  return static_cast<int>(results.report->errors.size());
}

/// The outputs written, the closing lines printed; the exit status.
int write_and_close(SuiteResults& results, const OutputOptions& o, StagedOutput& staged) {
  write_outputs(results, o, staged);
  const int report_problems = print_report_problems(results, o);
  print_summary(results, o, staged);
  if (report_problems > 0)
    std::cout << fmt::format("the report has {} problem{} (listed above{})\n", report_problems,
                             report_problems == 1 ? "" : "s",
                             index_written(staged.final_path()) ? " and in index.html" : "");
  // A report that could not be built counts: the suite is not whole without it.
  return summarize(results).all_as_expected() && report_problems == 0 ? 0 : 1;
}

}  // namespace

int finish_suite(SuiteResults& results, const OutputOptions& o, const std::optional<SuiteResults>& baseline,
                 StagedOutput& staged) {
  print_failed_gates(results);
  if (baseline) compare_with_baseline(results, o.baseline_path, *baseline, o.worse_factor);
  return write_and_close(results, o, staged);
}

int render_again(SuiteResults& results, const OutputOptions& o, StagedOutput& staged) {
  return write_and_close(results, o, staged);
}

}  // namespace liftcheck::cli
