#pragma once
#include "engines/engine.hpp"
namespace liftcheck {
/// Simbody as Gazebo classic runs it: SemiExplicitEuler2Integrator at accuracy 1e-3, compliant
/// Hunt-Crossley contact (1e8 Pa, dissipation 100 s/m, transition velocity 0.01 m/s). The tricycle
/// is a tree of mobilizers (Free chassis, Pin knuckle and wheels); the disks are on Translation
/// mobilizers.
EngineInfo simbody_engine();
}  // namespace liftcheck
