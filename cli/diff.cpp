// liftcheck diff: two results.json files compared, regressions and metrics whose errors grew.
#include <fmt/format.h>
#include <iostream>

#include "cli/command.hpp"
#include "input/params.hpp"  // InputError
#include "input/results_diff.hpp"
#include "input/results_file.hpp"

namespace liftcheck::cli {

namespace {

int cmd_diff(const std::string& base_path, const std::string& head_path, double growth, bool json) {
  if (!(growth > 1.0)) throw InputError(fmt::format("--growth must be > 1 (got {})", growth));
  // Only what the diff compares is kept of each file (a compact index, no document).
  const auto [base, head] = read_results_index_pair(base_path, head_path);
  DiffDef def;
  def.growth = growth;
  nlohmann::json d;
  try {
    d = diff_results(base, head, def);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("malformed results: {}", e.what()));
  }
  if (json)
    std::cout << d.dump() << "\n";
  else
    std::cout << diff_text(d);
  return d["regressions"].empty() && d["worse"].empty() ? 0 : 1;
}

}  // namespace

Command add_diff(CLI::App& app) {
  struct Options {
    std::string base_path, head_path;
    double growth = 10.0;
    bool json = false;
  };
  auto o = std::make_shared<Options>();
  auto* diff = app.add_subcommand("diff", "compare two results.json files: regressions and metrics whose errors grew");
  diff->add_option("base", o->base_path, "the earlier results.json")->required();
  diff->add_option("head", o->head_path, "the later results.json")->required();
  diff->add_option("--growth", o->growth, "factor by which a metric's error must grow to count as worse")
      ->capture_default_str();
  diff->add_flag("--json", o->json, "print the diff as one JSON object");
  return {diff, [o] { return cmd_diff(o->base_path, o->head_path, o->growth, o->json); }};
}

}  // namespace liftcheck::cli
