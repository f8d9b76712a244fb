// Conversions of the controllers' messages (conversions.h): trajectory commands to the core's
// trajectories, trajectory controllers' states to <controller>/state (doc/node.md#controllers).
#include "cga_rigid_sim/ros/conversions.h"

namespace cga_rigid_sim {
namespace node {

control::JointTrajectory toJointTrajectory(const trajectory_msgs::JointTrajectory& msg) {
  control::JointTrajectory t;
  t.joint_names = msg.joint_names;
  t.start_time = toSimTime(msg.header.stamp);
  t.points.reserve(msg.points.size());
  for (const trajectory_msgs::JointTrajectoryPoint& p : msg.points) {
    control::TrajectoryPoint point;
    point.positions = p.positions;
    point.velocities = p.velocities;
    point.accelerations = p.accelerations;
    point.effort = p.effort;
    point.time_from_start = p.time_from_start.toSec();
    t.points.push_back(std::move(point));
  }
  return t;
}

cga_rigid_sim::JointTrajectoryControllerState toControllerStateMsg(
    const control::TrajectoryControllerState& state, const ::ros::Time& stamp,
    const ::ros::Duration& uptime) {
  cga_rigid_sim::JointTrajectoryControllerState msg;
  msg.header.stamp = stamp;
  msg.joint_names = state.joint_names;
  msg.desired.positions = state.desired_positions;
  msg.desired.velocities = state.desired_velocities;
  msg.desired.accelerations = state.desired_accelerations;
  msg.actual.positions = state.actual_positions;
  msg.actual.velocities = state.actual_velocities;
  msg.error.positions = state.error_positions;
  msg.error.velocities = state.error_velocities;
  msg.desired.time_from_start = uptime;
  msg.actual.time_from_start = uptime;
  msg.error.time_from_start = uptime;
  return msg;
}

}  // namespace node
}  // namespace cga_rigid_sim
