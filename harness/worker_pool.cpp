#include "harness/worker_pool.hpp"

#include "input/results_codec.hpp"

#include <algorithm>
#include <optional>
#include <chrono>
#include <fmt/format.h>
#include <fnmatch.h>
#include <set>
#include <thread>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fcntl.h>
#include <filesystem>
#include <iostream>
#include <poll.h>
#include <sys/prctl.h>
#include <sys/resource.h>
#include <sys/time.h>
#include <sched.h>
#include <cmath>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

extern char** environ;

#include "engines/protocol/child.hpp"  // end_adapters_of
#include "harness/results.hpp"
#include "harness/runner.hpp"
#include "input/suggest.hpp"

namespace liftcheck {

namespace {

/// The last non-empty line of a worker's stderr, for the error record of a run that ended it.
std::string last_line(const std::string& text) {
  size_t end = text.find_last_not_of("\r\n");
  if (end == std::string::npos) return "";
  const size_t start = text.find_last_of('\n', end);
  return text.substr(start == std::string::npos ? 0 : start + 1,
                     end - (start == std::string::npos ? 0 : start + 1) + 1);
}

struct Worker {
  pid_t pid = -1;
  int in_fd = -1, out_fd = -1, err_fd = -1;
  std::string out, err;  ///< what it wrote since its current item began
  long slot = -1;        ///< the item it runs (-1: idle)
  std::chrono::steady_clock::time_point started;
};

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

/// Starts `liftcheck worker` from `exe` (a path; "/proc/self/fd/N" for the running binary's own
/// open file), showing `shown` as its argv[0].
Worker spawn_worker(const std::string& exe, const std::string& shown) {
  int in[2], out[2], err[2];
  if (pipe2(in, O_CLOEXEC) != 0 || pipe2(out, O_CLOEXEC) != 0 || pipe2(err, O_CLOEXEC) != 0)
    throw std::runtime_error(fmt::format("cannot create pipes for a worker process: {}", std::strerror(errno)));
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, in[0], 0);
  posix_spawn_file_actions_adddup2(&fa, out[1], 1);
  posix_spawn_file_actions_adddup2(&fa, err[1], 2);
  std::string arg0 = shown, arg1 = "worker";
  char* argv[] = {arg0.data(), arg1.data(), nullptr};
  // Its own process group: a terminal's Ctrl-C reaches liftcheck, which stops its workers itself.
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETPGROUP);
  posix_spawnattr_setpgroup(&attr, 0);
  Worker w;
  const int rc = posix_spawn(&w.pid, exe.c_str(), &fa, &attr, argv, environ);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  ::close(in[0]), ::close(out[1]), ::close(err[1]);
  if (rc != 0) {
    ::close(in[1]), ::close(out[0]), ::close(err[0]);
    throw std::runtime_error(fmt::format("cannot start a worker process '{}' ({}): {}", shown, exe, std::strerror(rc)));
  }
  w.in_fd = in[1], w.out_fd = out[0], w.err_fd = err[0];
  fcntl(w.out_fd, F_SETFL, O_NONBLOCK);
  fcntl(w.err_fd, F_SETFL, O_NONBLOCK);
  return w;
}

/// Reads what is there; false at end of file.
bool drain(int fd, std::string& into) {
  char buf[65536];
  for (;;) {
    const ssize_t got = ::read(fd, buf, sizeof buf);
    if (got > 0) {
      into.append(buf, static_cast<size_t>(got));
      continue;
    }
    if (got == 0) return false;
    if (errno == EINTR) continue;
    return true;  // EAGAIN: nothing more for now
  }
}

/// The engine's warnings: passed on, the end kept for an error record.
void pass_on_stderr(Worker& w) {
  if (w.err_fd < 0) return;
  const size_t before = w.err.size();
  drain(w.err_fd, w.err);
  if (w.err.size() > before)
    std::cerr.write(w.err.data() + before, static_cast<std::streamsize>(w.err.size() - before)).flush();
  if (w.err.size() > 8192) w.err.erase(0, w.err.size() - 8192);
}

