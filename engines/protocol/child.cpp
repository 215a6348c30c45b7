#include "engines/protocol/child.hpp"

#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fmt/format.h>

extern char** environ;

namespace liftcheck {

namespace {

double now_s() { return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count(); }

/// At most `n` characters of `text` on one line, for messages.
std::string clip(const std::string& text, size_t n = 160) {
  std::string s;
  for (char c : text) s += (c == '\n' || c == '\r' || c == '\t') ? ' ' : c;
  if (s.size() > n) s = s.substr(0, n) + "...";
  return s;
}

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

ProtocolChild::ProtocolChild(std::string label, const std::vector<std::string>& argv, const std::string& cwd) : label_(std::move(label)) {
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
  posix_spawnattr_setflags(&attr, POSIX_SPAWN_SETSIGDEF);
  std::vector<std::string> args = argv;
  std::vector<char*> cargs;
  for (std::string& a : args) cargs.push_back(a.data());
  cargs.push_back(nullptr);
  // A worker's memory limit (RLIMIT_AS, harness/suite.cpp) is for the engines compiled in: an
  // outside engine's runtime starts without it (V8 reserves address space for WebAssembly far
  // beyond any useful limit and would not start), bounded by its own heap limits and its reply timeout.
  rlimit as{};
  const bool lift = getrlimit(RLIMIT_AS, &as) == 0 && as.rlim_cur != as.rlim_max;
  if (lift) {
    rlimit open = as;
    open.rlim_cur = as.rlim_max;
    setrlimit(RLIMIT_AS, &open);
  }
  const int rc = posix_spawnp(&pid_, args[0].c_str(), &fa, &attr, cargs.data(), environ);
  if (lift) setrlimit(RLIMIT_AS, &as);
  posix_spawn_file_actions_destroy(&fa);
  posix_spawnattr_destroy(&attr);
  ::close(in[0]), ::close(out[1]), ::close(err[1]);
  if (rc != 0) {
    ::close(in[1]), ::close(out[0]), ::close(err[0]);
    pid_ = -1;
    throw EngineError(fmt::format("engine '{}': cannot start '{}' (in {}): {}", label_, clip(argv[0]), cwd.empty() ? "." : cwd, std::strerror(rc)));
  }
  in_fd_ = in[1], out_fd_ = out[0], err_fd_ = err[0];
  fcntl(in_fd_, F_SETFL, O_NONBLOCK);
  fcntl(out_fd_, F_SETFL, O_NONBLOCK);
  fcntl(err_fd_, F_SETFL, O_NONBLOCK);
}

ProtocolChild::~ProtocolChild() { kill_and_reap(); }

void ProtocolChild::kill_and_reap() {
  healthy_ = false;
  close_fd(in_fd_);
  if (pid_ > 0) {
    ::kill(pid_, SIGKILL);
    int status = 0;
    while (waitpid(pid_, &status, 0) < 0 && errno == EINTR) {
    }
    if (exit_how_.empty())
      exit_how_ = WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status)) : fmt::format("exited with status {}", WEXITSTATUS(status));
    pid_ = -1;
  }
  drain_stderr();
  close_fd(out_fd_), close_fd(err_fd_);
}

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
    return;  // end of file or nothing more for now
  }
}

std::string ProtocolChild::context() const {
  std::string s = last_line_.empty() ? "; it sent nothing" : fmt::format("; it sent last: '{}'", clip(last_line_));
  const std::string err = last_nonempty_line(err_tail_);
  if (!err.empty()) s += fmt::format("; its stderr ended: '{}'", clip(err));
  if (err_tail_.find("ERR_MODULE_NOT_FOUND") != std::string::npos || err_tail_.find("Cannot find module") != std::string::npos ||
      err_tail_.find("Cannot find package") != std::string::npos)
    s += " (are the npm packages installed? 'npm ci' in engines/outside, which 'make build' runs)";
  return s;
}

