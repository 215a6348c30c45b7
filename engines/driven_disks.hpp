// What every rigid-body engine's two-disk vehicle shares: the control loop. Each step the rule is
// evaluated on the state the engine reports (as a vehicle's controller would) and M's commanded
// velocity handed to the engine, which realises it with its own actuation and integrator, moves N
// along its path, detects contact with its own collision pipeline and applies its own contact
// response. The loop never computes M's next position; it only books what the engine reports.
#pragma once

#include "engines/engine.hpp"

namespace liftcheck {

class DrivenDisks : public DiskEngine {
  friend class ProtocolServer;  // `liftcheck serve`: these hooks over the engine protocol

 public:
  DiskRun run(const DiskSetup& setup, const DiskProblem& problem) final;
  double simulated_s() const final { return stepped_s_; }

 protected:
  struct State {
    disks::Vec2 cM, cN;
    /// M's angular velocity in the world frame, rad/s: Farber's disks are planar vehicles whose
    /// velocity is commanded, so every engine holds M's spin (about every axis) and reports it.
    /// NaN until the adapter reads it: a read() that leaves it out is an error at the first step.
    Eigen::Vector3d wM_radps = Eigen::Vector3d::Constant(NAN);
  };
  /// Contacts between M and N that the engine's collision pass generated during one step.
  struct StepContacts {
    int count = 0;
    double depth_max_m = 0.0;  ///< deepest penetration among them (>= 0)
    /// The smallest signed distance among them where the engine reports one (an outside engine:
    /// positive for a speculative contact generated before the shapes touch); NaN: not reported
    /// (the contacts touch).
    double distance_min_m = NAN;
  };
  /// Builds the world: M a dynamic body at cM0 at rest, its rotation held, N a kinematic body at cN0.
  virtual void build(const DiskSetup& setup, const disks::Vec2& cM0, const disks::Vec2& cN0) = 0;
  /// One engine step of dt_s from the current state: M's actuation tracks vM_cmd, N moves to
  /// cN_next (velocity vN), collision detection runs on the state at the start of the step.
  virtual StepContacts step(const disks::Vec2& vM_cmd, const disks::Vec2& cN_next, const disks::Vec2& vN,
                            double dt_s) = 0;
  virtual State read() const = 0;
  /// A step's contacts touch when their smallest reported distance is at most this (an engine
  /// that reports distances stores positions with a rounding of about this much).
  virtual double touching_distance_m() const { return 0.0; }

 private:
  double stepped_s_ = 0.0;
};

}  // namespace liftcheck