/// Ends a worker (killed when `kill_it`, else by closing its input) and says how it ended; the
/// signal that ended it, if one did, in `signal`.
std::string end_worker(Worker& w, bool kill_it, int* signal = nullptr) {
  close_fd(w.in_fd);
  // Its process group, and the outside engines it started (each in a group of its own, found by
  // the worker's tag in their environment) with whatever they started: a hung engine goes with it.
  if (kill_it) ::kill(-w.pid, SIGKILL), ::kill(w.pid, SIGKILL);
  int status = 0;
  siginfo_t info{};
  while (waitid(P_PID, static_cast<id_t>(w.pid), &info, WEXITED | WNOWAIT) < 0 && errno == EINTR) {}
  end_adapters_of(w.pid);  // the worker is a zombie until reaped: its pid and start time still name it
  while (waitpid(w.pid, &status, 0) < 0 && errno == EINTR) {}
  pass_on_stderr(w);  // its last words, all in the pipe now
  close_fd(w.out_fd), close_fd(w.err_fd);
  w.pid = -1;
  if (signal) *signal = WIFSIGNALED(status) ? WTERMSIG(status) : 0;
  if (WIFSIGNALED(status))
    return fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)));
  return fmt::format("exited with status {}", WEXITSTATUS(status));
}

constexpr double kWallFactor = 4.0, kWallGrace_s = 30.0;

std::string timed_out(double timeout_s) {
  return fmt::format("timed out: still running after {:g} s of CPU time (--timeout), stopped", timeout_s);
}

/// The running executable's own file, kept open for the whole suite: workers start from it even
/// when the file at its path is deleted or replaced by another build (which would otherwise run the
/// rest of the suite under this build's name).
struct RunningBinary {
  int fd = -1;
  std::string path, shown;
  explicit RunningBinary(const std::string& exe) {
    std::error_code ec;
    shown = exe.empty() ? std::filesystem::read_symlink("/proc/self/exe", ec).string() : exe;
    if (const auto del = shown.rfind(" (deleted)"); del != std::string::npos && del + 10 == shown.size())
      shown.erase(del);
    if (!exe.empty()) {
      path = exe;
      return;
    }
    fd =
        ::open("/proc/self/exe", O_RDONLY | O_CLOEXEC);  // closed at each worker's exec, once the kernel holds the file
    if (fd < 0)
      throw std::runtime_error(
          fmt::format("cannot open the running executable /proc/self/exe: {}", std::strerror(errno)));
    path = fmt::format("/proc/self/fd/{}", fd);
  }
  ~RunningBinary() {
    if (fd >= 0) ::close(fd);
  }
  RunningBinary(const RunningBinary&) = delete;
  RunningBinary& operator=(const RunningBinary&) = delete;
};

}  // namespace

int usable_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0 && CPU_COUNT(&set) > 0) return CPU_COUNT(&set);
  return static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
}

namespace {

/// The CPUs this process may run on, in order (empty where the affinity cannot be read).
std::vector<int> usable_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  std::vector<int> cpus;
  if (sched_getaffinity(0, sizeof set, &set) != 0) return cpus;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &set)) cpus.push_back(c);
  return cpus;
}

/// Binds worker `pid` to `cpu`, before it is given an item: an outside engine it starts inherits
/// the binding, so the protocol's round trip between the two processes stays on one core (a
/// wake-up on the other core costs 10 to 40 us a step on a virtual machine; on one core the
/// round trip is about 14 us, make bench). Best effort: a binding refused leaves the worker free.
void bind_worker(pid_t pid, int cpu) {
  cpu_set_t set;
  CPU_ZERO(&set);
  CPU_SET(cpu, &set);
  (void)sched_setaffinity(pid, sizeof set, &set);
}

