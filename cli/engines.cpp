// liftcheck engines: every configuration with its description and settings.
#include <fmt/format.h>
#include <iostream>
#include <nlohmann/json.hpp>

#include "cli/command.hpp"
#include "engines/protocol/outside.hpp"
#include "harness/results.hpp"
#include "input/results_codec.hpp"
#include "input/trace.hpp"  // printable

namespace liftcheck::cli {

namespace {

/// Every configuration: what it is, the fixed settings it applies and the ones --set may change.
int cmd_engines(bool json) {
  const std::vector<EngineInfo>& all_engines = described_engines();  // outside ones: their hello read
  close_idle_children();
  if (json) {
    // An outside configuration's files (registration, adapter) are its context's: which adapter it
    // runs, so a copied build can be checked.
    nlohmann::json es = nlohmann::json::array();
    for (const auto& e : all_engines) es.push_back(encode_engine_context(engine_context(e)));
    std::cout << es.dump(2) << "\n";
    return 0;
  }
  // An outside registration's texts are the user's: one line each, whatever they hold.
  const auto line = [](const std::string& s) { return printable(s, 1000); };
  std::cout << fmt::format("default suite of outside configurations: {} ({})\n", line(default_suite_dir()),
                           default_suite_is_beside_binary()
                               ? "beside the binary"
                               : "the source tree's, compiled in: there is no outside/suite beside the binary");
  for (const auto& e : all_engines) {
    std::vector<std::string> vehicles;
    for (const Vehicle v : vehicles_of(e)) vehicles.push_back(to_string(v));
    if (!e.outside.unavailable.empty()) vehicles = {"UNAVAILABLE"};
    std::cout << fmt::format(
        "{}  [{} {}; {}{}; {}; colour {}{}]\n  {}\n", e.name, line(e.library), line(e.version),
        fmt::join(vehicles, ", "), e.is_reference ? "; the reference" : "", e.precision, line(e.color),
        !e.is_outside() ? "" : "; outside: " + line(e.outside.registration) + ", runs " + line(adapter_path(e)),
        line(e.description));
    for (const auto& [k, v] : e.settings) std::cout << fmt::format("    {:<22} {}\n", line(k), line(v));
    for (const SettingSpec& k : e.knobs)
      std::cout << fmt::format("    --set {:<16} {} ({}): {}; default {}, {}\n", k.key, to_string(k.vehicle),
                               k.kind_name(), line(k.help), line(k.default_text), line(k.range_text()));
  }
  return 0;
}

}  // namespace

Command add_engines(CLI::App& app) {
  auto json = std::make_shared<bool>(false);
  auto* engines_cmd =
      app.add_subcommand("engines", "list every engine configuration with its description and settings");
  engines_cmd->add_flag("--json", *json, "print JSON");
  // Interruptible: a signal while an outside engine starts ends it and its process group.
  return {engines_cmd, [json] { return cmd_engines(*json); }};
}

}  // namespace liftcheck::cli
