// joint_trajectory_controller's semantics (trajectory_controller.h; doc/control.md).
#include "cga_rigid_sim/control/trajectory_controller.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>
#include <utility>

namespace cga_rigid_sim {
namespace control {
namespace {

std::string number(double x) {
  std::ostringstream s;
  s << x;
  return s.str();
}

std::string listed(const std::vector<std::string>& names) {
  std::string out;
  for (const std::string& n : names) out += (out.empty() ? "" : ", ") + n;
  return out;
}

bool nonNegative(double x) { return std::isfinite(x) && x >= 0; }

}  // namespace

const char* statusName(TrajectoryStatus status) {
  switch (status) {
    case TrajectoryStatus::kHolding:
      return "holding";
    case TrajectoryStatus::kExecuting:
      return "executing";
    case TrajectoryStatus::kSucceeded:
      return "succeeded";
    case TrajectoryStatus::kAborted:
      return "aborted";
  }
  return "?";
}

TrajectoryController::TrajectoryController(TrajectoryControllerOptions options)
    : options_(std::move(options)) {}

Result<TrajectoryController> TrajectoryController::create(TrajectoryControllerOptions options,
                                                          double now, JointValues q) {
  const std::string& name = options.name;
  auto refuse = [&](const std::string& field, const std::string& rule) {
    return Error("config", name + "." + field, rule);
  };
  const std::size_t n = options.joint_names.size();
  if (n == 0) return refuse("joints", "must name at least one joint");
  std::set<std::string> seen;
  for (std::size_t j = 0; j < n; ++j) {
    if (!seen.insert(options.joint_names[j]).second) {
      return refuse("joints[" + std::to_string(j) + "]",
                    "'" + options.joint_names[j] + "' is named twice");
    }
  }
  if (options.joint_indices.size() != n) {
    return refuse("joints", "needs one joint index per joint name");
  }
  for (std::size_t j = 0; j < n; ++j) {
    if (options.joint_indices[j] >= q.size) {
      return refuse("joints[" + std::to_string(j) + "]",
                    "index " + std::to_string(options.joint_indices[j]) +
                        " is past the joint vector (" + std::to_string(q.size) + " joints)");
    }
  }
  const TrajectoryConstraints& c = options.constraints;
  if (!nonNegative(c.goal_time)) return refuse("constraints.goal_time", "must be finite and >= 0");
  if (!nonNegative(c.stopped_velocity_tolerance)) {
    return refuse("constraints.stopped_velocity_tolerance", "must be finite and >= 0");
  }
  if (!c.joints.empty() && c.joints.size() != n) {
    return refuse("constraints", "needs tolerances for every joint or for none");
  }
  for (std::size_t j = 0; j < c.joints.size(); ++j) {
    const std::string field = "constraints." + options.joint_names[j];
    if (!nonNegative(c.joints[j].trajectory)) {
      return refuse(field + ".trajectory", "must be finite and >= 0");
    }
    if (!nonNegative(c.joints[j].goal)) return refuse(field + ".goal", "must be finite and >= 0");
  }
  if (!nonNegative(options.stop_trajectory_duration)) {
    return refuse("stop_trajectory_duration", "must be finite and >= 0");
  }
  TrajectoryController controller(std::move(options));
  controller.options_.constraints.joints.resize(n);
  controller.state_.joint_names = controller.options_.joint_names;
  controller.goal_reached_.assign(n, 0);
  controller.spline_.joints.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    controller.spline_.joints[j] = JointSpline::hold(now, q[controller.options_.joint_indices[j]]);
  }
  const std::vector<double> zeros(q.size, 0.0);
  controller.update(now, q, zeros);
  return controller;
}

Result<std::vector<std::size_t>> TrajectoryController::mapJoints(
    const JointTrajectory& trajectory) const {
  const std::vector<std::string>& mine = options_.joint_names;
  std::vector<std::size_t> map(trajectory.joint_names.size());
  for (std::size_t i = 0; i < trajectory.joint_names.size(); ++i) {
    std::size_t j = 0;
    while (j < mine.size() && mine[j] != trajectory.joint_names[i]) ++j;
    if (j == mine.size()) {
      return Error("command", "joint_names[" + std::to_string(i) + "]",
                   "'" + trajectory.joint_names[i] + "' is not a joint of controller '" +
                       options_.name + "' (its joints: " + listed(mine) + ")");
    }
    map[i] = j;
  }
  if (!options_.allow_partial_joints_goal && map.size() != mine.size()) {
    return Error("command", "joint_names",
                 "names " + std::to_string(map.size()) + " of the " + std::to_string(mine.size()) +
                     " joints of controller '" + options_.name + "'; it takes all of them (" +
                     listed(mine) + ") unless allow_partial_joints_goal is true");
  }
  return map;
}

Result<int> TrajectoryController::command(const JointTrajectory& trajectory, double now,
                                          JointValues q, JointValues qd, bool check_tolerances) {
  if (auto valid = validate(trajectory); !valid) return valid.failure();
  auto map = mapJoints(trajectory);
  if (!map) return map.failure();
  if (trajectory.points.empty()) {
    hold(now, q);
    update(now, q, qd);
    return 0;
  }
  // Points at or before `now` are dropped (joint_trajectory_controller); all dropped → refused.
  const double start = trajectory.start_time == 0 ? now : trajectory.start_time;
  std::size_t first = 0;
  while (first < trajectory.points.size() &&
         start + trajectory.points[first].time_from_start <= now) {
    ++first;
  }
  if (first == trajectory.points.size()) {
    const double last = start + trajectory.points.back().time_from_start;
    return Error("command", "points",
                 "every point is at or before the current time (the last is " + number(now - last) +
                     " s in the past); nothing to execute");
  }
  const std::vector<TrajectoryPoint> kept(trajectory.points.begin() + first,
                                          trajectory.points.end());
  const double t_b = std::max(start, now);
  for (std::size_t i = 0; i < map->size(); ++i) {
    const std::size_t j = (*map)[i];
    spline_.joints[j] =
        JointSpline::splice(spline_.joints[j], now, t_b, knotsOfJoint(kept, start, i));
  }
  status_ = TrajectoryStatus::kExecuting;
  check_tolerances_ = check_tolerances;
  goal_reached_.assign(goal_reached_.size(), 0);
  reason_.clear();
  update(now, q, qd);
  return static_cast<int>(first);
}

void TrajectoryController::hold(double now, JointValues q) {
  const double T = options_.stop_trajectory_duration;
  for (std::size_t j = 0; j < spline_.joints.size(); ++j) {
    JointSpline& spline = spline_.joints[j];
    if (T == 0) {  // hold where the joint is
      spline = JointSpline::hold(now, q[options_.joint_indices[j]]);
      continue;
    }
    // Stop from the desired (p, v) over T as joint_trajectory_controller does: the first half of
    // the quintic from (p, v, 0) to (p, −v, 0) over 2T, which is even about its midpoint, so
    // there q̇ = 0, q = p + 5vT/8 and q̈ = −3v/(2T) (doc/control.md#holding).
    const JointSample d = spline.sample(now);
    SplineKnot a, b;
    a.time = now;
    a.position = d.position;
    a.velocity = d.velocity;
    b.time = now + T;
    b.position = d.position + 5.0 / 8.0 * d.velocity * T;
    b.acceleration = -1.5 * d.velocity / T;
    a.has_velocity = a.has_acceleration = b.has_velocity = b.has_acceleration = true;
    spline = JointSpline::through(a, {b});
  }
  status_ = TrajectoryStatus::kHolding;
  check_tolerances_ = false;
  reason_.clear();
}

void TrajectoryController::abort(double now, JointValues q, std::string reason) {
  hold(now, q);
  status_ = TrajectoryStatus::kAborted;
  reason_ = std::move(reason);
}

TrajectoryStatus TrajectoryController::update(double now, JointValues q, JointValues qd) {
  const std::size_t n = spline_.joints.size();
  spline_.sample(now, desired_);
  TrajectoryControllerState& s = state_;
  s.desired_positions.resize(n);
  s.desired_velocities.resize(n);
  s.desired_accelerations.resize(n);
  s.actual_positions.resize(n);
  s.actual_velocities.resize(n);
  s.error_positions.resize(n);
  s.error_velocities.resize(n);
  for (std::size_t j = 0; j < n; ++j) {
    const std::size_t k = options_.joint_indices[j];
    s.desired_positions[j] = desired_[j].position;
    s.desired_velocities[j] = desired_[j].velocity;
    s.desired_accelerations[j] = desired_[j].acceleration;
    s.actual_positions[j] = q[k];
    s.actual_velocities[j] = qd[k];
    s.error_positions[j] = desired_[j].position - q[k];
    s.error_velocities[j] = desired_[j].velocity - qd[k];
  }
  if (status_ != TrajectoryStatus::kExecuting) return status_;
  if (!check_tolerances_) {
    if (now >= spline_.endTime()) status_ = TrajectoryStatus::kSucceeded;
    return status_;
  }
  const TrajectoryConstraints& c = options_.constraints;
  // The reasons are formatted only when a check fails: update() runs every step.
  const auto at = [now] { return " at t = " + number(now) + " s"; };
  for (std::size_t j = 0; j < n; ++j) {
    const std::string& joint = options_.joint_names[j];
    const double e = s.error_positions[j], ev = s.error_velocities[j];
    const JointTolerances& tol = c.joints[j];
    const double end = spline_.joints[j].endTime();
    if (now < end) {  // running: the path tolerance
      if (tol.trajectory > 0 && std::abs(e) > tol.trajectory) {
        abort(now, q,
              "path tolerance violated: joint '" + joint + "' position error " + number(e) +
                  " exceeds constraints." + joint + ".trajectory = " + number(tol.trajectory) +
                  at());
        return update(now, q, qd);
      }
      continue;
    }
    if (goal_reached_[j]) continue;
    const bool position_ok = !(tol.goal > 0 && std::abs(e) > tol.goal);
    const bool velocity_ok =
        !(c.stopped_velocity_tolerance > 0 && std::abs(ev) > c.stopped_velocity_tolerance);
    if (position_ok && velocity_ok) {
      goal_reached_[j] = 1;
    } else if (!(now < end + c.goal_time)) {
      const std::string what = !position_ok
                                   ? "position error " + number(e) + " exceeds constraints." +
                                         joint + ".goal = " + number(tol.goal)
                                   : "velocity error " + number(ev) +
                                         " exceeds constraints.stopped_velocity_tolerance = " +
                                         number(c.stopped_velocity_tolerance);
      abort(now, q,
            "goal tolerance violated: joint '" + joint + "' " + what + at() + ", goal_time " +
                number(c.goal_time) + " s after the end at " + number(end) + " s");
      return update(now, q, qd);
    }
  }
  bool all = true;
  for (char r : goal_reached_) all = all && r;
  if (all) status_ = TrajectoryStatus::kSucceeded;
  return status_;
}

}  // namespace control
}  // namespace cga_rigid_sim
