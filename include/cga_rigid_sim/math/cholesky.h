// Cholesky factorization of small dense matrices, on scalars (math::Cholesky below).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>

namespace cga_rigid_sim {
namespace math {

/// The Cholesky factorization A = L Lᵀ of a small symmetric positive definite matrix (a tree's
/// mass matrix), on scalars with the reciprocals of L's diagonal kept: the solves of a step are
/// short dependent chains, which divisions and Eigen's dynamic-size kernels would lengthen
/// several times. A matrix that is not positive definite leaves NaN in L (and in every
/// solution), which the integrators treat as a failed step.
class Cholesky {
 public:
  void compute(const Eigen::MatrixXd& A) {
    const int n = static_cast<int>(A.rows());
    L_.resize(n, n);
    inv_diag_.resize(n);
    switch (n) {  // the sizes of small trees with the loops unrolled: the same operations
      case 1:
        return computeFixed<1>(A.data(), L_.data(), inv_diag_.data());
      case 2:
        return computeFixed<2>(A.data(), L_.data(), inv_diag_.data());
      case 3:
        return computeFixed<3>(A.data(), L_.data(), inv_diag_.data());
      case 4:
        return computeFixed<4>(A.data(), L_.data(), inv_diag_.data());
      case 5:
        return computeFixed<5>(A.data(), L_.data(), inv_diag_.data());
      case 6:
        return computeFixed<6>(A.data(), L_.data(), inv_diag_.data());
      case 7:
        return computeFixed<7>(A.data(), L_.data(), inv_diag_.data());
      case 8:
        return computeFixed<8>(A.data(), L_.data(), inv_diag_.data());
      default:
        return computeAny(n, A.data(), L_.data(), inv_diag_.data());
    }
  }
  /// x ← A⁻¹ x: L y = x forward, then Lᵀ z = y backward, both along L's columns.
  void solveInPlace(Eigen::VectorXd& x) const {
    const int n = static_cast<int>(x.size());
    const double *L = L_.data(), *inv = inv_diag_.data();
    double* v = x.data();
    switch (n) {
      case 1:
        return solveFixed<1>(L, inv, v);
      case 2:
        return solveFixed<2>(L, inv, v);
      case 3:
        return solveFixed<3>(L, inv, v);
      case 4:
        return solveFixed<4>(L, inv, v);
      case 5:
        return solveFixed<5>(L, inv, v);
      case 6:
        return solveFixed<6>(L, inv, v);
      case 7:
        return solveFixed<7>(L, inv, v);
      case 8:
        return solveFixed<8>(L, inv, v);
      default:
        return solveAny(n, L, inv, v);
    }
  }
  Eigen::VectorXd solve(const Eigen::VectorXd& b) const {
    Eigen::VectorXd x = b;
    solveInPlace(x);
    return x;
  }

 private:
  // Column-major n × n: A(i, j) = A[i + n j]. The loops of the fixed sizes are unrolled fully
  // (the trip counts are constants), so the entries stay in registers.
  template <int N>
  static void computeFixed(const double* A, double* L, double* inv) {
    computeAny(N, A, L, inv);
  }
  template <int N>
  static void solveFixed(const double* L, const double* inv, double* v) {
    double x[N];
#pragma GCC unroll 8
    for (int i = 0; i < N; ++i) x[i] = v[i];
#pragma GCC unroll 8
    for (int j = 0; j < N; ++j) {
      const double y = x[j] * inv[j];
      x[j] = y;
#pragma GCC unroll 8
      for (int i = j + 1; i < N; ++i) x[i] -= L[i + N * j] * y;
    }
#pragma GCC unroll 8
    for (int i = N - 1; i >= 0; --i) {
      double sum = x[i];
#pragma GCC unroll 8
      for (int j = i + 1; j < N; ++j) sum -= L[j + N * i] * x[j];
      x[i] = sum * inv[i];
    }
#pragma GCC unroll 8
    for (int i = 0; i < N; ++i) v[i] = x[i];
  }
  static inline __attribute__((always_inline)) void computeAny(int n, const double* A, double* L,
                                                               double* inv_diag) {
#pragma GCC unroll 8
    for (int j = 0; j < n; ++j) {
      double d = A[j + n * j];
#pragma GCC unroll 8
      for (int k = 0; k < j; ++k) d -= L[j + n * k] * L[j + n * k];
      const double l = std::sqrt(d), inv = 1.0 / l;
      L[j + n * j] = l;
      inv_diag[j] = inv;
#pragma GCC unroll 8
      for (int i = j + 1; i < n; ++i) {
        double x = A[i + n * j];
#pragma GCC unroll 8
        for (int k = 0; k < j; ++k) x -= L[i + n * k] * L[j + n * k];
        L[i + n * j] = x * inv;
      }
    }
  }
  static void solveAny(int n, const double* L, const double* inv, double* v) {
    for (int j = 0; j < n; ++j) {
      const double* col = L + static_cast<std::ptrdiff_t>(j) * n;
      const double y = v[j] * inv[j];
      v[j] = y;
      for (int i = j + 1; i < n; ++i) v[i] -= col[i] * y;
    }
    for (int i = n - 1; i >= 0; --i) {
      const double* col = L + static_cast<std::ptrdiff_t>(i) * n;
      double sum = v[i];
      for (int j = i + 1; j < n; ++j) sum -= col[j] * v[j];
      v[i] = sum * inv[i];
    }
  }

  Eigen::MatrixXd L_;
  Eigen::VectorXd inv_diag_;
};

}  // namespace math
}  // namespace cga_rigid_sim
