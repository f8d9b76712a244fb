// The rules every input to the World is checked against (finite numbers, magnitudes, poses),
// each returning the refusal as a structured Error naming input, field and rule. Internal to
// the sim layer.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <optional>
#include <string>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/rotation_rule.h"

namespace cga_rigid_sim {
namespace sim {

/// Stamps and durations within this many steps of a step boundary count as on it: it absorbs
/// the round-off of s/dt for stamps that are multiples of dt (a few ulps of s/dt ≤ kMaxSteps,
/// i.e. ≤ 1e15 · 2.2e-16 ≈ 0.2 steps at the very end of the range, ~1e-13 for hours at 1 ms).
constexpr double kStepTolerance = 1e-9;

/// Numbers in refusals: 15 significant digits show any typed-in double unchanged.
inline std::string num(double x) { return formatNumber(x, 15); }

/// "<field>.x: not finite (nan)" for the first non-finite component, or nothing.
inline std::optional<Error> checkFinite(const std::string& input, const std::string& field,
                                        const Eigen::Vector3d& v) {
  static const char* const kAxes[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i)
    if (!std::isfinite(v[i]))
      return Error(input, field + "." + kAxes[i], "not finite (" + num(v[i]) + ")");
  return std::nullopt;
}
inline std::optional<Error> checkFinite(const std::string& input, const std::string& field,
                                        double x) {
  if (!std::isfinite(x)) return Error(input, field, "not finite (" + num(x) + ")");
  return std::nullopt;
}

/// |v| ≤ limit, or "|<field>| = … <unit> exceeds <limit_name> = … <unit>". stableNorm: the
/// norm of a finite vector is reported finite (norm() squares, and 1e200 would read "inf").
inline std::optional<Error> checkMagnitude(const std::string& input, const std::string& field,
                                           const Eigen::Vector3d& v, double limit,
                                           const char* limit_name, const char* unit) {
  const double m = v.stableNorm();
  if (m > limit)
    return Error(input, field,
                 "|" + field + "| = " + num(m) + " " + unit + " exceeds " + limit_name + " = " +
                     num(limit) + " " + unit);
  return std::nullopt;
}

/// A pose: finite translation, and a rotation by the one rotation rule (scene/rotation_rule.h).
inline std::optional<Error> checkPose(const std::string& input, const Eigen::Isometry3d& pose) {
  if (auto e = checkFinite(input, "pose.translation", Eigen::Vector3d(pose.translation())))
    return e;
  if (auto rule = scene::rotationMatrixRule(pose.linear()))
    return Error(input, "pose.rotation", *rule);
  return std::nullopt;
}

}  // namespace sim
}  // namespace cga_rigid_sim
