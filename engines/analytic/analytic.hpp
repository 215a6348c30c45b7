#pragma once
#include "engines/engine.hpp"

namespace liftcheck {
/// The reference engine: the horizontal lift (4.1) of the commanded path, integrated with an
/// error-controlled Dormand-Prince stepper at tolerance 1e-13.
EngineInfo analytic_engine();
}  // namespace liftcheck
