// liftcheck report: a results file's report, junit.xml and summary.md written again.
#include <filesystem>
#include <fmt/format.h>

#include "cli/command.hpp"
#include "cli/suite_output.hpp"
#include "input/params.hpp"  // InputError
#include "input/results_file.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck::cli {

namespace {

/// What rendering reads besides the runs (which read_results checks): the summary's counts, the
/// context, the sweeps and maps. A results file without them is bad input, named.
void check_renderable(const nlohmann::json& r, const std::string& file) {
  const std::string name = printable(file, 200);
  const auto refuse = [&](const std::string& what) {
    return InputError(fmt::format("'{}' is not a results file of validate or merge: {}", name, what));
  };
  if (!r.contains("summary") || !r["summary"].is_object()) throw refuse("no 'summary' object");
  for (const char* k : {"total", "unexpected", "pass", "known failure", "unexpected pass", "fail", "error", "skip"})
    if (!r["summary"].contains(k) || !r["summary"][k].is_number_integer())
      throw refuse(fmt::format("'summary.{}' is not a whole number", k));
  if (!r.contains("context") || !r["context"].is_object()) throw refuse("no 'context' object");
  if (r["context"].contains("engines") && !r["context"]["engines"].is_array())
    throw refuse("'context.engines' is not an array");
  for (const char* k : {"sweeps", "maps", "scenarios"})
    if (r.contains(k) && !r[k].is_array()) throw refuse(fmt::format("'{}' is not an array", k));
}

}  // namespace

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
            nlohmann::json results = read_results(m->results);
            check_renderable(results, m->results);
            m->out.snapshots = !m->no_snapshots;
            StagedOutput staged(m->out.out_dir);
            staged.refuse_inside(m->results, "the results file");
            try {
              return render_again(results, m->out, staged);
            } catch (const nlohmann::json::exception& e) {
              // A field the checks do not cover: the file is bad input, and nothing is published.
              throw InputError(fmt::format("'{}' is not a results file liftcheck can render: {}",
                                           printable(m->results, 200), printable(e.what(), 300)));
            }
          }};
}

}  // namespace liftcheck::cli
