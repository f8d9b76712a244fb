// ros_control controller configuration, read from the parameter server's dictionary of a
// controllers' namespace (doc/control.md#configuration): the controller types we run, their
// joints, PID gains, trajectory constraints and rates; gazebo_ros_control's pid_gains; and the
// mapping of each controller joint onto the simulator's joint servo law.
#pragma once

#include <map>
#include <string>
#include <vector>

#include "cga_rigid_sim/control/pid_integral.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/param_value.h"

namespace cga_rigid_sim {
namespace control {

enum class ControllerType {
  kJointState,          ///< joint_state_controller/JointStateController
  kPositionTrajectory,  ///< position_controllers/JointTrajectoryController
  kEffortTrajectory,    ///< effort_controllers/JointTrajectoryController
  kVelocityTrajectory,  ///< velocity_controllers/JointTrajectoryController
  kGroupPosition,       ///< position_controllers/JointGroupPositionController
  kGroupVelocity,       ///< velocity_controllers/JointGroupVelocityController
  kGroupEffort,         ///< effort_controllers/JointGroupEffortController
};
/// The ros_control type string ("position_controllers/JointTrajectoryController", …).
const char* typeName(ControllerType type);
bool isTrajectoryController(ControllerType type);
/// What a joint of this controller type is driven through (JointState: none).
enum class JointInterface { kNone, kPosition, kVelocity, kEffort };
JointInterface jointInterface(ControllerType type);

struct JointConstraint {
  double trajectory = 0;  ///< path position tolerance; 0 = not checked
  double goal = 0;        ///< goal position tolerance; 0 = not checked
};

struct ControllerConstraints {
  double goal_time = 0;
  double stopped_velocity_tolerance = 0.01;
  std::map<std::string, JointConstraint> joints;  ///< by joint name; absent = 0, 0
};

struct ControllerConfig {
  std::string name;
  ControllerType type = ControllerType::kJointState;
  std::vector<std::string> joints;        ///< empty for the joint state controller
  std::map<std::string, PidGains> gains;  ///< `gains` (effort and velocity trajectory controllers)
  std::map<std::string, double> velocity_ff;  ///< `velocity_ff` (same), default 0
  ControllerConstraints constraints;
  /// joint_state_controller: publish_rate (required); trajectory controllers:
  /// state_publish_rate (default 50 Hz); group controllers: 0 (they publish no state).
  double publish_rate = 0;
  double action_monitor_rate = 20;      ///< trajectory controllers; for the action seam
  double stop_trajectory_duration = 0;  ///< trajectory controllers
  bool allow_partial_joints_goal = false;
};

struct ControllerSet {
  std::vector<ControllerConfig> controllers;  ///< in the order of `names`, or by name
  std::vector<std::string> warnings;          ///< keys not read, values ignored
};

/// Reads the controllers `names` from `ns`, the dictionary of the controllers' namespace
/// (controller name → its dictionary). `names` empty: every entry with a `type` (others are
/// passed over with a warning, gazebo_ros_control silently). Refused, naming
/// "<controller>.<key>" and the rule: a name absent, a type we do not run (the supported ones
/// listed), a missing or empty `joints`, a joint twice, a joint commanded by two controllers,
/// a value of the wrong kind, a negative gain, tolerance, time or rate, a trajectory
/// controller on effort or velocity without a p gain for one of its joints.
/// Error input: "controllers".
Result<ControllerSet> parseControllers(const scene::ParamValue& ns,
                                       const std::vector<std::string>& names = {});

struct PidGainsSet {
  std::map<std::string, PidGains> gains;  ///< by joint name
  std::vector<std::string> warnings;
};
/// Reads gazebo_ros_control's `pid_gains` dictionary (<ns>/gazebo_ros_control/pid_gains: joint →
/// {p, i, d, i_clamp, i_clamp_min, i_clamp_max, antiwindup}), as control_toolbox reads a Pid:
/// p required, i and d default 0, i_clamp gives ±|i_clamp|, i_clamp_min/max override each side.
/// Error input: "pid_gains".
Result<PidGainsSet> parsePidGains(const scene::ParamValue& pid_gains);

/// One joint's servo law, τ = kp (r − q) + kd (ṙ − q̇) + I + kff_velocity·ṙ + τ_ff, with
/// I = ki ∫(r − q) clamped to [i_clamp_min, i_clamp_max] as PidIntegral does, r and ṙ the
/// controller's reference (desired position and velocity; a velocity command is ṙ), τ_ff the
/// effort a controller commands directly. The effort is clamped to the joint's limit.
struct ServoGains {
  JointInterface interface = JointInterface::kEffort;
  double kp = 0, ki = 0, kd = 0;
  double i_clamp_min = 0, i_clamp_max = 0;
  bool antiwindup = false;
  double kff_velocity = 0;
};
/// The servo law of `joint` under `config` (doc/control.md#the-servo-law):
/// - position trajectory / group position: pid_gains of the joint (required: refused naming
///   gazebo_ros_control/pid_gains/<joint>), kp = p, ki = i, kd = d;
/// - effort trajectory: `gains` (p, i, d), kff_velocity = velocity_ff;
/// - velocity trajectory: the commanded velocity v = ff·ṙ + p e + d ė + i∫e on a velocity servo
///   τ = P (v − q̇) of pid_gains' p = P: kp = P p, kd = P (1 + d), ki = P i (clamps × P),
///   kff_velocity = P (ff − 1);
/// - group velocity: kd = P, kp = ki = 0 (the command is ṙ);
/// - group effort: all zero (the command is τ_ff).
/// A velocity servo with pid_gains i or d ≠ 0 is refused (not supported). Error input:
/// "controllers", field "<controller>.joints" or the missing gains' path.
Result<ServoGains> servoGains(const ControllerConfig& config, const std::string& joint,
                              const std::map<std::string, PidGains>& pid_gains);

}  // namespace control
}  // namespace cga_rigid_sim
