#include "engines/protocol/child.hpp"

#include <fcntl.h>
#include <mutex>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fmt/format.h>
#include <fstream>

#include "input/interrupt.hpp"
#include "input/trace.hpp"  // printable

extern char** environ;

namespace liftcheck {

namespace {

double now_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// At most `n` characters of `text` on one line, for messages. Whatever an engine sends is data:
/// a byte that is not UTF-8 (a Latin-1 message), a NUL or another control character is '?', so
/// the message is one printable line that JSON can hold and no C string cuts short.
std::string clip(const std::string& text, size_t n = 160) {
  std::string s;
  for (char c : text) s += (c == '\n' || c == '\r' || c == '\t') ? ' ' : c;
  return printable(s, n);
}

/// How long a wait lasts at most before a signal or the child's end is looked at again.
constexpr double kWakeS = 0.25;

/// Milliseconds for poll(): what is left of a wait, at most kWakeS.
int wait_ms(double left_s) { return static_cast<int>(std::min(left_s, kWakeS) * 1000.0) + 1; }

/// "PID.START": this process, by its pid and start time (a pid alone may be reused).
std::string process_tag(pid_t pid) {
  std::ifstream in(fmt::format("/proc/{}/stat", pid));
  std::string stat;
  std::getline(in, stat);
  size_t at = stat.rfind(')');
  for (int field = 2; field < 22 && at != std::string::npos; ++field) at = stat.find(' ', at + 1);
  const std::string start = at == std::string::npos ? "0" : stat.substr(at + 1, stat.find(' ', at + 1) - at - 1);
  return fmt::format("{}.{}", pid, start);
}

constexpr const char* kAdapterVar = "LIFTCHECK_ADAPTER_OF=";

/// The environment of an adapter: liftcheck's, with its tag first (read first in /proc/PID/environ).
std::vector<std::string> adapter_environment(const std::string& tag) {
  std::vector<std::string> env{tag};
  for (char** e = environ; *e; ++e)
    if (std::strncmp(*e, kAdapterVar, std::strlen(kAdapterVar)) != 0) env.emplace_back(*e);
  return env;
}

/// SIGKILL to every process whose environment holds an entry starting with `prefix`, but this
/// one. Reads at most 1 MiB of each environment.
int kill_tagged(const std::string& prefix) {
  int n = 0;
  std::error_code ec;
  for (const auto& entry : std::filesystem::directory_iterator("/proc", ec)) {
    const std::string name = entry.path().filename().string();
    if (name.find_first_not_of("0123456789") != std::string::npos) continue;
    const pid_t pid = static_cast<pid_t>(std::stol(name));
    if (pid == getpid()) continue;
    std::ifstream in(entry.path() / "environ", std::ios::binary);
    std::string env(size_t{1} << 20, '\0');
    in.read(env.data(), static_cast<std::streamsize>(env.size()));
    env.resize(static_cast<size_t>(in.gcount()));
    for (size_t at = 0; at < env.size(); at = env.find('\0', at) + 1) {
      if (env.compare(at, prefix.size(), prefix) == 0) {
        n += ::kill(pid, SIGKILL) == 0;
        break;
      }
      if (env.find('\0', at) == std::string::npos) break;
    }
  }
  return n;
}

std::atomic<long> g_adapters{0};  ///< adapters started by this process, for their tags

std::string last_nonempty_line(const std::string& text) {
  const size_t end = text.find_last_not_of("\r\n \t");
  if (end == std::string::npos) return "";
  const size_t nl = text.find_last_of('\n', end);
  const size_t start = nl == std::string::npos ? 0 : nl + 1;
  return text.substr(start, end - start + 1);
}

void close_fd(int& fd) {
  if (fd >= 0) ::close(fd);
  fd = -1;
}

}  // namespace

ProtocolChild::ProtocolChild(std::string label, const std::vector<std::string>& argv, const std::string& cwd)
    : label_(std::move(label)) {
  if (argv.empty()) throw EngineError(fmt::format("engine '{}': its registration names no command", label_));
  // A child that died is seen at its pipe's end, not by a signal that would end liftcheck.
  std::signal(SIGPIPE, SIG_IGN);
  int in[2], out[2], err[2];
  if (pipe2(in, O_CLOEXEC) != 0) throw EngineError(fmt::format("engine '{}': cannot create pipes", label_));
  if (pipe2(out, O_CLOEXEC) != 0) {
    ::close(in[0]), ::close(in[1]);
    throw EngineError(fmt::format("engine '{}': cannot create pipes", label_));
  }
  if (pipe2(err, O_CLOEXEC) != 0) {
    ::close(in[0]), ::close(in[1]), ::close(out[0]), ::close(out[1]);
    throw EngineError(fmt::format("engine '{}': cannot create pipes", label_));
  }
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, in[0], 0);
  posix_spawn_file_actions_adddup2(&fa, out[1], 1);
  posix_spawn_file_actions_adddup2(&fa, err[1], 2);
  posix_spawn_file_actions_addclosefrom_np(&fa, 3);  // nothing of liftcheck's leaks into the engine
  if (!cwd.empty()) posix_spawn_file_actions_addchdir_np(&fa, cwd.c_str());
  // Default signal dispositions in the child (liftcheck ignores SIGPIPE; the engine should not).
  posix_spawnattr_t attr;
  posix_spawnattr_init(&attr);
  sigset_t defaults;
  sigemptyset(&defaults);
  sigaddset(&defaults, SIGPIPE);
  posix_spawnattr_setsigdefault(&attr, &defaults);
  // A process group of its own: it is ended as a group, with what it started (kill_and_reap).
  posix_spawnattr_setpgroup(&attr, 0);
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF | POSIX_SPAWN_SETPGROUP);
  std::vector<std::string> args = argv;
  std::vector<char*> cargs;
  for (std::string& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  // Its tag, inherited by whatever it starts: a process that leaves the group (setsid) is still found.
  // Ended by a '/': as a prefix it names this adapter alone (".../1/" is no prefix of ".../10/").
  tag_ = fmt::format("{}{}/{}/", kAdapterVar, process_tag(getpid()), ++g_adapters);
  std::vector<std::string> env = adapter_environment(tag_);
  std::vector<char*> cenv;
  for (std::string& v : env) cenv.push_back(v.data());
  cenv.push_back(nullptr);
  // A worker's memory limit (RLIMIT_AS, harness/worker.cpp) is for the engines compiled in: an
  // outside engine's runtime starts without it (V8 reserves address space for WebAssembly far
  // beyond any useful limit and would not start), bounded by its own heap limits and its reply timeout.
  // The limit is the process's: children started at once from several threads take turns at it.
  static std::mutex limit_m;
  int rc = 0;
  {
    std::lock_guard<std::mutex> lock(limit_m);
    rlimit as{};
    const bool lift = getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != as.rlim_max;
    if (lift) {
      rlimit open = as;
      open.rlim_cur = as.rlim_max;
      setrlimit(RLIMIT_AS, &open);
    }
    rc = posix_spawnp(&pid_, args[0].c_str(), &fa, &attr, cargs.data(), cenv.data());
    if (lift) setrlimit(RLIMIT_AS, &as);
  }
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  ::close(in[0]), ::close(out[1]), ::close(err[1]);
  if (rc != 0) {
    ::close(in[1]), ::close(out[0]), ::close(err[0]);
    pid_ = -1;
    throw EngineError(fmt::format("engine '{}': cannot start '{}' (in {}): {}", label_, clip(argv[0]),
                                  cwd.empty() ? "." : cwd, std::strerror(rc)));
  }
  in_fd_ = in[1], out_fd_ = out[0], err_fd_ = err[0];
  fcntl(in_fd_, F_SETFL, O_NONBLOCK);
  fcntl(out_fd_, F_SETFL, O_NONBLOCK);
  fcntl(err_fd_, F_SETFL, O_NONBLOCK);
}

