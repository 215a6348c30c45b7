// liftcheck diff: two results.json files compared, regressions and metrics whose errors grew.
#include <fmt/format.h>
#include <iostream>

#include "cli/command.hpp"
#include "input/params.hpp"  // InputError
#include "input/results_diff.hpp"
#include "input/results_codec.hpp"
#include "input/results_file.hpp"

namespace liftcheck::cli {

namespace {

int cmd_diff(const std::string& base_path, const std::string& head_path, double growth, bool json) {
  if (!(growth > 1.0)) throw InputError(fmt::format("--worse-factor must be above 1 (got {})", growth));
  // Only what the diff compares is kept of each file (a compact index, no document).
  const auto [base, head] = read_results_index_pair(base_path, head_path);
  DiffDef def;
  def.growth = growth;
  const ResultsDiff d = diff_results(base, head, def);
  if (json)
    std::cout << encode_diff(d).dump() << "\n";
  else
    std::cout << diff_text(d);
  return d.problems() == 0 ? 0 : 1;
}

}  // namespace

Command add_diff(CLI::App& app) {
  struct Options {
    std::string base_path, head_path;
    double growth = kDefaultWorseFactor;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* diff = app.add_subcommand("diff", "compare two results.json files: regressions and metrics whose errors grew");
  diff->add_option("base", o->base_path, "the earlier results.json")->required();
  diff->add_option("head", o->head_path, "the later results.json")->required();
  diff->add_option("--worse-factor,--growth", o->growth,
                   "factor by which a metric's error must grow to count as worse (every change is listed as moved)")
      ->capture_default_str();
  diff->add_flag("--json", o->json, "print the diff as one JSON object");
  return {diff, [o] { return cmd_diff(o->base_path, o->head_path, o->growth, o->json); }};
}

}  // namespace liftcheck::cli
