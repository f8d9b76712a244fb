// Changes to the set of bodies: spawning a URDF's body and deleting a body. Each edits the
// Model and the Data together, here and nowhere else, and bumps Model::topology_version.
// Internal to the sim layer (World's façade calls them; rules in world.h).
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/input/inputs.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// World::spawnUrdf: a single body (no namespace, no joints) here, a robot by spawnRobot.
Result<bool> spawnUrdf(Model& model, Data& data, const std::string& name, const std::string& urdf,
                       const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                       const Eigen::Vector3d& w_W, const SpawnOptions& options = {});

/// World::deleteBody: a body, or a spawned robot whole (deleteRobot).
Result<bool> deleteBody(Model& model, Data& data, const std::string& body);

/// A loaded URDF (the world's λ, gravity, world frame) spawned as a robot named `name`
/// (topology_robots.cc): prefixed, placed, compiled on its own and appended at the end of the
/// Model and the Data; its controllers started. All or nothing.
Result<bool> spawnRobot(Model& model, Data& data, const std::string& name,
                        const SpawnOptions& options, scene::Scene robot,
                        const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                        const Eigen::Vector3d& w_W);

/// Removes spawned robot `robot` (Model::robots index) with its bodies, joints, trees, their
/// queued and active inputs and its controllers; the indices after them shift down.
Result<bool> deleteRobot(Model& model, Data& data, int robot);

/// Takes out of the scene the sensors fixed to links of bodies [b0, b0 + nb) and the drives
/// turning their joints (before those bodies leave Model::link_owner).
void removeSensorsOf(Model& model, int b0, int nb);

}  // namespace sim
}  // namespace cga_rigid_sim
