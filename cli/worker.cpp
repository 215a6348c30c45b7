// liftcheck worker (hidden): runs validate's items in a process of its own.
#include "cli/command.hpp"
#include <cstdlib>

#include "engines/protocol/outside.hpp"
#include "harness/suite_plan.hpp"
#include "harness/suite_results.hpp"
#include "harness/worker_pool.hpp"

namespace liftcheck::cli {

Command add_worker(CLI::App& app) {
  auto* worker = app.add_subcommand("worker", "");
  worker->group("");
  return {worker,
          [] {
            // The run's --timeout, from the liftcheck that started this worker (cli/lookup.cpp).
            if (const char* t = std::getenv("LIFTCHECK_RUN_TIMEOUT_S")) set_protocol_timeout(std::strtod(t, nullptr));
            return worker_main();
          },
          false};
}

}  // namespace liftcheck::cli
