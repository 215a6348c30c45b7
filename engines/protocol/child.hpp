// An engine outside liftcheck as a child process speaking the engine protocol (docs/protocol.md):
// started with posix_spawn from an argument vector (never a shell), one JSON object per line on
// its standard input and output, every read bounded in size (1 MiB a line) and in time (poll with
// a deadline), its standard error drained as it comes and its last lines kept for error records.
// Whatever goes wrong, the child is killed and the caller gets an EngineError whose one-line
// reason names what the child sent last.
#pragma once

#include <sys/types.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engines/engine.hpp"

namespace liftcheck {

/// The longest line either side may send (docs/protocol.md).
constexpr size_t kProtocolLineMax = size_t{1} << 20;

class ProtocolChild {
 public:
  /// Starts `argv` (argv[0] looked up on PATH) in the folder `cwd`. `label` names the
  /// configuration in every error ("rapier"). Throws EngineError when it cannot start.
  ProtocolChild(std::string label, const std::vector<std::string>& argv, const std::string& cwd);
  ~ProtocolChild();
  ProtocolChild(const ProtocolChild&) = delete;
  ProtocolChild& operator=(const ProtocolChild&) = delete;

  /// Writes `request` and waits up to `timeout_s` for its one reply line. Returns the reply, an
  /// object with "ok": true. A reply {"ok": false, "error": ...} throws EngineError with the
  /// engine's reason and leaves the child up (it may serve the next run); anything else wrong (no
  /// reply in time, the child gone, a line too long, not a JSON object) kills it first.
  nlohmann::json call(const nlohmann::json& request, double timeout_s);
  /// The round trip of call() without the JSON tree: writes `request` (one JSON object on one
  /// line; a newline is appended to it) and returns the reply line unread, valid until the next
  /// exchange. Fails as call() does on no reply in time, the child gone or a line too long.
  const std::string& exchange(const char* op, std::string& request, double timeout_s);
  /// A reply line read as call() reads it: the object with "ok": true, else fail() or EngineError.
  nlohmann::json checked_reply(const std::string& line);

  /// Kills the child and throws EngineError: "engine 'NAME' (OP): WHAT; last line ...".
  [[noreturn]] void fail(const std::string& what);

  /// The reply's number `key` (finite), or fail() naming the field.
  double number(const nlohmann::json& reply, const char* key, const char* where = "");
  /// Its array `key` of exactly `n` finite numbers (n = 0: any length of at least 1), or fail().
  std::vector<double> numbers(const nlohmann::json& reply, const char* key, size_t n, const char* where = "");

  /// Still running and in step with the protocol (no violation seen).
  bool healthy() const { return pid_ > 0 && healthy_; }
  /// Asks it to end ("bye"), waits up to `timeout_s`, then kills it.
  void close(double timeout_s);
  pid_t pid() const { return pid_; }

 private:
  std::string context() const;
  void kill_and_reap();
  void drain_stderr();
  /// One line from stdout before `deadline_s` (steady clock seconds), or fail().
  const std::string& read_line(double deadline_s);
  void write_all(const std::string& text, double deadline_s);

  std::string label_;
  std::string op_ = "start";    ///< the request in flight, for messages
  pid_t pid_ = -1;
  int in_fd_ = -1, out_fd_ = -1, err_fd_ = -1;
  std::string out_buf_;         ///< stdout read past the last complete line
  std::string err_tail_;        ///< the last 8 KiB of stderr
  std::string last_line_;       ///< the last complete line it sent on stdout
  std::string exit_how_;        ///< "exited with status 1", once reaped
  bool healthy_ = true;
  double timeout_hint_s_ = 0.0;  ///< the time limit of the call in flight
};

}  // namespace liftcheck
