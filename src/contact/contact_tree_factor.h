// The factor of an articulated tree's mass matrix M(q) that the contact solve works with
// (doc/contacts.md#trees): its responses M⁻¹ Jᵀ to the contacts' impulses, the Delassus blocks
// J M⁻¹ Jᵀ and the joint stops' columns M⁻¹ e_k.
//
// M(q) from the composite-rigid-body algorithm is zero except where one coordinate is an
// ancestor of the other (or the same): the branches of a tree do not couple. Featherstone's LTL
// factorisation M = Lᵀ L (math::LtlFactor; Rigid Body Dynamics Algorithms, 2008, §6.5) keeps that
// sparsity: L_ij is nonzero only for j = i or j an ancestor of i, so factoring costs Σ_i d_i² and
// a solve 2 Σ_i d_i (d_i: the number of ancestors of coordinate i) instead of n³/6 and n². And L⁻ᵀ
// leaves a vector on the coordinates between one link and the base on those coordinates: with
// Y = L⁻ᵀ Jᵀ a contact's block J M⁻¹ Jᵀ = Yᵀ Y costs O(d²) for a point whose link is d
// coordinates from the base, however large the rest of the tree; its response M⁻¹ Jᵀ = L⁻¹ Y
// (all coordinates) is made only where an impulse is applied through it (the Gauss–Seidel
// sweeps, not the resting tree's Newton solve). A floating base's six coordinates are a chain
// (each the parent of the next), so its dense 6 × 6 block is factored as one.
//
// Where the solver's coordinates are not the joints' (mimic joints: M_r = Gᵀ M G couples a
// leader's branch with its follower's), M is factored densely (Eigen's LLT, M = L Lᵀ, and
// Y = L⁻¹ Jᵀ): the same interface and the same products.
#pragma once

#include <Eigen/Dense>
#include <vector>

#include "cga_rigid_sim/math/ltl_factor.h"

namespace cga_rigid_sim {
namespace sim {

class TreeFactor {
 public:
  using Columns = Eigen::Matrix<double, Eigen::Dynamic, 3>;

  /// Factors M (its lower triangle is read). `parent`: per coordinate its parent coordinate,
  /// smaller than its own index, or −1; M must be zero off the pairs of a coordinate and its
  /// ancestors. Empty: M is factored densely. False when M is not positive definite in double
  /// precision (or not finite).
  bool compute(const Eigen::MatrixXd& M, const std::vector<int>& parent);
  bool ok() const { return ok_; }
  bool sparse() const { return sparse_; }

  /// x ← M⁻¹ x.
  void solveInPlace(Eigen::VectorXd& x) const;
  void solveInPlace(Columns& x) const;
  /// The first half of a solve, Y ← L⁻ᵀ Y (sparse) or L⁻¹ Y (dense), for Y = Jᵀ zero off the
  /// coordinates from `leaf_a` and `leaf_b` to the root (−1: no such path); Yᵀ Y is then
  /// J M⁻¹ Jᵀ. Sparse, Y stays zero off those coordinates and the rest is not touched.
  void halfSolve(Columns& Y, int leaf_a, int leaf_b) const;
  /// The second half, after halfSolve: Y ← M⁻¹ Jᵀ.
  void finishSolve(Columns& Y) const;
  /// The second half for one column: z ← L⁻¹ z (sparse) or L⁻ᵀ z (dense).
  void finishSolve(Eigen::VectorXd& z) const;

 private:
  // Coordinate i's step of Lᵀ y = Y (its descendants' done): y_i, taken off its ancestors.
  void eliminate(Columns& Y, int i) const;

  math::LtlFactor ltl_;  // sparse (math/ltl_factor.h)
  Eigen::LLT<Eigen::MatrixXd> dense_;
  bool sparse_ = false, ok_ = false;
};

}  // namespace sim
}  // namespace cga_rigid_sim
