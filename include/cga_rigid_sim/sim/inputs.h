// Inputs to the world, in the core's terms (the node converts messages to these). Each is
// validated by World before anything is applied; a refusal names the field and the rule.
#pragma once

#include <Eigen/Core>
#include <string>

#include "cga_rigid_sim/cga/force.h"

namespace cga_rigid_sim {
namespace sim {

/// A wrench F = f + αn at a point plus a couple, for a duration (exact rules: world.h).
/// `frame`: the world frame name (or empty), or a link of `body`. Given in a link frame the
/// wrench is fixed in that link and turns with it (a thruster); given in the world frame its
/// directions stay fixed in the world and its point is the material point that was there at
/// the start of its first step. α never changes the motion; it must be finite.
/// Error messages call the fields apply_wrench.{body, frame, f, alpha, point, couple,
/// start_time, duration}.
struct WrenchInput {
  std::string body;   ///< a body's name or any link of it
  std::string frame;  ///< world frame, empty (= world frame) or a link of `body`
  cga::Force F;       ///< N
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< m, in `frame`
  Eigen::Vector3d couple = Eigen::Vector3d::Zero();  ///< N m, in `frame`
  double start_time = 0.0;                           ///< sim time to start, s; 0 = the next step
  double duration = 0.0;  ///< s; 0 = one step; < 0 = until cleared; else round(d/dt) ≥ 1 steps
};

/// An impulse J = j + αn at a point plus an angular impulse, applied at the start of the step
/// its stamp falls in: ΔΩ_B = (I∧n)⁻¹ T_imp, the pose does not jump. `body`, `frame` as for
/// WrenchInput (a world-frame impulse acts at the world point at that step's pose).
/// Error messages call the fields apply_impulse.{body, frame, J, alpha, point, angular,
/// start_time}.
struct ImpulseInput {
  std::string body;
  std::string frame;
  cga::Force J;                                       ///< N s
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< m, in `frame`
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  ///< N m s, in `frame`
  double start_time = 0.0;                            ///< 0 = the next step
};

}  // namespace sim
}  // namespace cga_rigid_sim
