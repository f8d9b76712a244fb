// What a World reports about itself: momentum and energy, body states, frames to publish, and
// a one-screen summary — computed from (Model, Data), never stored.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>
#include <string>
#include <vector>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/cga/bivector4.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// Entries of the momentum report for articulated trees are named this prefix plus the name of
/// the tree's first moving body (its floating root, or the child of its first joint).
constexpr const char* kTreePrefix = "tree:";

/// Momentum and energy of one body, of one articulated tree (named kTreePrefix + its first
/// body) or of the whole scene (named "total"), world axes. For a tree and for "total":
/// linear, angular_origin and the energies are the sums over their moving bodies; `angular` is
/// the angular momentum about their centre of mass, L_origin − x_cm × P (the bodies' spins plus
/// their orbital momentum about x_cm).
struct MomentumReport {
  enum class Kind { kBody, kTree, kTotal };
  Kind kind = Kind::kBody;
  std::string body;
  Eigen::Vector3d linear = Eigen::Vector3d::Zero();          ///< kg m/s
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();         ///< about the CoM, kg m²/s
  Eigen::Vector3d angular_origin = Eigen::Vector3d::Zero();  ///< about the world origin
  double kinetic_energy = 0.0;                               ///< J
  double potential_energy = 0.0;                             ///< J, uniform gravity
  /// J: the energy contacts have taken out since the start (or the last reset), so that
  /// kinetic + potential + dissipated = initial + work of inputs. "total" only (0 for a body).
  double dissipated_energy = 0.0;
};

/// A contact of the last step as users see it (doc/contacts.md): the two bodies and links by
/// name (the ground plane is kGroundPlaneName for both), world axes, SI units.
struct ContactReport {
  std::string body_a, link_a;  ///< the moving body and the link whose collision touches
  std::string body_b, link_b;  ///< the other one
  Eigen::Vector3d point = Eigen::Vector3d::Zero();             ///< m, world
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();           ///< unit, from b towards a
  double depth = 0.0;                                          ///< m, penetration (≤ 0: a gap)
  double normal_impulse = 0.0;                                 ///< N s on a along normal
  Eigen::Vector3d friction_impulse = Eigen::Vector3d::Zero();  ///< N s on a, world
};

/// A body's state as users see it (world axes).
/// Curved space (WorldConfig::curvature): one moving body's (or the total's, body "total")
/// 4-d world momentum L_W = ψ L_B ψ̃ (six coefficients e23, e31, e12, e14, e24, e34;
/// doc/curved_space.md#equation-of-motion) and kinetic energy; both conserved torque-free.
struct CurvedMomentumReport {
  std::string body;
  cga::Bivector4 L_W;           ///< kg m²/s
  double kinetic_energy = 0.0;  ///< J
};

struct BodyStateReport {
  std::string name;
  Eigen::Isometry3d pose_root = Eigen::Isometry3d::Identity();  ///< root link frame in world
  Eigen::Vector3d com = Eigen::Vector3d::Zero();                ///< centre of mass, world
  Eigen::Vector3d linear_velocity = Eigen::Vector3d::Zero();    ///< of the CoM, world axes
  Eigen::Vector3d angular_velocity = Eigen::Vector3d::Zero();   ///< world axes
  dynamics::BodyState state;  ///< motor M_WB and bivelocity Ω_B (blade coefficients)
};

/// One joint of an articulated tree as users see it (the node's /joint_states).
struct JointStateReport {
  std::string name;
  double position = 0.0;  ///< rad or m
  double velocity = 0.0;  ///< rad/s or m/s
  /// The effort the joint's actuator applied in the last step (held + timed, clamped to
  /// <limit effort>), N m or N; damping, friction and limit forces are not in it.
  double effort = 0.0;
  /// Steps in which the commanded effort exceeded <limit effort> and was clamped.
  std::uint64_t clamped_steps = 0;
};

/// A frame to publish: `child` (a link) relative to `parent` (world frame or a root link).
struct FramePose {
  std::string parent;
  std::string child;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
};

/// Per moving body (scene order), then per articulated tree (model order), then the scene total
/// named kTotalName.
std::vector<MomentumReport> momentumReports(const Model& model, const Data& data);
/// Body j (static bodies: their fixed pose, zero velocities).
BodyStateReport bodyStateReport(const Model& model, const Data& data, int j);
/// Every moving body.
std::vector<BodyStateReport> bodyStateReports(const Model& model, const Data& data);
/// world_frame → root link of every moving body.
std::vector<FramePose> movingFrames(const Model& model, const Data& data);
/// world_frame → root link of static bodies, and root link → each merged link.
std::vector<FramePose> staticFrames(const Model& model);
/// The contacts of the last step, in the solver's (deterministic) order.
std::vector<ContactReport> contactReports(const Model& model, const Data& data);
/// One of them: the bodies' and links' names of a solver's contact.
ContactReport contactReport(const Model& model, const Contact& c);
/// The integrator path per body, first 20 listed, counts per path.
std::string worldSummary(const Model& model, const Data& data);
/// The last tree fault (Data::tree_faults) as an error naming the tree, the joint or the pair of
/// its deepest contact, and the rule: "step.tree: tree 'base': step 12 left joint 'j2' at 2.1,
/// past its limit 2 (rule: no joint passes its limits); it was undone …".
Error treeFaultError(const Model& model, const TreeFaults& fault);

}  // namespace sim
}  // namespace cga_rigid_sim
