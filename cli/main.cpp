// liftcheck: validation harness for physics engines against the analytic car and disk models.
// Each subcommand is a file of its own (cli/command.hpp lists them).
#include <CLI/CLI.hpp>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <sstream>
#include <unistd.h>
#include <fmt/format.h>
#include <iostream>

#include "cli/command.hpp"
#include "cli/interrupts.hpp"
#include "engines/engine.hpp"
#include <fmt/ranges.h>
#include "input/params.hpp"  // InputError
#include "input/suggest.hpp"
#include "input/trace.hpp"  // printable: a message stays one line, whatever names it holds
#include "liftcheck_version.hpp"

using namespace liftcheck;
using namespace liftcheck::cli;

namespace {

/// "; did you mean 'run'?" for a mistyped subcommand, or "; did you mean '--engine'?" for a
/// mistyped option of the given subcommand ("" when nothing is near).
std::string suggestion(const CLI::App& app, int argc, char** argv) {
  int first_at = 1;  // the subcommand's place: after any --engine-dir DIR before it
  while (first_at < argc && std::string(argv[first_at]) == "--engine-dir") first_at += 2;
  if (first_at >= argc) return "";
  const std::string first = argv[first_at];
  std::vector<std::string> names;
  for (const CLI::App* sub : app.get_subcommands([](const CLI::App*) { return true; }))
    names.push_back(sub->get_name());
  const CLI::App* sub = nullptr;
  for (const CLI::App* s : app.get_subcommands([](const CLI::App*) { return true; }))
    if (s->get_name() == first) sub = s;
  if (!sub) return first.rfind("-", 0) == 0 ? "" : did_you_mean(first, names);
  std::vector<std::string> options;
  for (const CLI::App* a : {sub, &app})
    for (const CLI::Option* o : a->get_options())
      for (const auto& n : o->get_lnames()) options.push_back("--" + n);
  for (int i = first_at + 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a.rfind("--", 0) != 0) continue;
    const std::string key = a.substr(0, a.find('='));
    if (std::find(options.begin(), options.end(), key) == options.end()) return did_you_mean(key, options);
  }
  return "";
}

/// Every write to standard output is checked (a full disk, a closed pipe): the output that was
/// asked for is the command's result, so losing it is an error, exit 2 with the reason.
bool stdout_written() {
  errno = 0;
  std::cout.flush();
  const bool ok = std::cout.good() && std::fflush(stdout) == 0 && !std::ferror(stdout);
  if (ok) return true;
  // The stream's own error may have come earlier; a probe gives the reason (ENOSPC, EPIPE, ...).
  errno = 0;
  const int reason = ::write(STDOUT_FILENO, "\n", 1) < 0 && errno != 0 ? errno : EIO;
  std::cerr << fmt::format("liftcheck: error: cannot write to standard output: {}\n", std::strerror(reason));
  return ok;
}

/// --engine-dir DIR (anywhere on the command line) joins LIFTCHECK_ENGINE_PATH before the registry
/// is first read, and so reaches the worker processes too.
void engine_dirs_from_args(int argc, char** argv) {
  std::vector<std::string> dirs;
  for (int i = 1; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--engine-dir" && i + 1 < argc)
      dirs.push_back(argv[++i]);
    else if (a.rfind("--engine-dir=", 0) == 0)
      dirs.push_back(a.substr(13));
  }
  if (const char* old = std::getenv("LIFTCHECK_ENGINE_PATH"); old && *old) {
    std::stringstream ss(old);
    for (std::string d; std::getline(ss, d, ':');)
      if (!d.empty()) dirs.push_back(d);
  }
  if (dirs.empty()) return;
  // Absolute: a registered engine starts in its registration's folder, and a `liftcheck serve`
  // child reads the same variable there.
  std::error_code ec;
  for (std::string& d : dirs)
    if (const std::filesystem::path a = std::filesystem::absolute(d, ec); !ec) d = a.lexically_normal().string();
  setenv("LIFTCHECK_ENGINE_PATH", fmt::format("{}", fmt::join(dirs, ":")).c_str(), 1);
}

/// --help and --version print to standard output like any command: a write that fails is exit 2.
int help_or_version(const CLI::App& app, const CLI::Error& e) {
  const int status = app.exit(e);
  return stdout_written() ? status : 2;
}

}  // namespace

int main(int argc, char** argv) {
  engine_dirs_from_args(argc, argv);
  CLI::App app{
      "liftcheck: validates physics engines against exact kinematics (rolling without slipping, "
      "reaction mechanisms)"};
  app.require_subcommand(1);
  app.fallthrough();                         // --engine-dir after the subcommand
  std::vector<std::string> engine_dir_args;  // read before parsing (engine_dirs_from_args)
  app.add_option("--engine-dir", engine_dir_args,
                 "a folder of outside engine registrations, NAME.json (docs/protocol.md; also LIFTCHECK_ENGINE_PATH)");
  app.set_version_flag("--version", std::string(LIFTCHECK_VERSION_STRING));
  const std::vector<Command> commands = {add_list(app),  add_engines(app), add_run(app),   add_validate(app),
                                         add_merge(app), add_worker(app),  add_path(app),  add_score(app),
                                         add_diff(app),  add_report(app),  add_serve(app), add_explain(app),
                                         add_tune(app)};
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return help_or_version(app, e);
  } catch (const CLI::CallForAllHelp& e) {
    return help_or_version(app, e);
  } catch (const CLI::CallForVersion& e) {
    return help_or_version(app, e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "liftcheck: error: " << printable(e.what(), 2000) << printable(suggestion(app, argc, argv), 2000)
              << "\n";
    return 2;
  }
  try {
    if (!registration_problems().empty()) throw InputError(registration_problems().front());
    for (const Command& c : commands) {
      if (!*c.app) continue;
      if (c.interruptible) catch_interrupts();
      const int status = c.run();
      return stdout_written() ? status : 2;
    }
  } catch (const Interrupted& e) {
    std::cerr << fmt::format("liftcheck: interrupted by {}: {}; the previous outputs are left as they were\n",
                             strsignal(e.sig), printable(e.what(), 2000));
    return 128 + e.sig;
  } catch (const InputError& e) {
    std::cerr << "liftcheck: error: " << printable(e.what(), 2000) << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "liftcheck: internal error: " << printable(e.what(), 2000) << "\n";
    return 3;
  }
  return 2;
}