/// The cores of `jobs` workers: every usable core in order when they take them all; otherwise
/// `jobs` of them starting with the one this process runs on (empty where that cannot be read).
std::vector<int> worker_cpus(int jobs) {
  std::vector<int> cpus = usable_cpus();
  if (static_cast<int>(cpus.size()) <= jobs) return cpus;
  const int here = sched_getcpu();
  const auto at = std::find(cpus.begin(), cpus.end(), here);
  if (at == cpus.end()) return {};
  std::rotate(cpus.begin(), at, cpus.end());
  cpus.resize(static_cast<size_t>(jobs));
  return cpus;
}

}  // namespace

namespace {

/// The order items are handed out in: the runs first, so their lines appear early, then the
/// points; each longest first, ties in plan order. Workers never wait between the two.
std::vector<size_t> schedule_order(const SuitePlan& plan, const std::vector<size_t>& which) {
  std::vector<size_t> order(which.size());
  for (size_t k = 0; k < order.size(); ++k) order[k] = k;
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) {
    const SuiteItem &x = plan.items[which[a]], &y = plan.items[which[b]];
    return x.kind != y.kind ? x.kind == SuiteItem::kRun : x.cost > y.cost;
  });
  return order;
}

/// Hands out items in schedule order, keeping each outside configuration to one worker where it
/// can: its engine process (and the engine's compiled code) is warm in the worker that started it,
/// and a second worker pays the start-up again (for a WASM engine 0.2 to 2 s of CPU before its
/// steps reach full speed). A worker takes the first item left that is compiled in, of an outside
/// configuration it already runs, or of one no worker runs yet; when only other workers'
/// configurations are left, it takes the first of those rather than wait.
class Dispenser {
 public:
  Dispenser(const SuitePlan& plan, const std::vector<size_t>& which, std::vector<size_t> order)
      : plan_(plan), which_(which), order_(std::move(order)), handed_(order_.size(), 0) {}
  bool empty() const { return left_ == 0 || first_ >= order_.size(); }
  /// The next item (its index in `which`) for worker `w`.
  /// An outside configuration's items go to the worker that started its engine, and that worker
  /// takes them one after another: a worker keeps only the adapter of the configuration it runs
  /// (engines/protocol/child_pool.cpp), so each switch would start another.
  size_t next_for(size_t w) {
    while (first_ < order_.size() && handed_[first_]) ++first_;
    size_t pick = first_;
    const auto last = last_.find(w);
    bool same = false;
    if (last != last_.end())
      for (size_t k = first_; k < order_.size() && !same; ++k)
        if (!handed_[k] && plan_.items[which_[order_[k]]].engine == last->second) pick = k, same = true;
    for (size_t k = first_; k < order_.size() && !same; ++k)
      if (!handed_[k] && fits(order_[k], w)) {
        pick = k;
        break;
      }
    handed_[pick] = 1, --left_;
    const EngineInfo* e = plan_.items[which_[order_[pick]]].engine;
    if (e->is_outside()) owner_.emplace(e, w), last_[w] = e;
    return order_[pick];
  }

 private:
  bool fits(size_t i, size_t w) const {
    const EngineInfo* e = plan_.items[which_[i]].engine;
    if (!e->is_outside()) return true;
    const auto o = owner_.find(e);
    return o == owner_.end() || o->second == w;
  }
  const SuitePlan& plan_;
  const std::vector<size_t>& which_;
  std::vector<size_t> order_;
  std::vector<char> handed_;
  std::map<const EngineInfo*, size_t> owner_;
  std::map<size_t, const EngineInfo*> last_;  ///< the outside configuration each worker ran last
  size_t first_ = 0, left_ = order_.size();
};

