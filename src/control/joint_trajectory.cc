// The rules of a trajectory command (joint_trajectory.h).
#include "cga_rigid_sim/control/joint_trajectory.h"

#include <cmath>
#include <set>
#include <string>

namespace cga_rigid_sim {
namespace control {
namespace {

Error refuse(const std::string& field, const std::string& rule) {
  return Error("command", field, rule);
}

std::string indexed(const std::string& name, std::size_t i) {
  return name + "[" + std::to_string(i) + "]";
}

// A per-point vector: `required` → exactly n values; otherwise empty or n values; all finite.
Result<bool> checkValues(const std::vector<double>& values, std::size_t n, bool required,
                         const std::string& field) {
  if (values.empty() && !required) return true;
  if (values.size() != n) {
    return refuse(field, "has " + std::to_string(values.size()) + " values; must have " +
                             std::to_string(n) + " (one per joint name)" +
                             (required ? "" : " or none"));
  }
  for (std::size_t j = 0; j < n; ++j) {
    if (!std::isfinite(values[j]))  // the node's wording: "not finite (nan)"
      return refuse(indexed(field, j), std::string("not finite (") +
                                           (std::isnan(values[j]) ? "nan"
                                            : values[j] > 0       ? "inf"
                                                                  : "-inf") +
                                           ")");
  }
  return true;
}

}  // namespace

Result<bool> validate(const JointTrajectory& trajectory) {
  const std::size_t n = trajectory.joint_names.size();
  if (n == 0) return refuse("joint_names", "must name at least one joint");
  std::set<std::string> seen;
  for (std::size_t j = 0; j < n; ++j) {
    const std::string& name = trajectory.joint_names[j];
    if (name.empty()) return refuse(indexed("joint_names", j), "must not be empty");
    if (!seen.insert(name).second) {
      return refuse(indexed("joint_names", j), "'" + name + "' is named twice");
    }
  }
  if (!std::isfinite(trajectory.start_time) || trajectory.start_time < 0) {
    return refuse("header.stamp", "must be finite and >= 0 (0 = now)");
  }
  double previous = 0;
  for (std::size_t k = 0; k < trajectory.points.size(); ++k) {
    const TrajectoryPoint& p = trajectory.points[k];
    const std::string point = indexed("points", k);
    if (auto r = checkValues(p.positions, n, true, point + ".positions"); !r) return r;
    if (auto r = checkValues(p.velocities, n, false, point + ".velocities"); !r) return r;
    if (auto r = checkValues(p.accelerations, n, false, point + ".accelerations"); !r) return r;
    if (auto r = checkValues(p.effort, n, false, point + ".effort"); !r) return r;
    const double t = p.time_from_start;
    if (!std::isfinite(t) || t < 0) {
      return refuse(point + ".time_from_start", "must be finite and >= 0");
    }
    if (k > 0 && !(t > previous)) {
      return refuse(point + ".time_from_start", "must be greater than the previous point's (" +
                                                    std::to_string(previous) +
                                                    " s): times must increase strictly");
    }
    previous = t;
  }
  return true;
}

}  // namespace control
}  // namespace cga_rigid_sim
