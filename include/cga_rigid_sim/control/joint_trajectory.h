// A joint trajectory as trajectory_msgs/JointTrajectory carries it, without ROS, and the rules a
// command must satisfy before a controller takes it (doc/control.md#trajectories).
#pragma once

#include <string>
#include <vector>

#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace control {

/// One waypoint, as trajectory_msgs/JointTrajectoryPoint: values in the order of
/// JointTrajectory::joint_names. `positions` is required; the others are empty or as long.
struct TrajectoryPoint {
  std::vector<double> positions;
  std::vector<double> velocities;
  std::vector<double> accelerations;
  std::vector<double> effort;
  double time_from_start = 0;  ///< s after JointTrajectory::start_time
};

/// A trajectory command. `start_time` is header.stamp in simulation time (s); 0 means "now",
/// the time the controller receives it, as joint_trajectory_controller reads a zero stamp.
struct JointTrajectory {
  std::vector<std::string> joint_names;
  double start_time = 0;
  std::vector<TrajectoryPoint> points;
};

/// Checks a trajectory against the rules of trajectory_msgs users: joint names non-empty and
/// unique; each point's positions as long as joint_names, velocities, accelerations and effort
/// empty or as long; every value finite; time_from_start finite, ≥ 0 and strictly increasing;
/// start_time finite and ≥ 0. An empty `points` is valid (it means "stop and hold"). On error:
/// Error{"command", field, rule}, the field as the message names it ("joint_names[1]",
/// "points[3].time_from_start", "points[0].velocities[2]", "header.stamp").
Result<bool> validate(const JointTrajectory& trajectory);

}  // namespace control
}  // namespace cga_rigid_sim
