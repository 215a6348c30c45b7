// liftcheck list: the scenarios with their parameters, defaults and units.
#include <fmt/format.h>
#include <iostream>

#include "cli/command.hpp"
#include "engines/engine.hpp"
#include "scenarios/scenario.hpp"

namespace liftcheck::cli {

namespace {

int cmd_list(bool json) {
  if (json) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& s : scenarios()) j.push_back(s.to_json());
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  for (const auto& s : scenarios()) {
    std::cout << s.name << "  [" << s.vehicle << "; " << s.equations << "]\n  " << s.summary << "\n";
    for (const auto& p : s.params)
      std::cout << fmt::format("    {:<14} {:<10} {:<6} {}\n", p.key, p.default_text, p.unit, p.help);
  }
  std::cout << "engine configurations (see 'liftcheck engines'):";
  for (const auto& e : engines()) std::cout << " " << e.name;
  std::cout << "\n";
  return 0;
}

}  // namespace

Command add_list(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  auto* list = app.add_subcommand("list", "list the scenarios with their parameters, defaults and units");
  list->add_flag("--json", *json, "print JSON");
  return {list, [json] { return cmd_list(*json); }, false};
}

}  // namespace liftcheck::cli
