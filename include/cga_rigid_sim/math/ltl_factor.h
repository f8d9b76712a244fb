// Featherstone's LTL factorisation M = Lᵀ L of a matrix with a tree's sparsity (math::LtlFactor
// below): the one factorisation behind the midpoint integrator's TreeCholesky
// (src/tree/tree_factor.h) and the contact solve's TreeFactor (src/contact/contact_tree_factor.h).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <vector>

namespace cga_rigid_sim {
namespace math {

/// The factor M = Lᵀ L of a symmetric positive definite matrix that is zero except where one
/// coordinate is an ancestor of the other (or the same), for a numbering in which a parent's
/// index is smaller than its children's (Featherstone, Rigid Body Dynamics Algorithms, 2008,
/// §6.5). Eliminating from the leaves in keeps that sparsity: L_ij is nonzero only for j = i or
/// j an ancestor of i, so factoring costs Σ_i d_i² and a solve 2 Σ_i d_i (d_i: the ancestors of
/// coordinate i).
///
/// Row i of L left of its diagonal is stored contiguously in the order of i's path to the root
/// (parent first). The ancestors of an ancestor a of i are the rest of i's path after a, so
/// every loop of the factorisation and the solves runs over contiguous entries, where walking
/// the parents would make each step wait for the load of the next index. The arithmetic, and
/// its order per entry, is that of the walk over the parents.
class LtlFactor {
 public:
  /// Per coordinate its parent coordinate (smaller than its own index) or −1. Builds the paths
  /// (only when the parents differ from the last ones: no allocation once sized).
  void setParents(const std::vector<int>& parent) {
    if (parent == parent_) return;
    parent_ = parent;
    const int n = static_cast<int>(parent.size());
    offset_.resize(n + 1);
    path_.clear();
    for (int k = 0; k < n; ++k) {
      offset_[k] = static_cast<int>(path_.size());
      for (int i = parent[k]; i >= 0; i = parent[i]) path_.push_back(i);
    }
    offset_[n] = static_cast<int>(path_.size());
    row_.resize(path_.size());
    diag_.resize(n);
    inv_diag_.resize(n);
  }
  const std::vector<int>& parents() const { return parent_; }
  int size() const { return static_cast<int>(parent_.size()); }

  /// Factors A (of size(), its lower triangle read at the ancestor pairs). With `check`, stops
  /// and returns false at a pivot that is not positive and finite; without, such a matrix
  /// leaves NaN in the factor (and in every solve with it), and true is returned.
  bool compute(const Eigen::MatrixXd& A, bool check) {
    const int n = size();
    const double* a = A.data();
    const Eigen::Index lda = A.rows();
    for (int k = 0; k < n; ++k) {
      diag_[k] = a[k + k * lda];
      for (int p = offset_[k]; p < offset_[k + 1]; ++p) row_[p] = a[k + path_[p] * lda];
    }
    for (int k = n - 1; k >= 0; --k) {
      const double d = diag_[k];
      if (check && !(d > 0.0 && std::isfinite(d))) return false;
      const double l = std::sqrt(d), inv = 1.0 / l;
      diag_[k] = l;
      inv_diag_[k] = inv;
      double* r = row_.data() + offset_[k];
      const int m = offset_[k + 1] - offset_[k];
      for (int p = 0; p < m; ++p) r[p] *= inv;
      // L_k's outer product off its ancestors' block: (a, b) for b = a, then a's ancestors.
      for (int p = 0; p < m; ++p) {
        const int i = path_[offset_[k] + p];
        const double lki = r[p];
        diag_[i] -= lki * r[p];
        double* ri = row_.data() + offset_[i];
        const double* rk = r + p + 1;
        for (int q = 0, mi = m - p - 1; q < mi; ++q) ri[q] -= lki * rk[q];
      }
    }
    return true;
  }

  /// x ← M⁻¹ x: Lᵀ y = x (leaves first), then L z = y (root first), along the paths.
  void solveInPlace(double* x) const {
    const int n = size();
    for (int k = n - 1; k >= 0; --k) eliminate<1>(x, 1, 0, k);
    for (int k = 0; k < n; ++k) finish<1>(x, 1, 0, k);
  }

  /// x ← M⁻¹ e_k (x of size(), overwritten). Lᵀ y = e_k is zero off k's path to the root, so
  /// the first half runs along that path alone; the same bits as solveInPlace of e_k.
  void solveUnit(int k, double* x) const {
    const int n = size();
    for (int i = 0; i < n; ++i) x[i] = 0.0;
    x[k] = 1.0;
    eliminate<1>(x, 1, 0, k);
    for (int p = offset_[k]; p < offset_[k + 1]; ++p) eliminate<1>(x, 1, 0, path_[p]);
    for (int i = 0; i < n; ++i) finish<1>(x, 1, 0, i);
  }

  /// Coordinate i's step of Lᵀ y = x for C columns of x, entry (j, c) at x[j rs + c cs] (the
  /// coordinates below i done): y_i = x_i / L_ii, taken off its ancestors.
  template <int C>
  void eliminate(double* x, Eigen::Index rs, Eigen::Index cs, int i) const {
    const double s = inv_diag_[i];
    double y[C];
    for (int c = 0; c < C; ++c) y[c] = x[i * rs + c * cs] *= s;
    const double* r = row_.data() + offset_[i];
    const int* path = path_.data() + offset_[i];
    for (int p = 0, m = offset_[i + 1] - offset_[i]; p < m; ++p) {
      const double l = r[p];
      double* xj = x + path[p] * rs;
      for (int c = 0; c < C; ++c) xj[c * cs] -= l * y[c];
    }
  }
  /// Coordinate i's step of L z = y for C columns, laid out as in eliminate (its ancestors
  /// done): z_i.
  template <int C>
  void finish(double* x, Eigen::Index rs, Eigen::Index cs, int i) const {
    double z[C];
    for (int c = 0; c < C; ++c) z[c] = x[i * rs + c * cs];
    const double* r = row_.data() + offset_[i];
    const int* path = path_.data() + offset_[i];
    for (int p = 0, m = offset_[i + 1] - offset_[i]; p < m; ++p) {
      const double l = r[p];
      const double* xj = x + path[p] * rs;
      for (int c = 0; c < C; ++c) z[c] -= l * xj[c * cs];
    }
    const double s = inv_diag_[i];
    for (int c = 0; c < C; ++c) x[i * rs + c * cs] = z[c] * s;
  }

 private:
  std::vector<int> parent_;
  std::vector<int> offset_;  // row i's entries: [offset_[i], offset_[i + 1])
  std::vector<int> path_;    // per entry, its column (the ancestor), the paths concatenated
  std::vector<double> row_;  // per entry, L_ij
  std::vector<double> diag_, inv_diag_;
};

}  // namespace math
}  // namespace cga_rigid_sim
