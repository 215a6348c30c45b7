// liftcheck list: the scenarios with their parameters, defaults and units.
#include <algorithm>
#include <fmt/format.h>
#include <iostream>

#include "cli/command.hpp"
#include "engines/engine.hpp"
#include "input/results_codec.hpp"
#include "scenarios/scenario.hpp"

namespace liftcheck::cli {

namespace {

int cmd_list(bool json) {
  if (json) {
    nlohmann::json j = nlohmann::json::array();
    for (const auto& s : scenarios()) j.push_back(encode_scenario(s.info()));
    std::cout << j.dump(2) << "\n";
    return 0;
  }
  // The parameters every scenario of a vehicle has alike (key, default, unit) are listed once.
  for (const Vehicle vehicle : kVehicles) {
    std::vector<const Scenario*> of;
    for (const auto& s : scenarios())
      if (s.vehicle == vehicle) of.push_back(&s);
    if (of.empty()) continue;
    const auto same = [](const ParamSpec& a, const ParamSpec& b) {
      return a.key == b.key && a.default_text == b.default_text && a.unit == b.unit;
    };
    std::vector<ParamSpec> shared;
    for (const auto& p : of.front()->params)
      if (std::all_of(of.begin(), of.end(), [&](const Scenario* s) {
            return std::any_of(s->params.begin(), s->params.end(), [&](const ParamSpec& q) { return same(p, q); });
          }))
        shared.push_back(p);
    std::cout << fmt::format("parameters of every {} scenario (unless listed with the scenario):\n",
                             to_string(vehicle));
    for (const auto& p : shared)
      std::cout << fmt::format("    {:<14} {:<10} {:<6} {}\n", p.key, p.default_text, p.unit, p.help);
    for (const Scenario* s : of) {
      std::cout << s->name << "  [" << to_string(s->vehicle) << "; " << s->equations << "]\n  " << s->summary << "\n";
      for (const auto& p : s->params)
        if (std::none_of(shared.begin(), shared.end(), [&](const ParamSpec& q) { return same(p, q); }))
          std::cout << fmt::format("    {:<14} {:<10} {:<6} {}\n", p.key, p.default_text, p.unit, p.help);
    }
    std::cout << "\n";
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
