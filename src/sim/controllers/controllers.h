// The World's joint controllers (doc/control.md#in-the-world): loading them, their commands, and
// the control stage of the step. Internal to the sim layer (World's façade calls them).
//
// The control stage runs first in a step, after the due inputs: commands due at step k take
// effect (in (step, arrival) order), then every controller sets its joints' servos for the step
// from the state at t_k — a trajectory controller's desired state at t_k checked against the
// actual one (its tolerances), its references at the step's middle r + ½h ṙ, ṙ + ½h r̈ (the
// midpoint integrates the servo there); the integral term and feed-forward efforts go into
// TreeData::controller_effort.
#pragma once

#include <string>
#include <vector>

#include "cga_rigid_sim/control/joint_trajectory.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

/// Loads the controllers `names` (empty: all) of the ros_control dictionary `controllers`
/// (controller name → its dictionary), with gazebo_ros_control's `pid_gains` (none: defaults, a
/// warning each). All or nothing: a refusal leaves the data as it was. Returns the warnings.
Result<std::vector<std::string>> loadControllers(const Model& model, Data& data,
                                                 const scene::ParamValue& controllers,
                                                 const std::vector<std::string>& names,
                                                 const scene::ParamValue& pid_gains);
/// The controllers `names` (empty: all) of `controllers` instantiated for the spawned robot
/// `robot` (doc/control.md#spawned-robots): each one's name and joints prefixed by the robot's
/// namespace ("r1/arm_controller", joints "r1/joint1"; pid_gains and per-joint gains and
/// constraints likewise). Joint state controllers are passed over (/joint_states carries every
/// joint), so is a controller none of whose joints the robot has; one that has some but not all
/// is refused. All or nothing. Returns the warnings.
Result<std::vector<std::string>> loadRobotControllers(const Model& model, Data& data, int robot,
                                                      const scene::ParamValue& controllers,
                                                      const std::vector<std::string>& names,
                                                      const scene::ParamValue& pid_gains);
/// Removes the controllers of trees [first_tree, first_tree + count) with their waiting
/// commands; the trees after them shift down (a spawned robot deleted).
void removeControllersOfTrees(Data& data, int first_tree, int count);
/// Drops waiting commands; every controller holds the (reset) pose, integrals at zero.
void resetControllers(const Model& model, Data& data);

/// Validates a trajectory for a trajectory controller and queues it for the step of its
/// start_time (0 or past: the next step; its points already past are then dropped). Errors:
/// input "<controller>/command".
Result<bool> queueTrajectory(const Model& model, Data& data, const std::string& controller,
                             const control::JointTrajectory& trajectory);
/// Validates a group controller's command (one value per joint, finite; efforts within
/// max_force) and queues it for the next step.
Result<bool> queueGroupCommand(const Model& model, Data& data, const std::string& controller,
                               const std::vector<double>& values);

/// The controllers of tree `t` hold its joints where they are now (after a state edit): a
/// trajectory controller stops and holds, a group position controller's command becomes the
/// position, its servo's reference too; integrals restart.
void holdControllersAt(const Model& model, Data& data, int t);

/// The control stage (above).
void controlJoints(const Model& model, Data& data);

}  // namespace sim
}  // namespace cga_rigid_sim