ProtocolChild::~ProtocolChild() { kill_and_reap(); }

/// The group is asked to end (SIGTERM), given 0.5 s, then killed (SIGKILL) before its leader is
/// reaped (while the group's id cannot be taken by another process); a process it started that
/// left the group or outlived its leader is found by its tag.
void ProtocolChild::kill_and_reap() {
  healthy_ = false;
  close_fd(in_fd_);
  if (pid_ > 0) {
    ::kill(-pid_, SIGTERM);
    for (int k = 0; k < 50; ++k) {
      siginfo_t info{};
      if (waitid(P_PID, static_cast<id_t>(pid_), &info, WEXITED | WNOHANG | WNOWAIT) == 0 && info.si_pid == pid_) break;
      usleep(10000);
    }
    ::kill(-pid_, SIGKILL);
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {}
    if (exit_how_.empty())
      exit_how_ = WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                                      : fmt::format("exited with status {}", WEXITSTATUS(status));
    pid_ = -1;
  }
  // What it started that outlived it or left its group (reaped already, its group is not named).
  if (!tag_.empty()) kill_tagged(tag_), tag_.clear();
  drain_stderr();
  close_fd(out_fd_), close_fd(err_fd_);
}

int end_adapters_of(pid_t owner) { return kill_tagged(fmt::format("{}{}/", kAdapterVar, process_tag(owner))); }

