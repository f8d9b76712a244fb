// Point: a Euclidean point x and its conformal null vector
//   X(x) = (x² n + 2λx − λ² n̄) / (2λ²) = x/λ + (x²/(2λ²)) n − ½ n̄,   X² = 0, X·n = −1.
// The hot path keeps the Euclidean coordinates; the null vector's coefficients are formed on
// demand (tests compare them with the reference algebra).
#pragma once

#include <Eigen/Core>
#include <array>

namespace cga_rigid_sim {
namespace cga {

struct Point {
  Eigen::Vector3d x = Eigen::Vector3d::Zero();  ///< metres

  Point() = default;
  explicit Point(const Eigen::Vector3d& x_) : x(x_) {}

  /// Null-vector coefficients in the order e1, e2, e3, n, n̄.
  std::array<double, 5> nullCoefficients(double lambda) const {
    return {x.x() / lambda, x.y() / lambda, x.z() / lambda,
            x.squaredNorm() / (2.0 * lambda * lambda), -0.5};
  }
};

}  // namespace cga
}  // namespace cga_rigid_sim
