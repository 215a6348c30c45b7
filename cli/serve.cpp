// liftcheck serve CONFIG: a compiled-in configuration over the engine protocol (docs/protocol.md).
#include "cli/command.hpp"
#include "engines/protocol/serve.hpp"

namespace liftcheck::cli {

Command add_serve(CLI::App& app) {
  auto config = std::make_shared<std::string>();
  auto* serve = app.add_subcommand(
      "serve", "serve a compiled-in configuration over the engine protocol on stdin and stdout (docs/protocol.md)");
  serve->add_option("config", *config, "configuration name (see 'liftcheck engines')")->required();
  return {serve, [config] { return serve_main(*config); }, false};
}

}  // namespace liftcheck::cli