/// Waits for output of the busy workers, an end or the nearest wall-clock limit; returns the
/// (worker, stdout?) pipes that are readable or closed.
std::vector<std::pair<size_t, bool>> poll_workers(const std::vector<Worker>& workers, double wall_limit_s) {
  std::vector<pollfd> fds;
  std::vector<std::pair<size_t, bool>> whose, ready;  // worker, stdout?
  double wait_s = 0.25;
  for (size_t k = 0; k < workers.size(); ++k) {
    const Worker& w = workers[k];
    if (w.slot < 0) continue;
    fds.push_back({w.out_fd, POLLIN, 0}), whose.emplace_back(k, true);
    fds.push_back({w.err_fd, POLLIN, 0}), whose.emplace_back(k, false);
    wait_s = std::min(
        wait_s, wall_limit_s - std::chrono::duration<double>(std::chrono::steady_clock::now() - w.started).count());
  }
  if (!fds.empty() && poll(fds.data(), fds.size(), static_cast<int>(std::max(0.0, wait_s) * 1000.0) + 1) < 0 &&
      errno != EINTR)
    throw std::runtime_error(fmt::format("poll: {}", std::strerror(errno)));
  for (size_t f = 0; f < fds.size(); ++f)
    if (fds[f].revents & (POLLIN | POLLHUP | POLLERR)) ready.push_back(whose[f]);
  return ready;
}

/// Reads what worker `w` wrote on stdout for `item`: its record once a whole line is there, an
/// error record when the worker ended without one; nullopt while the item still runs.
std::optional<RunResult> read_record(Worker& w, const SuiteItem& item, double timeout_s) {
  const bool open = drain(w.out_fd, w.out);
  const size_t nl = w.out.find('\n');
  pass_on_stderr(w);  // what the item wrote on stderr belongs to it, before the next one starts
  if (nl != std::string::npos) {
    try {
      return decode_run_text(w.out.substr(0, nl), "the worker's record");
    } catch (const InputError& e) {
      return error_record(item, fmt::format("the worker process wrote a malformed record: {}", e.what()));
    }
  }
  if (open) return std::nullopt;
  int sig = 0;
  const std::string how = end_worker(w, false, &sig);
  const std::string said = last_line(w.err);
  return error_record(
      item, sig == SIGPROF ? timed_out(timeout_s)
                           : fmt::format("the engine ended its process ({}){}", how, said.empty() ? "" : ": " + said));
}

}  // namespace

namespace {

/// Hands `item` (the slot-th of the share) to worker `w`, starting the worker first where it has
/// none (bound to `cpu` unless it is -1); the item's error record where the request cannot be
/// written (the worker is ended), nullopt once it runs.
std::optional<RunResult> start_item(Worker& w, long slot, const SuiteItem& item, const RunnerDef& runner,
                                    const RunningBinary& binary, int cpu) {
  if (w.pid < 0) {
    w = spawn_worker(binary.path, binary.shown);
    if (cpu >= 0) bind_worker(w.pid, cpu);
  }
  w.slot = slot;
  w.started = std::chrono::steady_clock::now();
  nlohmann::json request = item_request(item);
  request["cpu_limit_s"] = runner.timeout_s;
  request["memory_limit_mib"] = runner.memory_limit_mib;
  if (write_all(w.in_fd, request.dump() + "\n")) return std::nullopt;
  const std::string how = end_worker(w, true);
  return error_record(item, fmt::format("the worker process {} before the run", how));
}

/// The message of an item stopped at the wall-clock limit.
std::string waited_too_long(double wall_limit_s, double timeout_s) {
  return fmt::format(
      "timed out: no record after {:g} s of wall-clock time ({:g} s of CPU time allowed by --timeout; "
      "the run waited rather than computed), stopped",
      wall_limit_s, timeout_s);
}

}  // namespace

