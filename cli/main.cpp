// liftcheck: validation harness for physics engines against the analytic car and disk models.
// Each subcommand is a file of its own (cli/command.hpp lists them).
#include <CLI/CLI.hpp>
#include <cstring>
#include <fmt/format.h>
#include <iostream>

#include "cli/command.hpp"
#include "cli/interrupts.hpp"
#include "input/params.hpp"  // InputError
#include "input/suggest.hpp"
#include "liftcheck_version.hpp"

using namespace liftcheck;
using namespace liftcheck::cli;

namespace {

/// "; did you mean 'run'?" for a mistyped subcommand, or "; did you mean '--engine'?" for a
/// mistyped option of the given subcommand ("" when nothing is near).
std::string suggestion(const CLI::App& app, int argc, char** argv) {
  if (argc < 2) return "";
  const std::string first = argv[1];
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; })) names.push_back(sub->get_name());
  const CLI::App* sub = nullptr;
  for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; }))
    if (s->get_name() == first) sub = s;
  if (!sub) return first.rfind("-", 0) == 0 ? "" : did_you_mean(first, names);
  std::vector<std::string> options;
  for (const CLI::Option* o : sub->get_options())
    for (const auto& n : o->get_lnames()) options.push_back("--" + n);
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0) continue;
    const std::string key = a.substr(0, a.find('='));
    if (std::find(options.begin(), options.end(), key) == options.end()) return did_you_mean(key, options);
  }
  return "";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"liftcheck: validates physics engines against exact kinematics (rolling without slipping, "
               "reaction mechanisms)"};
  app.require_subcommand(1);
  app.set_version_flag("--version", std::string(LIFTCHECK_VERSION_STRING));
  const std::vector<Command> commands = {add_list(app), add_engines(app), add_run(app),   add_validate(app), add_merge(app),
                                         add_worker(app), add_path(app),  add_score(app), add_diff(app), add_report(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "liftcheck: error: " << e.what() << suggestion(app, argc, argv) << "\n";
    return 2;
  }
  try {
    for (const Command& c : commands) {
      if (!*c.app) continue;
      if (c.interruptible) catch_interrupts();
      return c.run();
    }
  } catch (const Interrupted& e) {
    std::cerr << fmt::format("liftcheck: interrupted by {} {}; the previous outputs are left as they were\n", strsignal(e.sig), e.what());
    return 128 + e.sig;
  } catch (const InputError& e) {
    std::cerr << "liftcheck: error: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "liftcheck: internal error: " << e.what() << "\n";
    return 3;
  }
  return 2;
}