void ProtocolChild::fail(const std::string& what) {
  kill_and_reap();
  throw EngineError(fmt::format("engine '{}' ({}): {}{}", label_, op_, what, context()));
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
    if (poll(&p, 1, static_cast<int>(left * 1000.0) + 1) < 0 && errno != EINTR) fail(fmt::format("poll: {}", std::strerror(errno)));
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
    pollfd fds[2] = {{out_fd_, POLLIN, 0}, {err_fd_, POLLIN, 0}};
    if (poll(fds, 2, static_cast<int>(left * 1000.0) + 1) < 0 && errno != EINTR) fail(fmt::format("poll: {}", std::strerror(errno)));
    if (fds[1].revents) drain_stderr();
    if (fds[0].revents) {
      char buf[65536];
      const ssize_t got = ::read(out_fd_, buf, sizeof buf);
      if (got > 0) {
        out_buf_.append(buf, static_cast<size_t>(got));
      } else if (got == 0) {
        // End of its output: the child ended. Its last words are in the stderr pipe now.
        int status = 0;
        pid_t r = 0;
        for (int k = 0; k < 100 && (r = waitpid(pid_, &status, WNOHANG)) == 0; ++k) usleep(10000);
        if (r == pid_) {
          exit_how_ = WIFSIGNALED(status) ? fmt::format("killed by signal {} ({})", WTERMSIG(status), strsignal(WTERMSIG(status)))
                                          : fmt::format("exited with status {}", WEXITSTATUS(status));
          pid_ = -1;
        }
        drain_stderr();
        if (!out_buf_.empty()) last_line_ = out_buf_.substr(0, 200);
        fail(fmt::format("the process ended ({}) without replying", exit_how_.empty() ? "closed its standard output" : exit_how_));
      } else if (errno != EAGAIN && errno != EINTR) {
        fail(fmt::format("reading its output: {}", std::strerror(errno)));
      }
    }
  }
}

const std::string& ProtocolChild::exchange(const char* op, std::string& request, double timeout_s) {
  op_ = op;
  if (!healthy()) fail("the process is no longer serving");
  timeout_hint_s_ = timeout_s;
  const double deadline = now_s() + timeout_s;
  request += '\n';
  write_all(request, deadline);
  return read_line(deadline);
}

nlohmann::json ProtocolChild::checked_reply(const std::string& line) {
  nlohmann::json reply = nlohmann::json::parse(line, nullptr, false);
  if (reply.is_discarded()) {
    const bool non_finite = line.find("NaN") != std::string::npos || line.find("Infinity") != std::string::npos;
    fail(non_finite ? "a reply with a non-finite number (NaN or Infinity is not JSON)" : "a reply that is not one JSON object");
  }
  if (!reply.is_object()) fail("a reply that is not a JSON object");
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
  if (!it->is_number()) fail(fmt::format("field '{}{}' is {}, not a number", where, key, it->is_null() ? "null (not finite?)" : it->type_name()));
  const double v = it->get<double>();
  if (!std::isfinite(v)) fail(fmt::format("field '{}{}' is not finite", where, key));
  return v;
}

std::vector<double> ProtocolChild::numbers(const nlohmann::json& reply, const char* key, size_t n, const char* where) {
  const auto it = reply.find(key);
  if (it == reply.end()) fail(fmt::format("the reply has no field '{}{}'", where, key));
  if (!it->is_array() || (n > 0 && it->size() != n) || it->empty())
    fail(fmt::format("field '{}{}' is not an array of {} numbers", where, key, n > 0 ? fmt::format("{}", n) : "1 or more"));
  std::vector<double> out;
  for (const auto& v : *it) {
    if (!v.is_number()) fail(fmt::format("field '{}{}' holds {}, not a number", where, key, v.is_null() ? "null (not finite?)" : v.type_name()));
    out.push_back(v.get<double>());
    if (!std::isfinite(out.back())) fail(fmt::format("field '{}{}' holds a non-finite number", where, key));
  }
  return out;
}

void ProtocolChild::close(double timeout_s) {
  if (healthy()) {
    try {
      call({{"op", "bye"}}, timeout_s);
    } catch (const EngineError&) {
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
