// The liftcheck command: each subcommand registers its options on the app and says what it does.
#pragma once

#include <CLI/CLI.hpp>
#include <functional>

namespace liftcheck::cli {

struct Command {
  CLI::App* app = nullptr;  ///< the subcommand, set when it was given
  std::function<int()> run;
  /// SIGINT and SIGTERM stop it at its next event (list, serve and the worker keep the defaults).
  bool interruptible = true;
};

Command add_list(CLI::App& app);      // cli/list.cpp
Command add_engines(CLI::App& app);   // cli/engines.cpp
Command add_run(CLI::App& app);       // cli/run.cpp
Command add_validate(CLI::App& app);  // cli/validate.cpp
Command add_merge(CLI::App& app);     // cli/merge.cpp
Command add_worker(CLI::App& app);    // cli/worker.cpp
Command add_path(CLI::App& app);      // cli/path.cpp
Command add_score(CLI::App& app);     // cli/score.cpp
Command add_diff(CLI::App& app);      // cli/diff.cpp
Command add_report(CLI::App& app);    // cli/report.cpp
Command add_serve(CLI::App& app);     // cli/serve.cpp
Command add_explain(CLI::App& app);   // cli/explain.cpp
Command add_tune(CLI::App& app);      // cli/tune.cpp

}  // namespace liftcheck::cli
