#include "input/interrupt.hpp"

namespace liftcheck {

volatile std::sig_atomic_t g_interrupt_signal = 0;

namespace {
extern "C" void on_interrupt(int sig) { g_interrupt_signal = sig; }
}  // namespace

void catch_interrupts() {
  struct sigaction sa {};
  sa.sa_handler = on_interrupt;  // no SA_RESTART: a blocking read or wait returns EINTR and is checked
  sigemptyset(&sa.sa_mask);
  sigaction(SIGINT, &sa, nullptr);
  sigaction(SIGTERM, &sa, nullptr);
  sigaction(SIGHUP, &sa, nullptr);  // a closed terminal: the staging folder is removed, the old output kept
}

}  // namespace liftcheck
