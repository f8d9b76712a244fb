// Featherstone's LTL factorisation of a tree's mass matrix, and its dense stand-in
// (contact_tree_factor.h).
#include "contact/contact_tree_factor.h"

#include <cmath>

namespace cga_rigid_sim {
namespace sim {

bool TreeFactor::compute(const Eigen::MatrixXd& M, const std::vector<int>& parent) {
  sparse_ = !parent.empty();
  if (!sparse_) {
    dense_.compute(M);
    ok_ = dense_.info() == Eigen::Success && dense_.matrixLLT().allFinite();
    return ok_;
  }
  parent_ = parent;
  const int n = static_cast<int>(M.rows());
  L_ = M;
  inv_diag_.resize(n);
  ok_ = false;
  // From the leaves in: coordinate k's row of L, then its outer product taken off its
  // ancestors' block (only ancestor pairs: that is all the fill-in there is).
  for (int k = n - 1; k >= 0; --k) {
    const double d = L_(k, k);
    if (!(d > 0.0 && std::isfinite(d))) return false;
    const double l = std::sqrt(d), inv = 1.0 / l;
    L_(k, k) = l;
    inv_diag_[k] = inv;
    for (int i = parent_[k]; i >= 0; i = parent_[i]) L_(k, i) *= inv;
    for (int i = parent_[k]; i >= 0; i = parent_[i]) {
      const double a = L_(k, i);
      for (int j = i; j >= 0; j = parent_[j]) L_(i, j) -= a * L_(k, j);
    }
  }
  ok_ = true;
  return true;
}

void TreeFactor::solveInPlace(Eigen::VectorXd& x) const {
  if (!sparse_) return dense_.solveInPlace(x);
  const int n = static_cast<int>(x.size());
  for (int i = n - 1; i >= 0; --i) {  // Lᵀ y = x, from the leaves in
    const double y = x[i] * inv_diag_[i];
    x[i] = y;
    for (int j = parent_[i]; j >= 0; j = parent_[j]) x[j] -= L_(i, j) * y;
  }
  for (int i = 0; i < n; ++i) {  // L z = y, from the root out
    double z = x[i];
    for (int j = parent_[i]; j >= 0; j = parent_[j]) z -= L_(i, j) * x[j];
    x[i] = z * inv_diag_[i];
  }
}

void TreeFactor::solveInPlace(Columns& x) const {
  if (!sparse_) return dense_.solveInPlace(x);
  for (int i = static_cast<int>(x.rows()) - 1; i >= 0; --i) eliminate(x, i);  // Lᵀ y = x
  finishSolve(x);
}

void TreeFactor::halfSolve(Columns& Y, int leaf_a, int leaf_b) const {
  if (!sparse_) {
    dense_.matrixL().solveInPlace(Y);
    return;
  }
  // Lᵀ y = Y over the union of the two paths, from the leaves in (decreasing index: a parent's
  // index is smaller than its child's), each coordinate once; the others stay zero.
  int a = leaf_a, b = leaf_b;
  while (a >= 0 || b >= 0) {
    const int i = a > b ? a : b;
    eliminate(Y, i);
    if (a == i) a = parent_[a];
    if (b == i) b = parent_[b];
  }
}

void TreeFactor::eliminate(Columns& Y, int i) const {
  const double s = inv_diag_[i];
  const double y0 = Y(i, 0) * s, y1 = Y(i, 1) * s, y2 = Y(i, 2) * s;
  Y(i, 0) = y0;
  Y(i, 1) = y1;
  Y(i, 2) = y2;
  for (int j = parent_[i]; j >= 0; j = parent_[j]) {
    const double l = L_(i, j);
    Y(j, 0) -= l * y0;
    Y(j, 1) -= l * y1;
    Y(j, 2) -= l * y2;
  }
}

void TreeFactor::finishSolve(Columns& Y) const {
  if (!sparse_) {
    dense_.matrixU().solveInPlace(Y);
    return;
  }
  const int n = static_cast<int>(Y.rows());
  for (int i = 0; i < n; ++i) {
    double z0 = Y(i, 0), z1 = Y(i, 1), z2 = Y(i, 2);
    for (int j = parent_[i]; j >= 0; j = parent_[j]) {
      const double l = L_(i, j);
      z0 -= l * Y(j, 0);
      z1 -= l * Y(j, 1);
      z2 -= l * Y(j, 2);
    }
    const double s = inv_diag_[i];
    Y(i, 0) = z0 * s;
    Y(i, 1) = z1 * s;
    Y(i, 2) = z2 * s;
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
