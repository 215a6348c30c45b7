// An engine outside liftcheck as a child process speaking the engine protocol (docs/protocol.md):
// started with posix_spawn from an argument vector (never a shell) in a process group of its own,
// one JSON object per line on its standard input and output, every request numbered and every
// reply required to carry its request's number, every read bounded in size (1 MiB a line) and in
// time (poll with a deadline), its standard error drained as it comes and its last lines kept for
// error records. Whatever goes wrong, the child's process group is ended (SIGTERM, then SIGKILL)
// with every process it started, and the caller gets an EngineError whose one-line reason names
// what the child sent last: whatever bytes it sent, the reason is printable UTF-8.
#pragma once

#include <sys/types.h>

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "engines/engine.hpp"

namespace liftcheck {

/// The longest line either side may send (docs/protocol.md).
constexpr size_t kProtocolLineMax = size_t{1} << 20;
/// The protocol's version: 2 numbers every request ("id") and requires it in its reply; 3 adds M's
/// angular velocity (wM) to the disks' step reply.
constexpr int kProtocolVersion = 3;

/// Ends (SIGKILL) every process started as an adapter by the liftcheck process `owner` that is
/// still running, wherever it went (a new session, a parent that died): each adapter and whatever
/// it starts carries its owner in its environment (LIFTCHECK_ADAPTER_OF). Returns how many.
int end_adapters_of(pid_t owner);

class ProtocolChild {
 public:
  /// Starts `argv` (argv[0] looked up on PATH) in the folder `cwd`. `label` names the
  /// configuration in every error ("rapier"). Throws EngineError when it cannot start.
  ProtocolChild(std::string label, const std::vector<std::string>& argv, const std::string& cwd);
  ~ProtocolChild();
  ProtocolChild(const ProtocolChild&) = delete;
  ProtocolChild& operator=(const ProtocolChild&) = delete;

  /// Writes `request` (numbered: "id" is added) and waits up to `timeout_s` for its one reply line.
  /// Returns the reply, an object with "ok": true and the request's "id". A reply {"ok": false,
  /// "error": ...} with the right number throws EngineError with the engine's reason and leaves the
  /// child up (it may serve the next run); anything else wrong (no reply in time, the child gone, a
  /// line too long, not a JSON object, another number or none) kills it first. A signal
  /// (input/interrupt.hpp) ends the wait within 0.25 s: the child is ended and Interrupted thrown.
  nlohmann::json call(const nlohmann::json& request, double timeout_s);
  /// The round trip of call() without the JSON tree: writes `request` (one JSON object on one
  /// line; its "id" is put first and a newline appended) and returns the reply line unread, valid
  /// until the next exchange. Fails as call() does on no reply in time, the child gone or a line
  /// too long; the caller checks the reply's number (request_id()).
  const std::string& exchange(const char* op, std::string& request, double timeout_s);
  /// exchange() in its halves, for a request answered by several lines (docs/protocol.md,
  /// "steps"): send() writes it; each next_line() waits up to `timeout_s` for one more line.
  void send(const char* op, std::string& request, double timeout_s);
  const std::string& next_line(double timeout_s);
  /// A reply line read as call() reads it: the object with "ok": true and the request's "id",
  /// else fail() or EngineError.
  nlohmann::json checked_reply(const std::string& line);
  /// The number of the request in flight (the last one written); 1 for the hello.
  long request_id() const { return id_; }
  /// Still serving, and nothing sent that no request asked for (a line between runs): false
  /// ends it. For a child about to be given to a run or back to the idle ones.
  bool idle_and_clean();

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
  /// Reads what stdout holds now without waiting; false at its end.
  bool drain_stdout();
  /// Reaps the child if it has ended (its exit in exit_how_); true then.
  bool reaped_if_gone();
  /// Between two waits: a signal ends the child and throws Interrupted; an ended child fails.
  void check_between_waits();
  /// One line from stdout before `deadline_s` (steady clock seconds), or fail().
  const std::string& read_line(double deadline_s);
  void write_all(const std::string& text, double deadline_s);

  std::string label_;
  std::string op_ = "start";  ///< the request in flight, for messages
  pid_t pid_ = -1;
  int in_fd_ = -1, out_fd_ = -1, err_fd_ = -1;
  std::string out_buf_;    ///< stdout read past the last complete line
  std::string err_tail_;   ///< the last 8 KiB of stderr
  std::string last_line_;  ///< the last complete line it sent on stdout
  std::string exit_how_;   ///< "exited with status 1", once reaped
  bool healthy_ = true;
  double timeout_hint_s_ = 0.0;  ///< the time limit of the call in flight
  long id_ = 0;                  ///< the number of the request in flight
  bool err_open_ = true;         ///< its stderr not at its end yet
  double next_check_s_ = 0.0;    ///< when a wait next looks at signals and the child's end
  std::string tag_;              ///< LIFTCHECK_ADAPTER_OF=... in its environment and its descendants'
};

}  // namespace liftcheck
