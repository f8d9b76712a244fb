// Changes to the set of bodies: spawning a URDF's body and deleting a body. Each edits the
// Model and the Data together, here and nowhere else, and bumps Model::topology_version.
// Internal to the sim layer (World's façade calls them; rules in world.h).
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

Result<bool> spawnUrdf(Model& model, Data& data, const std::string& name, const std::string& urdf,
                       const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                       const Eigen::Vector3d& w_W);

Result<bool> deleteBody(Model& model, Data& data, const std::string& body);

}  // namespace sim
}  // namespace cga_rigid_sim
