// Edits of the bodies' states from outside the step: set one body's pose and velocities, and
// reset every body to its initial state. Internal to the sim layer (World's façade calls them).
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// The state of a body placed with its root link at pose_root and the given CoM and angular
/// velocities (world axes): M_WB = M_WL0 M_BL0⁻¹ (the root link's frame sits at M_BL0 in B),
/// Ω_B with body-axis coefficients (R̃ w, R̃ v/λ) (doc/conventions.md (E6)).
dynamics::BodyState placedState(const cga::Motor& M_BL0, const Eigen::Isometry3d& pose_root,
                                const Eigen::Vector3d& v_W, const Eigen::Vector3d& w_W,
                                double lambda);

/// World::setBodyState (rules in world.h).
Result<bool> setBodyState(const Model& model, Data& data, const std::string& body,
                          const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                          const Eigen::Vector3d& w_W);

/// World::reset: every moving body's data remade at its initial state, active wrenches and
/// queued inputs dropped; the step counter runs on.
void resetBodies(const Model& model, Data& data);

}  // namespace sim
}  // namespace cga_rigid_sim
