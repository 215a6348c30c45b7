#include "harness/results.hpp"

#include <chrono>
#include <ctime>
#include <fmt/format.h>
#include <fstream>
#include <map>
#include <thread>
#include <unistd.h>
#include <sys/utsname.h>

#include "engines/protocol/outside.hpp"  // adapter_path
#include "input/results_codec.hpp"
#include "liftcheck_errata.hpp"
#include "liftcheck_tune_table.hpp"
#include "liftcheck_version.hpp"

namespace liftcheck {

namespace {

KnobInfo knob_info(const SettingSpec& k) {
  KnobInfo i;
  i.key = k.key;
  i.vehicle = k.vehicle;
  i.default_text = k.default_text;
  i.help = k.help;
  i.kind = k.kind_name();
  if (k.role == SettingRole::kSolverIterations) i.role = "solver_iterations";
  if (k.role == SettingRole::kDamping) i.role = "damping";
  if (k.numeric())
    i.min = k.min, i.max = k.max, i.min_exclusive = k.min_exclusive;
  else
    i.choices = k.choices;
  return i;
}

/// The committed tune answers (data/tune/table.json) of `engines`, by "SCENARIO CONFIG".
std::map<std::string, TuneEntry> tune_table_of(const std::vector<EngineContext>& engines) {
  std::map<std::string, TuneEntry> out;
  const nlohmann::json table = nlohmann::json::parse(kTuneTableJson, nullptr, false);
  if (!table.is_object() || !table.contains("entries")) return out;
  static const std::string kName = "data/tune/table.json";
  const JsonIn entries = JsonIn(table, kName, "").obj("entries");
  for (const auto& [pair, entry] : entries.value().items())
    for (const auto& e : engines)
      if (pair.substr(pair.find(' ') + 1) == e.name) out[pair] = decode_tune_entry(entries.obj(pair.c_str()));
  return out;
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  char date[32] = "unknown";
  std::tm utc{};
  if (gmtime_r(&now, &utc)) std::strftime(date, sizeof date, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return date;
}

Machine this_machine() {
  char host[256] = "unknown";
  gethostname(host, sizeof host - 1);
  utsname u{};
  uname(&u);
  return {host, fmt::format("{} {} {}", u.sysname, u.release, u.machine), LIFTCHECK_COMPILER,
          static_cast<int>(std::thread::hardware_concurrency())};
}

}  // namespace

EngineContext engine_context(const EngineInfo& e) {
  EngineContext c;
  c.name = e.name, c.library = e.library, c.version = e.version, c.description = e.description, c.color = e.color;
  c.is_reference = e.is_reference;
  c.vehicles = vehicles_of(e);
  if (e.contact_dynamics) c.features.push_back("contact_dynamics");
  if (e.four_wheels) c.features.push_back("four_wheels");
  if (e.brakes) c.features.push_back("brakes");
  std::map<std::string, std::string> settings(e.settings.begin(), e.settings.end());
  // The settings a user may change (--set), with their defaults: part of what the engine is.
  for (const SettingSpec& k : e.knobs)
    settings[fmt::format("--set {} ({})", k.key, to_string(k.vehicle))] =
        fmt::format("{}; default {}; {}", k.help, k.default_text, k.range_text());
  c.settings.assign(settings.begin(), settings.end());
  for (const SettingSpec& k : e.knobs) c.knobs.push_back(knob_info(k));
  c.registration = e.outside.registration;
  if (e.is_outside()) c.adapter = adapter_path(e);
  return c;
}

SuiteContext context_of(const std::vector<const EngineInfo*>& engines, double wall_s) {
  SuiteContext c;
  c.version = LIFTCHECK_VERSION;
  c.commit = LIFTCHECK_COMMIT;
  c.date = utc_now();
  c.machine = this_machine();
  for (const EngineInfo* e : engines) c.engines.push_back(engine_context(*e));
  c.wall_s = wall_s;
  c.errata = kErrataMarkdown;
  c.tune_table = tune_table_of(c.engines);
  return c;
}

}  // namespace liftcheck
