// Engines outside liftcheck as configurations (docs/protocol.md): each registration file NAME.json
// (name, command, description, color) in the project's engines/outside/ or in a folder of
// LIFTCHECK_ENGINE_PATH becomes a registry entry; its hello (engine, version, precision, vehicles,
// knobs, fixed settings) is read when the configuration is first looked up, so listing the
// scenarios starts no process. Its car and disks are RigidCar and DrivenDisks over the protocol:
// the servo, the slip and contact bookkeeping and the scenario functions are liftcheck's own.
#pragma once

#include <string>
#include <vector>

#include "engines/engine.hpp"

namespace liftcheck {

/// The folders registrations are read from: the default suite's (default_suite_dir), then each
/// folder of LIFTCHECK_ENGINE_PATH (colon-separated; `--engine-dir` prepends to it).
std::vector<std::string> engine_dirs();

/// The default suite's registrations: `outside/suite` beside the running binary (the build copies
/// engines/outside there, so a build copied elsewhere runs the adapters it carries), or, where
/// there is none, the source tree's engines/outside/suite, compiled in.
std::string default_suite_dir();
/// True when default_suite_dir() is the folder beside the binary, false for the compiled-in one.
bool default_suite_is_beside_binary();

/// The script an outside configuration's command runs: the first argument (command[0] only where
/// it is a path) naming a file relative to the registration's folder, as an absolute path with
/// symbolic links resolved; empty for a compiled-in configuration or a command that names none.
std::string adapter_path(const EngineInfo& e);

/// One entry per registration file found, not yet described (no process started). A file that
/// cannot be read or is malformed, a name taken twice or by a compiled-in configuration is left
/// out and named in `problems` (one line each).
std::vector<EngineInfo> outside_engines(const std::vector<std::string>& compiled_names,
                                        std::vector<std::string>& problems);

/// Reads the entry's hello (starting its first child process) and fills in its library, version,
/// precision, vehicles, knobs and fixed settings. A child that cannot start or breaks the protocol
/// leaves the entry unavailable (EngineInfo::unavailable): its runs are error records naming why.
void describe_outside(EngineInfo& e);

/// describe_outside for each entry, as many at once as there are cores (each hello is mostly its
/// engine's start-up CPU: twelve npm configurations took 5.4 s one after another).
void describe_outside_all(const std::vector<EngineInfo*>& entries);

/// The replies of one run must all come within this many seconds of its engine object's making
/// (a little under the run's --timeout, so that a hang is an error record naming what the child
/// sent last rather than a worker stopped). 0.85 T - 1.5 s; 100.5 s for the default 120 s.
void set_protocol_timeout(double run_timeout_s);
double protocol_timeout_s();

/// A described outside configuration that no registration file names (tests, benchmarks): `name`
/// started by `command` in the folder `dir`. Unavailable (EngineInfo::unavailable) if its hello fails.
EngineInfo outside_engine(const std::string& name, const std::vector<std::string>& command, const std::string& dir);

/// Ends the idle child processes of every outside configuration (a process that only described
/// its configurations keeps none running).
void close_idle_children();

}  // namespace liftcheck
