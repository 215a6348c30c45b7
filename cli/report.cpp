// liftcheck report: a results file's report, junit.xml and summary.md written again.
#include <filesystem>
#include <fmt/format.h>

#include "cli/command.hpp"
#include "cli/suite_output.hpp"
#include "input/params.hpp"  // InputError
#include "input/results_file.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck::cli {

Command add_report(CLI::App& app) {
  struct Options {
    std::string results;
    OutputOptions out{"build/report"};
    bool no_snapshots = false;
  };
  auto m = std::make_shared<Options>();
  auto* cmd = app.add_subcommand(
      "report", "write the report, junit.xml and summary.md of a results.json again (nothing is run again)");
  cmd->add_option("results", m->results, "a results.json written by validate or merge")->required();
  cmd->add_option("--out", m->out.out_dir, "output folder")->capture_default_str();
  add_report_memory_option(cmd, m->out);
  cmd->add_flag("--no-snapshots", m->no_snapshots, "pages and plots only");
  return {cmd, [m] {
            SuiteResults results = read_results(m->results);  // every field checked: bad input is exit 2
            if (results.is_baseline)
              throw InputError(fmt::format("'{}' is a baseline: it holds what a regression gate compares, not a report",
                                           printable(m->results, 200)));
            if (results.shard)
              throw InputError(fmt::format("'{}' is a shard's results: join the shards with 'liftcheck merge' first",
                                           printable(m->results, 200)));
            m->out.snapshots = !m->no_snapshots;
            StagedOutput staged(m->out.out_dir);
            staged.refuse_inside(m->results, "the results file");
            return render_again(results, m->out, staged);
          }};
}

}  // namespace liftcheck::cli
