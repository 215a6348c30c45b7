// `liftcheck serve CONFIG`: one of liftcheck's own compiled-in configurations served over the
// engine protocol (docs/protocol.md) on standard input and output, so the protocol can be checked
// against the same engine in process (a test requires the same records) and its round trip
// measured (make bench).
#pragma once

#include <string>

namespace liftcheck {

/// Serves `config` on standard input and output until "bye" or the end of the input; 0 then.
/// Anything the engine itself prints on standard output goes to standard error instead. A
/// configuration that is not compiled in or not a rigid-body engine (the analytic reference) is
/// refused with one line on standard error: 2.
int serve_main(const std::string& config);

}  // namespace liftcheck
