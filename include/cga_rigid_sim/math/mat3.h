// 3×3 kernels on plain doubles, once: a matrix as nine numbers, row-major (R[3 i + j]), a
// symmetric one as six (xx, yy, zz, xy, xz, yz), a vector as three. Written out on scalars for
// the tree algorithms' hot loops (Eigen's 3×3 products do not unroll at -O2); callers rely on
// the order of operations written here to the last bit.
#pragma once

namespace cga_rigid_sim {
namespace math {

/// y = R x.
inline void mul(const double* R, const double* x, double* y) {
  y[0] = R[0] * x[0] + R[1] * x[1] + R[2] * x[2];
  y[1] = R[3] * x[0] + R[4] * x[1] + R[5] * x[2];
  y[2] = R[6] * x[0] + R[7] * x[1] + R[8] * x[2];
}
/// y = Rᵀ x.
inline void mulT(const double* R, const double* x, double* y) {
  y[0] = R[0] * x[0] + R[3] * x[1] + R[6] * x[2];
  y[1] = R[1] * x[0] + R[4] * x[1] + R[7] * x[2];
  y[2] = R[2] * x[0] + R[5] * x[1] + R[8] * x[2];
}
/// y = a × b.
inline void cross(const double* a, const double* b, double* y) {
  y[0] = a[1] * b[2] - a[2] * b[1];
  y[1] = a[2] * b[0] - a[0] * b[2];
  y[2] = a[0] * b[1] - a[1] * b[0];
}
/// a · b.
inline double dot(const double* a, const double* b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
/// y = S x for a symmetric S (six numbers).
inline void mulSymmetric(const double* S, const double* x, double* y) {
  y[0] = S[0] * x[0] + S[3] * x[1] + S[4] * x[2];
  y[1] = S[3] * x[0] + S[1] * x[1] + S[5] * x[2];
  y[2] = S[4] * x[0] + S[5] * x[1] + S[2] * x[2];
}
/// out = A Rᵀ (six numbers) where A = R X with X symmetric, so that A Rᵀ is symmetric: the rows
/// of A against the rows of R, upper triangle only.
inline void symmetricRowsTimesRt(const double* A, const double* R, double* out) {
  out[0] = dot(A, R);
  out[1] = dot(A + 3, R + 3);
  out[2] = dot(A + 6, R + 6);
  out[3] = dot(A, R + 3);
  out[4] = dot(A, R + 6);
  out[5] = dot(A + 3, R + 6);
}
/// out = R S Rᵀ (six numbers) for a symmetric S (six numbers): R S by rows, then its rows
/// against R's.
inline void rotateSymmetric(const double* R, const double* S, double* out) {
  double RS[9];
  for (int i = 0; i < 3; ++i) {
    const double r0 = R[3 * i], r1 = R[3 * i + 1], r2 = R[3 * i + 2];
    RS[3 * i] = r0 * S[0] + r1 * S[3] + r2 * S[4];
    RS[3 * i + 1] = r0 * S[3] + r1 * S[1] + r2 * S[5];
    RS[3 * i + 2] = r0 * S[4] + r1 * S[5] + r2 * S[2];
  }
  symmetricRowsTimesRt(RS, R, out);
}
/// out = R diag(d) Rᵀ (six numbers).
inline void rotateDiagonal(const double* R, const double* d, double* out) {
  double RD[9];
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) RD[3 * r + c] = R[3 * r + c] * d[c];
  symmetricRowsTimesRt(RD, R, out);
}

}  // namespace math
}  // namespace cga_rigid_sim
