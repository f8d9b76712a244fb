// joint_trajectory_controller's semantics on a set of joints, without ROS
// (doc/control.md#the-trajectory-controller): a command replaces the current trajectory from its
// start time, points already past are dropped, the new spline starts from the current desired
// state, an empty command stops and holds; each update samples the desired state and checks the
// path and goal tolerances, aborting and holding on a violation.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "cga_rigid_sim/control/joint_trajectory.h"
#include "cga_rigid_sim/control/trajectory_spline.h"
#include "cga_rigid_sim/result.h"

namespace cga_rigid_sim {
namespace control {

/// A read-only view of the caller's joint values (a std::vector<double>, an Eigen vector, …).
struct JointValues {
  const double* data = nullptr;
  std::size_t size = 0;
  JointValues() = default;
  JointValues(const double* d, std::size_t n) : data(d), size(n) {}
  template <class Container>
  JointValues(const Container& c)  // NOLINT: implicit by design
      : data(c.data()), size(static_cast<std::size_t>(c.size())) {}
  double operator[](std::size_t i) const { return data[i]; }
};

/// Position tolerances of one joint (rad or m); 0 = not checked (joint_trajectory_controller).
struct JointTolerances {
  double trajectory = 0;  ///< |desired − actual| while the trajectory runs
  double goal = 0;        ///< |final − actual| at the end
};

/// The `constraints` of a trajectory controller.
struct TrajectoryConstraints {
  double goal_time = 0;                      ///< s after the end within which the goal must be met
  double stopped_velocity_tolerance = 0.01;  ///< |q̇| at the end; 0 = not checked
  std::vector<JointTolerances> joints;       ///< per controller joint (empty = none checked)
};

/// How a trajectory controller is set up: its joints (names for messages, indices into the
/// caller's joint vectors), its constraints and options, as the YAML gives them.
struct TrajectoryControllerOptions {
  std::string name;  ///< the controller's name, for messages
  std::vector<std::string> joint_names;
  std::vector<std::size_t> joint_indices;  ///< same length as joint_names
  TrajectoryConstraints constraints;
  double stop_trajectory_duration = 0;  ///< s; 0 = hold the actual position at once
  bool allow_partial_joints_goal = false;
};

enum class TrajectoryStatus {
  kHolding,    ///< no trajectory commanded yet, or an empty one: holding
  kExecuting,  ///< a trajectory is running (or waiting for its start time)
  kSucceeded,  ///< the last trajectory ended within its goal tolerances; its end is held
  kAborted,    ///< a tolerance was violated; holding where the joints were (see reason())
};
const char* statusName(TrajectoryStatus status);

/// What /<controller>/state publishes (control_msgs/JointTrajectoryControllerState's fields),
/// in the controller's joint order; error = desired − actual.
struct TrajectoryControllerState {
  std::vector<std::string> joint_names;
  std::vector<double> desired_positions, desired_velocities, desired_accelerations;
  std::vector<double> actual_positions, actual_velocities;
  std::vector<double> error_positions, error_velocities;
};

class TrajectoryController {
 public:
  /// Checks the options (joints named once, indices given for all, tolerances per joint or
  /// none, values finite and ≥ 0). The controller starts holding at `q` at time `now`
  /// (joint_trajectory_controller's starting()).
  static Result<TrajectoryController> create(TrajectoryControllerOptions options, double now,
                                             JointValues q);

  /// Takes a command at time `now` (q, q̇: the caller's whole joint vectors). Refused, with the
  /// current trajectory left running, when it breaks validate()'s rules, names a joint not of
  /// this controller, names only some joints without allow_partial_joints_goal, or has every
  /// point at or before `now`. Otherwise: an empty command holds (the actual position, or a
  /// stop over stop_trajectory_duration); else the trajectory replaces the current one from
  /// t_b = max(start, now) (start = header.stamp, 0 = now), its spline starting from the
  /// current desired state at t_b, its points at or before `now` dropped. Joints a partial
  /// command leaves out keep their trajectory. `check_tolerances` = false runs it without path
  /// and goal checks (joint_trajectory_controller's topic interface); returns the number of
  /// points dropped.
  Result<int> command(const JointTrajectory& trajectory, double now, JointValues q, JointValues qd,
                      bool check_tolerances = true);

  /// The desired state at `now` and the checks against the actual (q, q̇): path tolerances while
  /// the trajectory runs, goal tolerances and stopped_velocity_tolerance once it has ended
  /// (succeeding when met, aborting when not met by end + goal_time). A violation aborts and
  /// holds. Fills state(); returns the status after the update.
  TrajectoryStatus update(double now, JointValues q, JointValues qd);

  /// Stops and holds as an empty command does (e.g. a cancelled action goal).
  void hold(double now, JointValues q);

  const TrajectoryControllerState& state() const { return state_; }
  /// The desired (q, q̇, q̈) of controller joint j at the last update.
  const JointSample& desired(std::size_t j) const { return desired_[j]; }
  TrajectoryStatus status() const { return status_; }
  /// Why the last trajectory aborted, naming the joint and the tolerance; empty otherwise.
  const std::string& reason() const { return reason_; }
  const TrajectoryControllerOptions& options() const { return options_; }
  /// The time the current trajectory's last point is reached.
  double endTime() const { return spline_.endTime(); }

 private:
  explicit TrajectoryController(TrajectoryControllerOptions options);
  void abort(double now, JointValues q, std::string reason);
  Result<std::vector<std::size_t>> mapJoints(const JointTrajectory& trajectory) const;

  TrajectoryControllerOptions options_;
  TrajectorySpline spline_;  // one JointSpline per controller joint
  TrajectoryStatus status_ = TrajectoryStatus::kHolding;
  bool check_tolerances_ = false;
  std::vector<char> goal_reached_;  // per joint, latched once within its goal tolerances
  std::vector<JointSample> desired_;
  TrajectoryControllerState state_;
  std::string reason_;
};

}  // namespace control
}  // namespace cga_rigid_sim
