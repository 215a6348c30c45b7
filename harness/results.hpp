// A suite's context (who ran it, on what, with which configurations): the typed SuiteContext of
// input/suite_result.hpp, filled from the registry and the machine.
#pragma once

#include <vector>

#include "engines/engine.hpp"
#include "input/suite_result.hpp"

namespace liftcheck {

/// The configuration as results.json records it: what it is, its features, settings and knobs.
EngineContext engine_context(const EngineInfo& e);

/// liftcheck's version and commit, the engines, the machine, the date, the wall time and the
/// committed tune answers of these configurations (data/tune/table.json).
SuiteContext context_of(const std::vector<const EngineInfo*>& engines, double wall_s);

}  // namespace liftcheck
