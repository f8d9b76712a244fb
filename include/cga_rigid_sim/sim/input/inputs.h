// Inputs to the world, in the core's terms (the node converts messages to these). Each is
// validated by World before anything is applied; a refusal names the field and the rule.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "cga_rigid_sim/cga/force.h"
#include "cga_rigid_sim/scene/param_value.h"

namespace cga_rigid_sim {
namespace sim {

/// A wrench F = f + αn at a point plus a couple, for a duration (exact rules: world.h).
/// `frame`: the world frame name (or empty), or a link of `body`. Given in a link frame the
/// wrench is fixed in that link and turns with it (a thruster); given in the world frame its
/// directions stay fixed in the world and its point is the material point that was there at
/// the start of its first step. α never changes the motion; it must be finite.
/// Error messages call the fields apply_wrench.{body, frame, f, alpha, point, couple,
/// start_time, duration}.
struct WrenchInput {
  std::string body;   ///< a body's name or any link of it
  std::string frame;  ///< world frame, empty (= world frame) or a link of `body`
  cga::Force F;       ///< N
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< m, in `frame`
  Eigen::Vector3d couple = Eigen::Vector3d::Zero();  ///< N m, in `frame`
  double start_time = 0.0;                           ///< sim time to start, s; 0 = the next step
  double duration = 0.0;  ///< s; 0 = one step; < 0 = until cleared; else round(d/dt) ≥ 1 steps
};

/// An impulse J = j + αn at a point plus an angular impulse, applied at the start of the step
/// its stamp falls in: ΔΩ_B = (I∧n)⁻¹ T_imp, the pose does not jump. `body`, `frame` as for
/// WrenchInput (a world-frame impulse acts at the world point at that step's pose).
/// Error messages call the fields apply_impulse.{body, frame, J, alpha, point, angular,
/// start_time}.
struct ImpulseInput {
  std::string body;
  std::string frame;
  cga::Force J;                                       ///< N s
  Eigen::Vector3d point = Eigen::Vector3d::Zero();    ///< m, in `frame`
  Eigen::Vector3d angular = Eigen::Vector3d::Zero();  ///< N m s, in `frame`
  double start_time = 0.0;                            ///< 0 = the next step
};

/// Efforts for joints by name (the node's ~joint_efforts, sensor_msgs/JointState), taking effect
/// at the step of `stamp` (0 = the next step) and each held until the next command for that
/// joint, as an effort controller does. Each effort is clamped to the joint's <limit effort>
/// when applied (counted in JointStateReport::clamped_steps). Refused as a whole, nothing
/// applied, for: names and efforts of different lengths, an unknown joint, a duplicate name,
/// an effort that is not finite or larger than max_force (N m or N), a stamp already past. Error
/// messages call the fields joint_efforts.{name, effort, stamp} ("joint_efforts.effort[2]: not
/// finite (nan)").
struct JointEffortInput {
  std::vector<std::string> names;
  std::vector<double> efforts;  ///< N m (revolute, continuous) or N (prismatic)
  double stamp = 0.0;           ///< sim time, s; 0 = the next step
};
/// An effort added to one joint for a time (the node's ~apply_joint_effort service), on top of
/// the held effort; the sum is clamped. Fields apply_joint_effort.{joint, effort, start_time,
/// duration}; the duration rules of WrenchInput (0 = one step, < 0 = until cleared).
struct TimedJointEffortInput {
  std::string joint;
  double effort = 0.0;
  double start_time = 0.0;
  double duration = 0.0;
};

/// Joint positions and rates set by joint name (the node's ~set_joint_state), at the step of
/// `stamp` (0 = the next step), as a state edit: the tree's integrator restarts from the new
/// state, mimic joints follow their leaders, and the controllers driving those joints hold the
/// new positions. Refused as a whole, nothing applied, for: lengths that differ (velocities may
/// be empty: 0), an unknown or repeated joint, a mimic joint (set its leader), a value not
/// finite, a position outside the joint's limits, a rate beyond its <limit velocity>, a stamp
/// already past. Fields set_joint_state.{name, position, velocity, stamp}.
struct JointStateInput {
  std::vector<std::string> names;
  std::vector<double> positions;   ///< rad or m
  std::vector<double> velocities;  ///< rad/s or m/s; empty = all 0
  double stamp = 0.0;              ///< sim time, s; 0 = the next step
};

/// What World::spawnUrdf takes besides the body's name, URDF and placement
/// (doc/node.md#spawning-robots). A URDF with joints, or any URDF given a namespace, is spawned
/// as a robot: every link and joint is named "<robot_namespace>/<its URDF name>", and the
/// controllers below are started for it under the namespace.
struct SpawnOptions {
  /// A ROS name ("r1", "cell/r1"); empty: names as the URDF has them.
  std::string robot_namespace;
  /// The ros_control dictionary, controller names and pid_gains of World::loadControllers; a
  /// robot runs those of its controllers whose joints it has (doc/control.md#spawned-robots).
  /// None and no names: no controller.
  scene::ParamValue controllers;
  std::vector<std::string> controller_names;
  scene::ParamValue pid_gains;
};

}  // namespace sim
}  // namespace cga_rigid_sim
