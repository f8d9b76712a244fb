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

/// World::setBodyState (rules in world.h).
Result<bool> setBodyState(const Model& model, Data& data, const std::string& body,
                          const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                          const Eigen::Vector3d& w_W);

/// World::reset: every moving body's data remade at its initial state, active wrenches and
/// queued inputs dropped; the step counter runs on.
void resetBodies(const Model& model, Data& data);

}  // namespace sim
}  // namespace cga_rigid_sim
