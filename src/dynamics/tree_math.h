// Coefficient vectors for the tree algorithms (articulated_body.h): bivectors and trivectors as
// six numbers in blade order, and the matrices that act on them. Internal to src/dynamics.
#pragma once

#include <Eigen/Core>

#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/dynamics/inertia.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace tree_math {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

inline Vector6d vec(const cga::Bivelocity& b) {
  Vector6d x;
  x << b.rot, b.trans;
  return x;
}
inline Vector6d vec(const cga::Moment& m) {
  Vector6d x;
  x << m.rot, m.trans;
  return x;
}
inline cga::Bivelocity bivector(const Vector6d& x) { return {x.head<3>(), x.tail<3>()}; }
inline cga::Moment moment(const Vector6d& x) { return {x.head<3>(), x.tail<3>()}; }

/// ⟨T, Ω⟩ = τ·w + f·v, the power of a moment on a velocity.
inline double pairing(const cga::Moment& T, const cga::Bivelocity& B) {
  return T.rot.dot(B.rot) + T.trans.dot(B.trans);
}

/// The inertia map I(·)∧n of a body as a matrix: diag(J1, J2, J3, mλ², mλ², mλ²).
inline Matrix6d inertiaMatrix(const Inertia& I, double lambda) {
  Vector6d d;
  d << I.principalMoments(), Eigen::Vector3d::Constant(I.mass() * lambda * lambda);
  return d.asDiagonal();
}

}  // namespace tree_math
}  // namespace dynamics
}  // namespace cga_rigid_sim
