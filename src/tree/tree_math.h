// Coefficient vectors for the tree algorithms (articulated_body.h): bivectors and trivectors as
// six numbers in blade order, the matrices that act on them, and the motor between a body and
// its parent in 3×3 blocks. Internal to src/tree.
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>

#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/cga/bivelocity.h"
#include "cga_rigid_sim/cga/moment.h"
#include "cga_rigid_sim/math/cholesky.h"
#include "cga_rigid_sim/math/mat3.h"
#include "cga_rigid_sim/tree/articulated_body.h"
#include "cga_rigid_sim/tree/tree_workspace.h"

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

/// A composite rigid body in one body's frame, the CRBA's ten numbers (tree_workspace.h).
using Composite = CompositeInertia;

/// Adds the composite c of a child whose frame sits at x_p = R x_b + t in its parent's (R as
/// nine numbers, row-major) to `parent`: m and h ← R h + m t, and I_o ← R I_o Rᵀ +
/// (2 h'·t + m t·t) 1 − (t h'ᵀ + h' tᵀ) − m t tᵀ with h' = R h (the parallel-axis shift of the
/// centre of mass from R c to R c + t).
inline void addCompositeToParent(const double* R, const double* t, const Composite& c,
                                 Composite& parent) {
  double RIR[6];  // R I_o Rᵀ
  math::rotateSymmetric(R, c.I, RIR);
  double hr[3];
  math::mul(R, c.h, hr);
  const double m = c.m;
  const double diag = 2.0 * math::dot(hr, t) + m * math::dot(t, t);
  const auto shift = [&](int i, int k) { return -(t[i] * hr[k] + hr[i] * t[k] + m * t[i] * t[k]); };
  parent.I[0] += RIR[0] + diag + shift(0, 0);
  parent.I[1] += RIR[1] + diag + shift(1, 1);
  parent.I[2] += RIR[2] + diag + shift(2, 2);
  parent.I[3] += RIR[3] + shift(0, 1);
  parent.I[4] += RIR[4] + shift(0, 2);
  parent.I[5] += RIR[5] + shift(1, 2);
  for (int i = 0; i < 3; ++i) parent.h[i] += hr[i] + m * t[i];
  parent.m += m;
}

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
// kin.t_P[b]. Each equals Motor::apply to round-off (test/tree).

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

/// I_p += Ad(M_bp)ᵀ I Ad(M_bp) for a symmetric 6×6 inertia I of body b (articulated or
/// composite), in 3×3 blocks: with I = [[A, B], [Bᵀ, C]] and A', B', C' the blocks turned by R
/// (R A Rᵀ, …), Ad(M_bp)ᵀ = [[1, T], [0, 1]] diag(R, R), T = [t]×, and
///   Ad(M_bp)ᵀ I Ad(M_bp) = [[A' + T B'ᵀ − Y T, Y], [Yᵀ, C']],   Y = B' + T C'.
/// Written out on scalars (Eigen's 3×3 products do not unroll at -O2); only the upper triangles
/// of the symmetric blocks are computed, and I_p is updated symmetrically.
inline void addToParent(const TreeKinematics& kin, int b, const Matrix6d& I, Matrix6d& I_p) {
  const Eigen::Matrix3d& R = kin.R_P[b];
  const double tx = kin.t_P[b].x(), ty = kin.t_P[b].y(), tz = kin.t_P[b].z();
  double RA[3][3], RB[3][3], RC[3][3];  // R times the blocks
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      RA[i][j] = R(i, 0) * I(0, j) + R(i, 1) * I(1, j) + R(i, 2) * I(2, j);
      RB[i][j] = R(i, 0) * I(0, j + 3) + R(i, 1) * I(1, j + 3) + R(i, 2) * I(2, j + 3);
      RC[i][j] = R(i, 0) * I(3, j + 3) + R(i, 1) * I(4, j + 3) + R(i, 2) * I(5, j + 3);
    }
  double A[3][3], B[3][3], C[3][3];  // turned blocks: X Rᵀ, (X Rᵀ)(i, j) = X_i · R_j
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      B[i][j] = RB[i][0] * R(j, 0) + RB[i][1] * R(j, 1) + RB[i][2] * R(j, 2);
      if (j < i) continue;
      A[i][j] = RA[i][0] * R(j, 0) + RA[i][1] * R(j, 1) + RA[i][2] * R(j, 2);
      C[i][j] = RC[i][0] * R(j, 0) + RC[i][1] * R(j, 1) + RC[i][2] * R(j, 2);
    }
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < i; ++j) {
      A[i][j] = A[j][i];
      C[i][j] = C[j][i];
    }
  // Y = B' + T C': column j of T C' is t × C'_j.
  double Y[3][3];
  for (int j = 0; j < 3; ++j) {
    Y[0][j] = B[0][j] + ty * C[2][j] - tz * C[1][j];
    Y[1][j] = B[1][j] + tz * C[0][j] - tx * C[2][j];
    Y[2][j] = B[2][j] + tx * C[1][j] - ty * C[0][j];
  }
  // T B'ᵀ: column j is t × (row j of B'); Y T: row i is (row i of Y) × t.
  const double* t = kin.t_P[b].data();
  double TBt[3][3], YT[3][3];  // TBt[j] is column j of T B'ᵀ, YT[i] row i of Y T
  for (int j = 0; j < 3; ++j) math::cross(t, B[j], TBt[j]);
  for (int i = 0; i < 3; ++i) {
    math::cross(t, Y[i], YT[i]);
    for (double& x : YT[i]) x = -x;  // (row of Y) × t = −t × (row of Y)
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = i; j < 3; ++j) {
      const double top = A[i][j] + TBt[j][i] - YT[i][j];
      I_p(i, j) += top;
      I_p(i + 3, j + 3) += C[i][j];
      if (j == i) continue;
      I_p(j, i) += top;
      I_p(j + 3, i + 3) += C[i][j];
    }
    for (int j = 0; j < 3; ++j) {
      I_p(i, j + 3) += Y[i][j];
      I_p(j + 3, i) += Y[i][j];
    }
  }
}

/// The Cholesky factorization of a tree's mass matrix (math/cholesky.h).
using Cholesky = math::Cholesky;

}  // namespace tree_math
}  // namespace dynamics
}  // namespace cga_rigid_sim
