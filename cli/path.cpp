// liftcheck path: a scenario's commanded path for a simulator outside liftcheck.
#include <iostream>

#include "cli/command.hpp"
#include "cli/lookup.hpp"

namespace liftcheck::cli {

namespace {

int cmd_path(const std::string& scenario, const std::vector<std::string>& sets, const std::string& format) {
  const Scenario& s = scenario_or_throw(scenario);
  const Overrides ov = overrides_or_throw(sets, s, nullptr);
  const nlohmann::json path = scenario_path(s, ov);
  if (format == "json")
    std::cout << path.dump() << "\n";
  else
    std::cout << path_csv(path);
  return 0;
}

}  // namespace

Command add_path(CLI::App& app) {
  struct Options {
    std::string scenario, format = "csv";
    std::vector<std::string> sets;
  };
  auto o = std::make_shared<Options>();
  auto* path_cmd = app.add_subcommand(
      "path",
      "write a scenario's commanded path (cars: t,alpha,beta; disks: N's t,cNx,cNy) for a simulator outside liftcheck");
  path_cmd->add_option("scenario", o->scenario, "scenario name (see 'liftcheck list')")->required();
  path_cmd->add_option("--set", o->sets, "override a parameter, KEY=VALUE (repeatable)")->allow_extra_args(false);
  path_cmd->add_option("--format", o->format, "csv or json")
      ->check(CLI::IsMember({"csv", "json"}))
      ->capture_default_str();
  return {path_cmd, [o] { return cmd_path(o->scenario, o->sets, o->format); }};
}

}  // namespace liftcheck::cli
