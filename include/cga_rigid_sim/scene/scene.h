// Scene: what is simulated, as loaded and validated from URDF — constant after loading.
// (What changes as the simulation runs, the body states, lives in sim::World.)
//
// A body is a set of links merged by fixed joints. Its reference frame B has its origin at the
// body's centre of mass and its axes along the principal axes (body/inertia.h); every
// merged link keeps its frame as a constant motor M_BL so its pose M_WL = M_WB M_BL can be
// published. Static bodies (fixed to `world`) are never stepped; their B is their root link's
// frame. Every <collision> of the merged links becomes a CollisionShape of the body, at its
// constant pose M_BS in B (collision_shape.h); static bodies keep theirs (obstacles).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/motor.h"
#include "cga_rigid_sim/scene/collision_shape.h"
#include "cga_rigid_sim/scene/joint.h"
#include "cga_rigid_sim/scene/self_collision.h"
#include "cga_rigid_sim/scene/sensors.h"

namespace cga_rigid_sim {
namespace scene {

/// A link merged into a body, and where its frame sits in the body's frame B.
struct LinkFrame {
  std::string link;
  cga::Motor M_BL;
};

struct BodyModel {
  std::string name;                          ///< the body's name: its root link's name
  bool is_static = false;                    ///< fixed to the world: never stepped
  std::optional<dynamics::Inertia> inertia;  ///< set for every moving body
  std::vector<LinkFrame> links;              ///< root link first
  cga::Motor M_WB0;                          ///< initial pose of B
  cga::Bivelocity omega_B0;                  ///< initial body bivelocity
  std::vector<std::string> merged_joints;    ///< fixed joints merged into this body
  /// Every <collision> of every link in `links`, in the order of `links` and, within a link,
  /// of the document.
  std::vector<CollisionShape> shapes;
};

struct Scene {
  std::string source;  ///< file name or "robot_description"
  std::string robot_name;
  double lambda = 1.0;
  Eigen::Vector3d gravity_W{0.0, 0.0, -9.81};
  std::vector<BodyModel> bodies;
  /// The revolute, continuous and prismatic joints (joint.h), parent first: a joint's parent
  /// body is the world, a static body, a free root, or the child of an earlier joint. A child
  /// body's M_WB0 is its pose at the joints' initial positions; its omega_B0 is left zero (the
  /// World derives link velocities from the joint velocities).
  std::vector<JointModel> joints;
  /// Which pairs of one robot's links may collide: Gazebo's <self_collide> from the URDF, an
  /// SRDF's rules (srdf.h); combined with the mode when a World is made (self_collision.h).
  SelfCollisionRules self_collision;
  /// Gazebo's sensors and base drives the URDF declares (sensors.h, doc/sensors.md).
  SensorSet sensors;
  std::vector<std::string> warnings;  ///< e.g. relaxed triangle inequality

  /// Index of the joint with that name, or -1.
  int findJoint(const std::string& name) const;
  /// Index of the body with that name, or -1.
  int findBody(const std::string& name) const;
  /// Index of the body that owns the link, or -1; `link_index` gets its place in links.
  int findLink(const std::string& link, int* link_index = nullptr) const;
};

/// The integrator names the summary knows (those of body/integrator.h, in its order).
const std::vector<std::string>& summaryIntegratorNames();

/// The integrator path a body takes under `integrator` with the loads the scene itself defines
/// (uniform gravity, which is torque-free), before any applied wrench:
///   static bodies → "static"; under `auto`: "at-rest" (no gravity and zero initial velocity),
///   else "exact-spherical" / "exact-symmetric" / "exact-asymmetric" by inertia class; any
///   other integrator → its own name. An applied wrench (which can reach every moving body)
///   switches `auto` to "exact+kicks" while it acts.
std::string plannedIntegratorPath(const Scene& scene, const BodyModel& body,
                                  const std::string& integrator);

}  // namespace scene
}  // namespace cga_rigid_sim
