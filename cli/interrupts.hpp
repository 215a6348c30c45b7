// SIGINT and SIGTERM: the runner stops at its next event, the outputs are left as they were.
#pragma once

#include <stdexcept>
#include <string>

namespace liftcheck::cli {

/// Installs the handlers that record the signal.
void catch_interrupts();
/// The signal received, 0 when none.
int pending_signal();

/// Thrown when a signal stopped the work: exit 128 + the signal.
struct Interrupted : std::runtime_error {
  int sig;
  Interrupted(int s, const std::string& where) : std::runtime_error(where), sig(s) {}
};
void throw_if_interrupted(const std::string& where);

}  // namespace liftcheck::cli
