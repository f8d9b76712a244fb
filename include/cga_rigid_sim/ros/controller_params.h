// The node's controllers as the parameter server holds them (doc/node.md#controllers):
// `~controllers` names the controllers to run; each one's dictionary is read from the node's
// namespace, as ros_control's convention puts it there (`rosparam load controllers.yaml` makes
// `<ns>/arm_controller/type`, `<ns>/arm_controller/joints`, …), and gazebo_ros_control's servo
// gains from `<ns>/gazebo_ros_control/pid_gains`. Read here into the core's ParamValue
// (parameters.h toParamValue); the World checks them (World::loadControllers,
// doc/control.md#configuration).
#pragma once

#include <ros/node_handle.h>

#include <string>
#include <vector>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/sim/world.h"

namespace cga_rigid_sim {
namespace node {

struct ControllerParams {
  /// `~controllers`, in order: a list of names, or one string of names separated by spaces as
  /// controller_manager's spawner takes them. Empty (or unset): no controller runs.
  std::vector<std::string> names;
  bool set = false;  ///< ~controllers was given (perhaps empty)
  /// `~spawn_controllers` (the same forms): the controllers a robot spawned by ~spawn_urdf
  /// runs under its namespace (doc/node.md#spawning-robots); unset: those of ~controllers.
  std::vector<std::string> spawn_names;
  /// Controller name → its dictionary: the named ones, and every other entry of the namespace
  /// with a `type` (so a misspelt name is answered with the controllers there are).
  scene::ParamValue controllers;
  /// `<ns>/gazebo_ros_control/pid_gains` (joint → {p, i, d, i_clamp}); none when unset.
  scene::ParamValue pid_gains;
  /// The node's namespace with a trailing slash ("/" or "/robot/"): where the names are read.
  std::string prefix;
};

/// Reads `~controllers` and `~spawn_controllers` from `pnh` and the controllers' dictionaries from
/// `nh`'s namespace. Errors name the parameter and the form ("~controllers[1]: expected a
/// controller name (a string), got int"); a dictionary the parameter server holds in a form the
/// core cannot take (date/time, binary) is refused naming its path.
Result<ControllerParams> readControllerParams(const ::ros::NodeHandle& nh,
                                              const ::ros::NodeHandle& pnh);

/// A refusal of World::loadControllers as the node says it at start: the core's field path
/// ("arm_controller.constraints.joint1.goal", input "controllers"; "joint1.p", input
/// "pid_gains") becomes the parameter's name ("/arm_controller/constraints/joint1/goal",
/// "/gazebo_ros_control/pid_gains/joint1/p"), followed by the rule.
std::string controllerRefusalText(const Error& refusal, const std::string& prefix);

/// Loads the controllers onto `world` (none when `params.names` is empty) and says so in the
/// start-up log: each warning of the load (ROS_WARN), then one line per controller with its
/// type, joints and rate. A refusal is logged as FATAL naming the parameter and the rule
/// (controllerRefusalText); returns false then.
bool startControllers(sim::World& world, const ControllerParams& params);

}  // namespace node
}  // namespace cga_rigid_sim
