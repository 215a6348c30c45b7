#include "cli/interrupts.hpp"

#include <csignal>

namespace liftcheck::cli {

namespace {
volatile std::sig_atomic_t g_signal = 0;
extern "C" void on_signal(int sig) { g_signal = sig; }
}  // namespace

void catch_interrupts() {
  struct sigaction sa {};
  sa.sa_handler = on_signal;
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
}

int pending_signal() { return g_signal; }

void throw_if_interrupted(const std::string& where) {
  if (g_signal) throw Interrupted(g_signal, where);
}

}  // namespace liftcheck::cli
