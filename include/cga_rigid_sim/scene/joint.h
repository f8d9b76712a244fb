// Joint: a revolute, continuous or prismatic joint of an articulated tree, as loaded from URDF
// and validated (doc/urdf.md#joints) — constant after loading.
//
// The joint connects a parent body (links merged by fixed joints, scene.h) to a child body. Its
// frame J is the URDF joint frame: placed in the parent's body frame B_p by M_PJ (the joint
// <origin> composed with the parent link's place in its body), and equal to the child link's
// frame at q = 0. The joint moves the child relative to J by exp(−½ q S) with the unit screw
// axis S = (axis, 0) (revolute, continuous: q an angle, rad) or S = (0, axis/λ) (prismatic:
// q a length, m), axis the unit <axis> in J (doc/articulated.md#joint-motion). The child body's
// own frame B_c sits in J as M_JC = M_B_cL⁻¹ with L the child link (its M_BL in scene.h).
#pragma once

#include <Eigen/Core>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cga_rigid_sim/cga/motor.h"

namespace cga_rigid_sim {
namespace scene {

enum class JointType { kRevolute, kContinuous, kPrismatic };
const char* toString(JointType t);

/// From <limit>. A continuous joint has no position limits; a missing attribute is unbounded.
struct JointLimits {
  bool has_position = false;  ///< revolute, prismatic: lower ≤ upper from <limit>
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
  /// |effort| the joint can apply, N m or N (≥ 0; +∞ when absent).
  double effort = std::numeric_limits<double>::infinity();
  /// |velocity|, rad/s or m/s (≥ 0; +∞ when absent); documented, not enforced.
  double velocity = std::numeric_limits<double>::infinity();
};

/// URDF <mimic joint multiplier offset>: the joint follows another joint of its tree exactly,
/// q = multiplier · q_leader + offset (and its rate likewise), as an equality constraint of the
/// tree's motion (doc/urdf.md#mimic-joints). A chain of mimics (a follower of a follower) is
/// resolved to its end: `leader` never mimics another joint, and the multipliers and offsets
/// along the chain are composed.
struct JointMimic {
  int leader = -1;          ///< Scene::joints index of the independent joint followed
  double multiplier = 1.0;  ///< composed along the chain
  double offset = 0.0;      ///< rad or m, composed along the chain
  std::string written;      ///< the joint the URDF's <mimic joint=…> names (for messages)
};

struct JointModel {
  std::string name;
  JointType type = JointType::kRevolute;
  /// Body index (Scene::bodies) of the parent: a moving body (the child of an earlier joint,
  /// or the free root of a floating-base tree), a static body (a fixed base), or −1 for the
  /// world frame itself (then M_PJ places J in the world).
  int parent_body = -1;
  int child_body = -1;      ///< body index of the child (always a moving body)
  std::string parent_link;  ///< URDF names, for messages
  std::string child_link;
  cga::Motor M_PJ;  ///< the joint frame J in the parent's body frame B_p
  cga::Motor M_JC;  ///< the child's body frame B_c in J
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();  ///< unit, in J
  JointLimits limits;
  double damping = 0.0;           ///< <dynamics damping>, N m s/rad or N s/m, ≥ 0
  double friction = 0.0;          ///< <dynamics friction>, N m or N, ≥ 0 (Coulomb)
  double initial_position = 0.0;  ///< q at t = 0 (rad or m): ~initial_state, clamped to limits
  double initial_velocity = 0.0;  ///< q̇ at t = 0
  /// Set for a mimic joint; its initial position and velocity then follow its leader's.
  std::optional<JointMimic> mimic;
};

/// The positions the leader `joint` can take with every joint that mimics it within its own
/// limits: the leader's limits intersected with each follower's mapped through
/// (limit − offset) / multiplier. [lower, upper]; lower > upper when the constraints cannot be
/// met; ±∞ where nothing bounds it.
std::pair<double, double> mimicRange(const std::vector<JointModel>& joints, int joint);
/// Every mimic joint's initial position and velocity from its leader's
/// (q0 = multiplier · q0_leader + offset, clamped into its limits against rounding).
void followLeaders(std::vector<JointModel>& joints);

}  // namespace scene
}  // namespace cga_rigid_sim
