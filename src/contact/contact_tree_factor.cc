// Featherstone's LTL factorisation of a tree's mass matrix, and its dense stand-in
// (contact_tree_factor.h).
#include "contact/contact_tree_factor.h"

namespace cga_rigid_sim {
namespace sim {

bool TreeFactor::compute(const Eigen::MatrixXd& M, const std::vector<int>& parent) {
  sparse_ = !parent.empty();
  if (!sparse_) {
    dense_.compute(M);
    ok_ = dense_.info() == Eigen::Success && dense_.matrixLLT().allFinite();
    return ok_;
  }
  ltl_.setParents(parent);  // (the paths are rebuilt only for other parents than the last)
  ok_ = ltl_.compute(M, true);
  return ok_;
}

void TreeFactor::solveInPlace(Eigen::VectorXd& x) const {
  if (!sparse_) return dense_.solveInPlace(x);
  ltl_.solveInPlace(x.data());
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
  const std::vector<int>& parent = ltl_.parents();
  int a = leaf_a, b = leaf_b;
  while (a >= 0 || b >= 0) {
    const int i = a > b ? a : b;
    eliminate(Y, i);
    if (a == i) a = parent[a];
    if (b == i) b = parent[b];
  }
}

void TreeFactor::eliminate(Columns& Y, int i) const { ltl_.eliminate<3>(Y.data(), 1, Y.rows(), i); }

void TreeFactor::finishSolve(Columns& Y) const {
  if (!sparse_) {
    dense_.matrixU().solveInPlace(Y);
    return;
  }
  const int n = static_cast<int>(Y.rows());
  for (int i = 0; i < n; ++i) ltl_.finish<3>(Y.data(), 1, Y.rows(), i);
}

void TreeFactor::finishSolve(Eigen::VectorXd& z) const {
  if (!sparse_) {
    dense_.matrixU().solveInPlace(z);
    return;
  }
  const int n = static_cast<int>(z.size());
  for (int i = 0; i < n; ++i) ltl_.finish<1>(z.data(), 1, 0, i);
}

}  // namespace sim
}  // namespace cga_rigid_sim
