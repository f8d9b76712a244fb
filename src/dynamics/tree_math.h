// Coefficient vectors for the tree algorithms (articulated_body.h): bivectors and trivectors as
// six numbers in blade order, the matrices that act on them, and the motor between a body and
// its parent in 3×3 blocks. Internal to src/dynamics.
#pragma once

#include <Eigen/Core>

#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/dynamics/articulated_body.h"
#include "cga_rigid_sim/dynamics/inertia.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace tree_math {

using Vector6d = Eigen::Matrix<double, 6, 1>;
using Matrix6d = Eigen::Matrix<double, 6, 6>;

// (Fixed-size halves, not a comma initializer: that copies through dynamic-size blocks.)
inline Vector6d vec(const cga::Bivelocity& b) {
  Vector6d x;
  x.head<3>() = b.rot;
  x.tail<3>() = b.trans;
  return x;
}
inline Vector6d vec(const cga::Moment& m) {
  Vector6d x;
  x.head<3>() = m.rot;
  x.tail<3>() = m.trans;
  return x;
}
inline cga::Bivelocity bivector(const Vector6d& x) { return {x.head<3>(), x.tail<3>()}; }
inline cga::Moment moment(const Vector6d& x) { return {x.head<3>(), x.tail<3>()}; }

/// ⟨T, Ω⟩ = τ·w + f·v, the power of a moment on a velocity.
inline double pairing(const cga::Moment& T, const cga::Bivelocity& B) {
  return T.rot.dot(B.rot) + T.trans.dot(B.trans);
}
inline double pairing(const Vector6d& T, const cga::Bivelocity& B) {
  return T.head<3>().dot(B.rot) + T.tail<3>().dot(B.trans);
}

/// The inertia map I(·)∧n of a body as a matrix: diag(J1, J2, J3, mλ², mλ², mλ²).
inline Matrix6d inertiaMatrix(const Inertia& I, double lambda) {
  Matrix6d out = Matrix6d::Zero();
  const double m = I.mass() * lambda * lambda;
  for (int i = 0; i < 3; ++i) {
    out(i, i) = I.principalMoments()[i];
    out(i + 3, i + 3) = m;
  }
  return out;
}

// The sandwiches with M_pb = T(a) R (body b's frame in its parent's, TreeKinematics::M_P) in
// the blocks of the adjoint matrix (doc/articulated.md (A1)): R = kin.R_P[b], t = a/λ =
// kin.t_P[b]. Each equals Motor::apply to round-off (test/dynamics).

/// M_bp B M̃_bp: a bivector in the parent's frame seen from b, Ad(M_pb)⁻¹ (w, u) =
/// (Rᵀ w, Rᵀ (u − t × w)).
inline cga::Bivelocity toChild(const TreeKinematics& kin, int b, const cga::Bivelocity& B) {
  const Eigen::Matrix3d& R = kin.R_P[b];
  return {R.transpose() * B.rot, R.transpose() * (B.trans - kin.t_P[b].cross(B.rot))};
}
/// M_pb T M̃_pb: a trivector in b's frame carried to the parent's, Ad(M_pb)⁻ᵀ (τ, F) =
/// (R τ + t × R F, R F).
inline cga::Moment toParent(const TreeKinematics& kin, int b, const cga::Moment& T) {
  const Eigen::Vector3d F = kin.R_P[b] * T.trans;
  return {kin.R_P[b] * T.rot + kin.t_P[b].cross(F), F};
}

/// [t]× A for a 3×3 A: the cross product of t with every column.
inline Eigen::Matrix3d crossColumns(const Eigen::Vector3d& t, const Eigen::Matrix3d& A) {
  Eigen::Matrix3d out;
  for (int c = 0; c < 3; ++c) out.col(c) = t.cross(A.col(c));
  return out;
}

/// I_p += Ad(M_bp)ᵀ I Ad(M_bp) for a symmetric 6×6 inertia I of body b (articulated or
/// composite), in 3×3 blocks: with I = [[A, B], [Bᵀ, C]] and A', B', C' the blocks turned by R
/// (R A Rᵀ, …), Ad(M_bp)ᵀ = [[1, T], [0, 1]] diag(R, R), T = [t]×, and
///   Ad(M_bp)ᵀ I Ad(M_bp) = [[A' + T B'ᵀ − Y T, Y], [Yᵀ, C']],   Y = B' + T C'.
inline void addToParent(const TreeKinematics& kin, int b, const Matrix6d& I, Matrix6d& I_p) {
  const Eigen::Matrix3d& R = kin.R_P[b];
  const Eigen::Vector3d& t = kin.t_P[b];
  const Eigen::Matrix3d RA = R * I.topLeftCorner<3, 3>(), RB = R * I.topRightCorner<3, 3>(),
                        RC = R * I.bottomRightCorner<3, 3>();
  const Eigen::Matrix3d A = RA * R.transpose(), B = RB * R.transpose(), C = RC * R.transpose();
  const Eigen::Matrix3d Y = B + crossColumns(t, C);
  const Eigen::Matrix3d TBt = crossColumns(t, B.transpose());
  // Y T = −(T Yᵀ)ᵀ.
  const Eigen::Matrix3d YT = -crossColumns(t, Y.transpose()).transpose();
  I_p.topLeftCorner<3, 3>() += A + TBt - YT;
  I_p.topRightCorner<3, 3>() += Y;
  I_p.bottomLeftCorner<3, 3>() += Y.transpose();
  I_p.bottomRightCorner<3, 3>() += C;
}

}  // namespace tree_math
}  // namespace dynamics
}  // namespace cga_rigid_sim
