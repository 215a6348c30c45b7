// liftcheck worker (hidden): runs validate's items in a process of its own.
#include "cli/command.hpp"
#include "harness/suite.hpp"

namespace liftcheck::cli {

Command add_worker(CLI::App& app) {
  auto* worker = app.add_subcommand("worker", "");
  worker->group("");
  return {worker, [] { return worker_main(); }, false};
}

}  // namespace liftcheck::cli