void ProtocolChild::drain_stderr() {
  if (err_fd_ < 0) return;
  char buf[16384];
  for (;;) {
    const ssize_t got = ::read(err_fd_, buf, sizeof buf);
    if (got > 0) {
      err_tail_.append(buf, static_cast<size_t>(got));
      if (err_tail_.size() > 8192) err_tail_.erase(0, err_tail_.size() - 8192);
      continue;
    }
    if (got < 0 && errno == EINTR) continue;
    if (got == 0) err_open_ = false;  // its end: polled no more (it would wake every poll at once)
    return;                           // end of file or nothing more for now
  }
}

std::string ProtocolChild::context() const {
  std::string s = last_line_.empty() ? "; it sent nothing" : fmt::format("; it sent last: '{}'", clip(last_line_));
  const std::string err = last_nonempty_line(err_tail_);
  if (!err.empty()) s += fmt::format("; its stderr ended: '{}'", clip(err));
  if (err_tail_.find("ERR_MODULE_NOT_FOUND") != std::string::npos ||
      err_tail_.find("Cannot find module") != std::string::npos ||
      err_tail_.find("Cannot find package") != std::string::npos)
    s += " (are the npm packages installed? 'npm ci' in engines/outside, which 'make build' runs)";
  return s;
}

void ProtocolChild::fail(const std::string& what) {
  kill_and_reap();
  throw EngineError(fmt::format("engine '{}' ({}): {}{}", label_, op_, printable(what, 1000), context()));
}

bool ProtocolChild::reaped_if_gone() {
  if (pid_ <= 0) return true;
  int status = 0;
  if (waitpid(pid_, &status, WNOHANG) != pid_) return false;
  exit_how_ = WIFSIGNALED(status)
                  ? fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)))
                  : fmt::format("exited with status {}", WEXITSTATUS(status));
  pid_ = -1;
  return true;
}

void ProtocolChild::check_between_waits() {
  if (const int sig = g_interrupt_signal) {
    kill_and_reap();
    throw Interrupted(sig, fmt::format("while waiting for engine '{}' ({})", label_, op_));
  }
  // Its own process ended while another it started holds its output open: no reply will come.
  if (reaped_if_gone()) {
    drain_stdout();
    if (out_buf_.find('\n') != std::string::npos) return;  // it replied before it ended
    drain_stderr();
    if (!out_buf_.empty()) last_line_ = out_buf_.substr(0, 200);
    fail(fmt::format("the process ended ({}) without replying", exit_how_));
  }
}

bool ProtocolChild::drain_stdout() {
  char buf[65536];
  for (;;) {
    const ssize_t got = ::read(out_fd_, buf, sizeof buf);
    if (got > 0) {
      out_buf_.append(buf, static_cast<size_t>(got));
      if (out_buf_.size() > kProtocolLineMax + sizeof buf) return true;  // read_line refuses it
      // A short read that ends a line: the reply is here, and another read would only find the
      // pipe empty (one system call a step saved; what comes later, the next poll sees).
      if (static_cast<size_t>(got) < sizeof buf && buf[got - 1] == '\n') return true;
      continue;
    }
    if (got < 0 && errno == EINTR) continue;
    return got != 0;
  }
}

