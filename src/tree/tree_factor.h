// TreeCholesky: the factor of a tree's mass matrix (or of M + ½hC, which has its sparsity) that
// the variational midpoint iterates and solves with (tree_integrator_midpoint.cc), and its joint
// rows (joint_rows.h). Internal to the tree layer.
//
// M(q) from the composite-rigid-body algorithm is zero except where one coordinate is an
// ancestor of the other (or the same). Featherstone's LTL factorisation M = Lᵀ L
// (math::LtlFactor) keeps that sparsity: factoring costs Σ_i d_i² and a solve 2 Σ_i d_i (d_i:
// the ancestors of coordinate i) instead of n³/6 and n² (a floating base's six coordinates are
// a chain, so its dense 6 × 6 block is factored as one). The contact solve's TreeFactor
// (contact_tree_factor.h) is the same factorisation for its own products. Without
// parents (mimic joints: the reduced matrix couples a leader's branch with its follower's) the
// matrix is factored densely (math::Cholesky).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "cga_rigid_sim/math/cholesky.h"
#include "cga_rigid_sim/math/ltl_factor.h"
#include "cga_rigid_sim/tree/articulated_body.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace tree_math {

class TreeCholesky {
 public:
  /// Per coordinate its parent coordinate (smaller than its own index) or −1; empty: dense.
  /// The matrices factored must be zero off the pairs of a coordinate and its ancestors.
  void setParents(const std::vector<int>& parent) { ltl_.setParents(parent); }
  bool sparse() const { return ltl_.size() > 0; }

  /// Factors A (its lower triangle is read). Not positive definite in double precision: the
  /// factor, and every solve with it, holds NaN (the callers' finiteness checks catch it).
  void compute(const Eigen::MatrixXd& A) {
    if (!sparse() || ltl_.size() != A.rows()) return dense_.compute(A);
    ltl_.compute(A, false);
  }

  /// x ← A⁻¹ x.
  void solveInPlace(Eigen::VectorXd& x) const {
    if (!sparse() || ltl_.size() != x.size()) return dense_.solveInPlace(x);
    ltl_.solveInPlace(x.data());
  }
  /// x ← A⁻¹ e_k (x of A's size): the same as solveInPlace of e_k, with the first half of the
  /// sparse solve along k's path alone.
  void solveUnit(int k, Eigen::VectorXd& x) const {
    if (!sparse()) {
      x.setZero();
      x[k] = 1.0;
      return dense_.solveInPlace(x);
    }
    ltl_.solveUnit(k, x.data());
  }

 private:
  math::LtlFactor ltl_;  // sparse (math/ltl_factor.h)
  math::Cholesky dense_;
};

/// The coordinate parents of `tree`'s ν for TreeCholesky::setParents: a floating base's six as a
/// chain, each joint's rate the child of its parent joint's (of the base's last, or none). With
/// mimic joints none (dense): the matrices on ν_r couple a leader's branch with its follower's.
inline std::vector<int> coordinateParents(const ArticulatedBody& tree) {
  std::vector<int> parent;
  if (tree.hasMimic()) return parent;
  const int off = tree.floating() ? 6 : 0;
  for (int i = 0; i < off; ++i) parent.push_back(i - 1);
  for (const TreeJoint& j : tree.joints())
    parent.push_back(j.parent == 0 ? off - 1 : tree.velocityIndex(j.parent - 1));
  return parent;
}

}  // namespace tree_math
}  // namespace dynamics
}  // namespace cga_rigid_sim
