// loadUrdfScene: URDF (file or string) → Scene, with urdfdom, ROS-free.
// Returns the scene or an error that names the file, the link or joint, and the rule broken;
// never a partially loaded scene.
//
// The URDF subset, the extension element <cga_rigid_sim:mass_from_geometry> and every message
// are documented in doc/urdf.md; the initial-state dictionary in doc/initial_state.md (and at
// the top of src/scene/urdf/urdf_loader.cc).
#pragma once

#include <cstddef>
#include <string>

#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/scene/scene.h"

namespace cga_rigid_sim {
namespace scene {

struct SceneOptions {
  double lambda = 1.0;                         ///< CGA length scale, m
  Eigen::Vector3d gravity_W{0.0, 0.0, -9.81};  ///< zero switches gravity off
  /// ROS parameter ~relax_inertia (default true): the inertia repairs real robots' descriptions
  /// need (doc/urdf.md#inertias-from-cad). kNearestPhysical (default) makes them with a warning
  /// in Scene::warnings naming the link and the change: an inertia that breaks the triangle
  /// inequality becomes the nearest physical one, a massless link's inertia is dropped, a joint
  /// that moves no mass is welded, a moving body without mass that carries massive links gets a
  /// placeholder. kRefuse (strict) refuses each of them instead.
  dynamics::TrianglePolicy triangle_policy = dynamics::TrianglePolicy::kNearestPhysical;
  std::string world_frame = "world";  ///< the root link that means "the world"
  /// When set, every gazebo_ros plugin's <robotNamespace> is this one, written or not: what
  /// Gazebo's spawn service does with a robot_namespace (doc/sensors.md#spawned-robots).
  std::string plugin_namespace;
  ParamValue initial_state;  ///< README "Initial state"; may be none
};

/// What the loader reads at most (doc/urdf.md#bounds), checked on the text before urdfdom parses
/// it (urdfdom builds the link tree recursively: a chain of 200 000 links overflows an 8 MB
/// stack). A description past a bound is refused with a message naming the bound.
constexpr std::size_t kMaxUrdfBytes = std::size_t{128} << 20;  ///< 128 MiB of text
constexpr int kMaxUrdfLinks = 200000;  ///< <link> elements (and as many <joint> elements)
/// Joints from the root link to the deepest link (fixed ones included). Far below urdfdom's
/// recursion limit, and about the longest chain a tree integrator steps in reasonable time
/// (its mass matrix is factored every step: O(n³)).
constexpr int kMaxUrdfDepth = 1000;

Result<Scene> loadUrdfFile(const std::string& path, const SceneOptions& options);
/// `source` names the string in messages (e.g. "robot_description").
Result<Scene> loadUrdfString(const std::string& xml, const std::string& source,
                             const SceneOptions& options);

}  // namespace scene
}  // namespace cga_rigid_sim
