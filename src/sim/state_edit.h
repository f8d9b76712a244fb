// Edits of the bodies' states from outside the step: set one body's pose and velocities, and
// reset every body to its initial state. Internal to the sim layer (World's façade calls them).
#pragma once

#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// Bounds on a state set from outside (setBodyState, spawnUrdf): the root link's origin within
/// kMaxPointDistance (1e9 m) of the world origin, as points of application are; speeds up to
/// 1e9 m/s (three times the speed of light) and 1e9 rad/s. Far beyond anything physical, they
/// keep the body's state, momentum and energy, and a step's products of them, far from
/// overflow: an angular velocity of 1.8e308 rad/s was accepted before and made the state NaN.
constexpr double kMaxSpeed = 1e9;         ///< m/s
constexpr double kMaxAngularSpeed = 1e9;  ///< rad/s

/// The pose (finite, a proper rotation, origin within kMaxPointDistance) and the velocities
/// (finite, within kMaxSpeed and kMaxAngularSpeed) of setBodyState and spawnUrdf, or the
/// refusal naming `input` and the field ("set_body_state.linear_velocity: |linear_velocity| =
/// 2e+09 m/s exceeds the largest speed = 1e+09 m/s").
std::optional<Error> checkStateInput(const std::string& input, const Eigen::Isometry3d& pose_root,
                                     const Eigen::Vector3d& v_W, const Eigen::Vector3d& w_W);

/// World::setBodyState (rules in world.h).
Result<bool> setBodyState(const Model& model, Data& data, const std::string& body,
                          const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                          const Eigen::Vector3d& w_W);

/// World::reset: every moving body's data remade at its initial state, active wrenches and
/// queued inputs dropped; the step counter runs on.
void resetBodies(const Model& model, Data& data);

}  // namespace sim
}  // namespace cga_rigid_sim
