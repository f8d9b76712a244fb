// loadUrdfScene: URDF (file or string) → Scene, with urdfdom, ROS-free.
// Returns the scene or an error that names the file, the link or joint, and the rule broken;
// never a partially loaded scene.
#pragma once

#include <string>

#include "cga_rigid_sim/dynamics/inertia.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/scene/scene.h"

namespace cga_rigid_sim {
namespace scene {

struct SceneOptions {
  double lambda = 1.0;                                  ///< CGA length scale, m
  Eigen::Vector3d gravity_W{0.0, 0.0, -9.81};           ///< zero switches gravity off
  dynamics::TrianglePolicy triangle_policy = dynamics::TrianglePolicy::kRefuse;
  std::string world_frame = "world";                    ///< the root link that means "the world"
  ParamValue initial_state;                             ///< README "Initial state"; may be none
};

Result<Scene> loadUrdfFile(const std::string& path, const SceneOptions& options);
/// `source` names the string in messages (e.g. "robot_description").
Result<Scene> loadUrdfString(const std::string& xml, const std::string& source,
                             const SceneOptions& options);

/// The one-screen summary printed on load: bodies, links merged into each, mass, principal
/// moments, inertia class, integrator path under `integrator`, active loads.
std::string sceneSummary(const Scene& scene, const std::string& integrator);

}  // namespace scene
}  // namespace cga_rigid_sim
