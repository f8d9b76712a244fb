// The rule for "is this a rotation", for every rotation a user hands the simulator: the
// orientation of an initial state (YAML), of a service request (a ROS quaternion) and of a
// pose given to the world as a matrix. One tolerance, two forms of the same check; each returns
// the refusal text (without the field's name: callers prefix it) or nothing.
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>

namespace cga_rigid_sim {
namespace scene {

/// How far from unit a quaternion may be and still be accepted (and normalised): |‖q‖ − 1|.
///
/// Rotations are typed by hand (YAML initial states, `rostopic pub`, service calls) with 4 to 7
/// significant digits. Rounding each component of a unit quaternion to 4 digits moves its norm
/// by at most ‖δq‖ ≤ √4 · 5e-5 = 1e-4 ((0.7071, 0, 0, 0.7071) has norm 0.99999), and by less
/// with more digits; 1e-3 accepts every such quaternion with a factor 10 of margin. Accepting
/// costs no accuracy: q and q/‖q‖ are the same rotation, so the one used is the one the digits
/// express. What is refused is not a rounded unit quaternion: the zero quaternion of an empty
/// message, a component left out or off by a digit (norm 0.71, 1.1).
constexpr double kRotationTolerance = 1e-3;

/// A quaternion (w, x, y, z) as a rotation: finite, and |‖q‖ − 1| ≤ kRotationTolerance. Returns
/// "not finite" or "must be a unit quaternion (norm …; …)", or nothing; the caller normalises.
std::optional<std::string> quaternionRule(double w, double x, double y, double z);

/// A matrix as a rotation: finite, max|RᵀR − I| ≤ 2 kRotationTolerance, det R > 0. The matrix
/// form of the quaternion's bound: the columns' norms within kRotationTolerance of 1 (so the
/// diagonal of RᵀR within 2 kRotationTolerance of 1, as |q|² is for the quaternion) and their
/// angles within 2 kRotationTolerance rad of 90°; a matrix typed to 4 digits is off by at most
/// 2 · √3 · 5e-5 ≈ 1.7e-4. det R > 0 refuses reflections. Returns "not finite" or "not a proper
/// rotation (max |R^T R - I| = …, det R = …; allowed …, det > 0)", or nothing.
std::optional<std::string> rotationMatrixRule(const Eigen::Matrix3d& R);

}  // namespace scene
}  // namespace cga_rigid_sim
