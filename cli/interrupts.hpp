// SIGINT, SIGTERM and SIGHUP: the runner stops at its next event, a file being read or parsed, a
// score or a diff at its next check (input/interrupt.hpp holds the flag they all check); the
// outputs are left as they were.
#pragma once

#include "input/interrupt.hpp"

namespace liftcheck::cli {

using liftcheck::catch_interrupts;
using liftcheck::Interrupted;
using liftcheck::throw_if_interrupted;

/// The signal received, 0 when none.
inline int pending_signal() { return g_interrupt_signal; }

}  // namespace liftcheck::cli
