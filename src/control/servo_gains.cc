// Controller types and the mapping of a controller joint onto the joint servo law
// (controller_config.h; doc/control.md#the-servo-law).
#include <string>

#include "cga_rigid_sim/control/controller_config.h"

namespace cga_rigid_sim {
namespace control {

const char* typeName(ControllerType type) {
  switch (type) {
    case ControllerType::kJointState:
      return "joint_state_controller/JointStateController";
    case ControllerType::kPositionTrajectory:
      return "position_controllers/JointTrajectoryController";
    case ControllerType::kEffortTrajectory:
      return "effort_controllers/JointTrajectoryController";
    case ControllerType::kVelocityTrajectory:
      return "velocity_controllers/JointTrajectoryController";
    case ControllerType::kGroupPosition:
      return "position_controllers/JointGroupPositionController";
    case ControllerType::kGroupVelocity:
      return "velocity_controllers/JointGroupVelocityController";
    case ControllerType::kGroupEffort:
      return "effort_controllers/JointGroupEffortController";
  }
  return "?";
}

bool isTrajectoryController(ControllerType type) {
  return type == ControllerType::kPositionTrajectory || type == ControllerType::kEffortTrajectory ||
         type == ControllerType::kVelocityTrajectory;
}

JointInterface jointInterface(ControllerType type) {
  switch (type) {
    case ControllerType::kJointState:
      return JointInterface::kNone;
    case ControllerType::kPositionTrajectory:
    case ControllerType::kGroupPosition:
      return JointInterface::kPosition;
    case ControllerType::kVelocityTrajectory:
    case ControllerType::kGroupVelocity:
      return JointInterface::kVelocity;
    case ControllerType::kEffortTrajectory:
    case ControllerType::kGroupEffort:
      return JointInterface::kEffort;
  }
  return JointInterface::kNone;
}

Result<ServoGains> servoGains(const ControllerConfig& config, const std::string& joint,
                              const std::map<std::string, PidGains>& pid_gains) {
  bool ours = false;
  for (const std::string& j : config.joints) ours = ours || j == joint;
  if (!ours) {
    return Error("controllers", config.name + ".joints",
                 "'" + joint + "' is not a joint of this controller");
  }
  ServoGains s;
  s.interface = jointInterface(config.type);
  if (s.interface == JointInterface::kNone) {
    return Error("controllers", config.name + ".type",
                 std::string(typeName(config.type)) + " commands no joint");
  }
  if (s.interface == JointInterface::kEffort) {
    if (config.type == ControllerType::kGroupEffort) return s;  // τ = the commanded effort
    // effort_controllers' trajectory controller: τ = velocity_ff·ṙ + PID(e, ė).
    const PidGains& g = config.gains.at(joint);  // parseControllers made sure it is there
    s.kp = g.p, s.ki = g.i, s.kd = g.d;
    s.i_clamp_min = g.i_clamp_min, s.i_clamp_max = g.i_clamp_max, s.antiwindup = g.antiwindup;
    const auto ff = config.velocity_ff.find(joint);
    s.kff_velocity = ff == config.velocity_ff.end() ? 0.0 : ff->second;
    return s;
  }
  // Position and velocity joints are servoed by gazebo_ros_control's PID from pid_gains.
  const auto servo = pid_gains.find(joint);
  if (servo == pid_gains.end()) {
    return Error("controllers", config.name + ".joints",
                 "joint '" + joint + "' is driven through a " +
                     (s.interface == JointInterface::kPosition ? "position" : "velocity") +
                     " interface, whose servo needs gains: set gazebo_ros_control/pid_gains/" +
                     joint + ": {p, i, d, i_clamp} in the controllers' namespace");
  }
  const PidGains& P = servo->second;
  if (s.interface == JointInterface::kPosition) {
    s.kp = P.p, s.ki = P.i, s.kd = P.d;
    s.i_clamp_min = P.i_clamp_min, s.i_clamp_max = P.i_clamp_max, s.antiwindup = P.antiwindup;
    return s;
  }
  if (P.i != 0 || P.d != 0) {
    return Error("pid_gains", joint,
                 "a velocity servo is proportional only here: i and d must be 0 (not supported)");
  }
  if (config.type == ControllerType::kGroupVelocity) {
    s.kd = P.p;  // τ = P (v − q̇), v the command = ṙ
    return s;
  }
  // velocity_controllers' trajectory controller: v = ff·ṙ + p e + d ė + i∫e, τ = P (v − q̇)
  //   = P p e + P (1 + d) ė + P i ∫e + P (ff − 1) ṙ   (using −P q̇ = P ė − P ṙ).
  const PidGains& g = config.gains.at(joint);
  const auto ff_it = config.velocity_ff.find(joint);
  const double ff = ff_it == config.velocity_ff.end() ? 0.0 : ff_it->second;
  s.kp = P.p * g.p;
  s.kd = P.p * (1 + g.d);
  s.ki = P.p * g.i;
  s.i_clamp_min = P.p * g.i_clamp_min, s.i_clamp_max = P.p * g.i_clamp_max;
  s.antiwindup = g.antiwindup;
  s.kff_velocity = P.p * (ff - 1);
  return s;
}

}  // namespace control
}  // namespace cga_rigid_sim
