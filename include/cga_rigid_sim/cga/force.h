// Force: the CGA force vector F = f + α n (doc/conventions.md (E12)); F·n = 0 for every α.
//
// f is the Euclidean force (N, or N s for an impulse), α a multiplier. α never changes the
// motion (it drops out of the moment λ X∧F once wedged with n); it is carried so messages can
// speak the algebra's language, and it is validated as finite.
#pragma once

#include <Eigen/Core>
#include <cmath>

namespace cga_rigid_sim {
namespace cga {

struct Force {
  Eigen::Vector3d f = Eigen::Vector3d::Zero();  ///< e1, e2, e3 coefficients
  double alpha = 0.0;                           ///< n coefficient

  Force() = default;
  Force(const Eigen::Vector3d& f_, double alpha_ = 0.0) : f(f_), alpha(alpha_) {}
  bool allFinite() const { return f.allFinite() && std::isfinite(alpha); }
};

}  // namespace cga
}  // namespace cga_rigid_sim
