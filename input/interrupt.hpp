// SIGINT, SIGTERM and SIGHUP: the handler records the signal, every long loop (a run's wait, a file being
// read or parsed, a score, a diff) checks it and stops with Interrupted (exit 128 + the signal).
#pragma once

#include <csignal>
#include <stdexcept>
#include <string>

namespace liftcheck {

/// The signal that asked liftcheck to stop (0: none); set by catch_interrupts' handler only.
extern volatile std::sig_atomic_t g_interrupt_signal;

/// Installs the handler for SIGINT, SIGTERM and SIGHUP.
void catch_interrupts();

/// Thrown when a signal stopped the work: exit 128 + the signal.
struct Interrupted : std::runtime_error {
  int sig;
  Interrupted(int s, const std::string& where) : std::runtime_error(where), sig(s) {}
};

/// Throws Interrupted ("while reading 'F'") when a signal has arrived.
inline void throw_if_interrupted(const std::string& where) {
  if (g_interrupt_signal) throw Interrupted(g_interrupt_signal, where);
}
/// The same, building the text only when needed.
template <class F>
void throw_if_interrupted_by(F&& where) {
  if (g_interrupt_signal) throw Interrupted(g_interrupt_signal, where());
}

}  // namespace liftcheck
