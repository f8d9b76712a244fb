// loadUrdfScene: URDF (file or string) → Scene, with urdfdom, ROS-free.
// Returns the scene or an error that names the file, the link or joint, and the rule broken;
// never a partially loaded scene.
//
// The URDF subset, the extension element <cga_rigid_sim:mass_from_geometry> and every message
// are documented in doc/urdf.md; the initial-state dictionary in doc/initial_state.md (and at
// the top of src/scene/urdf_loader.cc).
#pragma once

#include <string>

#include "cga_rigid_sim/dynamics/inertia.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/scene/scene.h"

namespace cga_rigid_sim {
namespace scene {

struct SceneOptions {
  double lambda = 1.0;                         ///< CGA length scale, m
  Eigen::Vector3d gravity_W{0.0, 0.0, -9.81};  ///< zero switches gravity off
  /// ROS parameter ~relax_inertia: kNearestPhysical accepts inertias that break the triangle
  /// inequality, with a warning in Scene::warnings, using the nearest physical inertia.
  dynamics::TrianglePolicy triangle_policy = dynamics::TrianglePolicy::kRefuse;
  std::string world_frame = "world";  ///< the root link that means "the world"
  ParamValue initial_state;           ///< README "Initial state"; may be none
};

Result<Scene> loadUrdfFile(const std::string& path, const SceneOptions& options);
/// `source` names the string in messages (e.g. "robot_description").
Result<Scene> loadUrdfString(const std::string& xml, const std::string& source,
                             const SceneOptions& options);

}  // namespace scene
}  // namespace cga_rigid_sim
