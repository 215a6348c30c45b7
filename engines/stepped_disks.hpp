// What the Bullet and ODE two-disk runs share: each step, M's next position is one classical
// Runge-Kutta step of its rule from the engine's measured state (so the integrator adds ~1e-15
// per step and the engine's contact step is within one step of the analytic contact), N's next
// position is its path; the engine moves both bodies, steps, and reports contact from its own
// collision pipeline.
#pragma once

#include "engines/engine.hpp"

namespace liftcheck {

class SteppedDisks : public DiskEngine {
 public:
  DiskRun run(const DiskSetup& setup, const DiskProblem& problem) final;

 protected:
  virtual void place(const DiskSetup& setup, const disks::Vec2& cM, const disks::Vec2& cN) = 0;
  /// Moves M and N to the given positions over one step of dt_s and steps the world.
  virtual void move(const disks::Vec2& cM_next, const disks::Vec2& cN_next, double dt_s) = 0;
  virtual disks::Vec2 read_M() const = 0;
  virtual disks::Vec2 read_N() const = 0;
  /// The engine's collision pipeline: are the two disks in contact (touching or overlapping)?
  virtual bool in_contact() = 0;
};

}  // namespace liftcheck