void ProtocolChild::write_all(const std::string& text, double deadline_s) {
  size_t done = 0;
  while (done < text.size()) {
    const ssize_t put = ::write(in_fd_, text.data() + done, text.size() - done);
    if (put > 0) {
      done += static_cast<size_t>(put);
      continue;
    }
    if (put < 0 && errno == EINTR) continue;
    if (put < 0 && errno != EAGAIN) {
      drain_stderr();
      fail("the process is gone (its standard input is closed)");
    }
    pollfd p{in_fd_, POLLOUT, 0};
    const double left = deadline_s - now_s();
    if (left <= 0.0) fail("does not read its standard input (timed out writing the request)");
    const int n = poll(&p, 1, wait_ms(left));
    if (n < 0 && errno != EINTR) fail(fmt::format("poll: {}", std::strerror(errno)));
    if (n <= 0) check_between_waits();
  }
}

const std::string& ProtocolChild::read_line(double deadline_s) {
  for (;;) {
    const size_t nl = out_buf_.find('\n');
    if (nl != std::string::npos) {
      if (nl > kProtocolLineMax) fail("sent a line longer than 1 MiB");
      last_line_.assign(out_buf_, 0, nl);  // both buffers keep their capacity from step to step
      out_buf_.erase(0, nl + 1);
      if (!last_line_.empty() && last_line_.back() == '\r') last_line_.pop_back();
      return last_line_;
    }
    if (out_buf_.size() > kProtocolLineMax) {
      last_line_ = out_buf_.substr(0, 200);
      fail("sent a line longer than 1 MiB");
    }
    const double left = deadline_s - now_s();
    if (left <= 0.0) fail(fmt::format("no reply within {:.3g} s (what the run's --timeout left it)", timeout_hint_s_));
    pollfd fds[2] = {{out_fd_, POLLIN, 0}, {err_open_ ? err_fd_ : -1, POLLIN, 0}};
    const int n = poll(fds, 2, wait_ms(left));
    if (n < 0 && errno != EINTR) fail(fmt::format("poll: {}", std::strerror(errno)));
    // Every kWakeS at least, however busy its stderr: a signal, or the child itself gone.
    if (n <= 0 || now_s() >= next_check_s_) {
      next_check_s_ = now_s() + kWakeS;
      check_between_waits();
      if (n <= 0) continue;
    }
    if (fds[1].revents) drain_stderr();
    if (fds[0].revents && !drain_stdout() && out_buf_.find('\n') == std::string::npos) {
      // End of its output: the child ended. Its last words are in the stderr pipe now.
      int status = 0;
      pid_t r = 0;
      for (int k = 0; k < 100 && pid_ > 0 && (r = waitpid(pid_, &status, WNOHANG)) == 0; ++k) usleep(10000);
      if (r == pid_ && pid_ > 0) {
        exit_how_ = WIFSIGNALED(status)
                        ? fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)))
                        : fmt::format("exited with status {}", WEXITSTATUS(status));
        pid_ = -1;
      }
      drain_stderr();
      if (!out_buf_.empty()) last_line_ = out_buf_.substr(0, 200);
      fail(fmt::format("the process ended ({}) without replying",
                       exit_how_.empty() ? "closed its standard output" : exit_how_));
    }
  }
}

const std::string& ProtocolChild::exchange(const char* op, std::string& request, double timeout_s) {
  send(op, request, timeout_s);
  return read_line(now_s() + timeout_s);
}

const std::string& ProtocolChild::next_line(double timeout_s) {
  timeout_hint_s_ = timeout_s;
  return read_line(now_s() + timeout_s);
}

void ProtocolChild::send(const char* op, std::string& request, double timeout_s) {
  op_ = op;
  if (!healthy()) fail("the process is no longer serving");
  // A line already waiting answers no request: an adapter out of step with the protocol.
  if (!out_buf_.empty()) {
    last_line_ = out_buf_.substr(0, std::min<size_t>(out_buf_.find('\n'), 200));
    fail("sent a line that answers no request (out of step: every request has exactly one reply)");
  }
  timeout_hint_s_ = timeout_s;
  const double deadline = now_s() + timeout_s;
  id_ += 1;
  // The number goes first: '{' + "id":N, + the rest ("{}" has no rest).
  request.insert(1, request.size() > 2 ? fmt::format("\"id\":{},", id_) : fmt::format("\"id\":{}", id_));
  request += '\n';
  write_all(request, deadline);
}

