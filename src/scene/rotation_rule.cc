#include "cga_rigid_sim/scene/rotation_rule.h"

#include <Eigen/LU>
#include <cmath>

#include "cga_rigid_sim/format.h"

namespace cga_rigid_sim {
namespace scene {

std::optional<std::string> quaternionRule(double w, double x, double y, double z) {
  if (!std::isfinite(w) || !std::isfinite(x) || !std::isfinite(y) || !std::isfinite(z))
    return "not finite";
  const double norm = std::sqrt(w * w + x * x + y * y + z * z);
  if (!(std::abs(norm - 1.0) <= kRotationTolerance))
    return "must be a unit quaternion (norm " + formatNumber(norm) + "; a norm within " +
           formatNumber(kRotationTolerance) + " of 1 is normalised, others are refused)";
  return std::nullopt;
}

std::optional<std::string> rotationMatrixRule(const Eigen::Matrix3d& R) {
  if (!R.allFinite()) return "not finite";
  const double tolerance = 2 * kRotationTolerance;  // the matrix form (rotation_rule.h)
  const double orth = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
  const double det = R.determinant();
  if (!(orth <= tolerance) || !(det > 0))
    return "not a proper rotation (max |R^T R - I| = " + formatNumber(orth) +
           ", det R = " + formatNumber(det) + "; allowed " + formatNumber(tolerance) + ", det > 0)";
  return std::nullopt;
}

}  // namespace scene
}  // namespace cga_rigid_sim