std::vector<RunResult> run_items(const SuitePlan& plan, const std::vector<size_t>& which, const RunnerDef& runner,
                                 const std::function<void(size_t, const RunResult&, double)>& done,
                                 const std::function<void(size_t, size_t)>& progress) {
  using clock = std::chrono::steady_clock;
  const size_t n = which.size();
  std::vector<RunResult> records(n);
  std::vector<double> held_s(n, 0.0);
  std::vector<char> ready(n, 0);
  Dispenser dispenser(plan, which, schedule_order(plan, which));
  const RunningBinary binary(runner.exe);
  std::signal(SIGPIPE, SIG_IGN);  // a worker that died is seen at its pipe's end, not by a signal
  const int jobs = std::min({runner.jobs, usable_cores(), static_cast<int>(std::max<size_t>(n, 1))});
  std::vector<Worker> workers(static_cast<size_t>(std::max(1, jobs)));
  // Worker k keeps to a core of its own, with its outside engine: the protocol's round trip then
  // never waits for a wake-up on another core (free to move, --jobs 1 took 2.7 times --jobs 2 on
  // two cores; bound, 1.7). With fewer jobs than cores, the cores are taken from the one this
  // process runs on when the suite starts: the kernel starts a process on an idle core, so two
  // suites at once (parallel shards, ctest -j) start on, and keep to, different cores.
  const std::vector<int> cpus = worker_cpus(jobs);
  // The time limit is the run's own CPU time, counted by its worker; this wall-clock limit only
  // catches a run that waits instead of computing (it is never reached by one that computes).
  const double wall_limit_s = std::max(kWallFactor * runner.timeout_s, runner.timeout_s + kWallGrace_s);
  size_t finished = 0, printed = 0;
  const auto finish = [&](Worker& w, RunResult record) {
    records[static_cast<size_t>(w.slot)] = std::move(record);
    held_s[static_cast<size_t>(w.slot)] = std::chrono::duration<double>(clock::now() - w.started).count();
    ready[static_cast<size_t>(w.slot)] = 1;
    ++finished;
    w.slot = -1;
    w.out.clear(), w.err.clear();
  };
  const auto stop_all = [&] {
    for (Worker& w : workers)
      if (w.pid > 0) end_worker(w, true);
  };
  try {
    while (printed < n) {
      if (runner.stop && runner.stop()) throw RunnerStopped(fmt::format("stopped after {} of {} items", finished, n));
      // Hand out work.
      for (size_t k = 0; k < workers.size(); ++k) {
        Worker& w = workers[k];
        if (w.slot >= 0 || dispenser.empty()) continue;
        const long slot = static_cast<long>(dispenser.next_for(k));
        if (auto failed = start_item(w, slot, plan.items[which[static_cast<size_t>(slot)]], runner, binary,
                                     cpus.empty() ? -1 : cpus[k % cpus.size()]))
          finish(w, std::move(*failed));
      }
      for (const auto& [k, is_out] : poll_workers(workers, wall_limit_s)) {
        Worker& w = workers[k];
        if (w.slot < 0) continue;
        if (!is_out) {
          pass_on_stderr(w);
          continue;
        }
        std::optional<RunResult> rec = read_record(w, plan.items[which[static_cast<size_t>(w.slot)]], runner.timeout_s);
        if (rec) finish(w, std::move(*rec));
      }
      for (Worker& w : workers)
        if (w.slot >= 0 && std::chrono::duration<double>(clock::now() - w.started).count() > wall_limit_s) {
          const SuiteItem& item = plan.items[which[static_cast<size_t>(w.slot)]];
          end_worker(w, true);
          finish(w, error_record(item, waited_too_long(wall_limit_s, runner.timeout_s)));
        }
      std::vector<size_t> now;
      while (printed < n && ready[printed]) now.push_back(printed++);
      for (size_t k : now) done(which[k], records[k], held_s[k]);
      if (progress) progress(finished, n);
    }
  } catch (...) {
    stop_all();
    throw;
  }
  for (Worker& w : workers)
    if (w.pid > 0) end_worker(w, false);
  return records;
}

}  // namespace liftcheck