bool ProtocolChild::idle_and_clean() {
  if (!healthy()) return false;
  const bool open = drain_stdout();
  if (open && out_buf_.empty() && !reaped_if_gone()) return true;
  kill_and_reap();
  return false;
}

nlohmann::json ProtocolChild::checked_reply(const std::string& line) {
  nlohmann::json reply = nlohmann::json::parse(line, nullptr, false);
  if (reply.is_discarded()) {
    const bool non_finite = line.find("NaN") != std::string::npos || line.find("Infinity") != std::string::npos;
    fail(non_finite ? "a reply with a non-finite number (NaN or Infinity is not JSON)"
                    : "a reply that is not one JSON object");
  }
  if (!reply.is_object()) fail("a reply that is not a JSON object");
  const auto id = reply.find("id");
  if (id == reply.end())
    fail(
        fmt::format("a reply without its request's number (\"id\": {}): since protocol 2 every request is numbered "
                    "and each reply must carry its number (an adapter written to protocol 1?)",
                    id_));
  if (!id->is_number_integer())
    fail(fmt::format("a reply whose \"id\" {} is not a whole number (the request's number is {})", clip(id->dump(), 40),
                     id_));
  if (id->get<long>() != id_)
    fail(fmt::format("a reply numbered {} to request {}: out of step with its requests (a line too many or too few)",
                     id->get<long>(), id_));
  const auto ok = reply.find("ok");
  if (ok == reply.end() || !ok->is_boolean()) fail("a reply without a boolean 'ok'");
  if (!ok->get<bool>()) {
    const auto e = reply.find("error");
    const std::string why = e != reply.end() && e->is_string() ? clip(e->get<std::string>(), 300) : "no reason given";
    throw EngineError(fmt::format("engine '{}' ({}): {}", label_, op_, why));
  }
  return reply;
}

nlohmann::json ProtocolChild::call(const nlohmann::json& request, double timeout_s) {
  const std::string op = request.value("op", "?");
  std::string text = request.dump();
  return checked_reply(exchange(op.c_str(), text, timeout_s));
}

double ProtocolChild::number(const nlohmann::json& reply, const char* key, const char* where) {
  const auto it = reply.find(key);
  if (it == reply.end()) fail(fmt::format("the reply has no field '{}{}'", where, key));
  if (!it->is_number())
    fail(fmt::format("field '{}{}' is {}, not a number", where, key,
                     it->is_null() ? "null (not finite?)" : it->type_name()));
  const double v = it->get<double>();
  if (!std::isfinite(v)) fail(fmt::format("field '{}{}' is not finite", where, key));
  return v;
}

std::vector<double> ProtocolChild::numbers(const nlohmann::json& reply, const char* key, size_t n, const char* where) {
  const auto it = reply.find(key);
  if (it == reply.end()) fail(fmt::format("the reply has no field '{}{}'", where, key));
  if (!it->is_array() || (n > 0 && it->size() != n) || it->empty())
    fail(fmt::format("field '{}{}' is not an array of {} numbers", where, key,
                     n > 0 ? fmt::format("{}", n) : "1 or more"));
  std::vector<double> out;
  for (const auto& v : *it) {
    if (!v.is_number())
      fail(fmt::format("field '{}{}' holds {}, not a number", where, key,
                       v.is_null() ? "null (not finite?)" : v.type_name()));
    out.push_back(v.get<double>());
    if (!std::isfinite(out.back())) fail(fmt::format("field '{}{}' holds a non-finite number", where, key));
  }
  return out;
}

void ProtocolChild::close(double timeout_s) {
  if (healthy()) {
    try {
      call({{"op", "bye"}}, timeout_s);
    } catch (const std::exception&) {  // a protocol error or a signal: it is ended below either way
    }
  }
  if (pid_ > 0) {
    close_fd(in_fd_);
    int status = 0;
    for (int k = 0; k < 20; ++k) {
      if (waitpid(pid_, &status, WNOHANG) == pid_) {
        exit_how_ = fmt::format("exited with status {}", WEXITSTATUS(status));
        pid_ = -1;
        break;
      }
      usleep(5000);
    }
  }
  kill_and_reap();
}

}  // namespace liftcheck
