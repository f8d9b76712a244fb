// A tree's contact problem solved in its own coordinates by Newton's method
// (doc/contacts.md#resting-trees): the velocity ν that minimises
//
//   ½ (ν − ν_f)ᵀ M (ν − ν_f) + ½ Σ_i D_i min(0, g_i ν − r_i)²
//
// — the step without the constraints' impulses, ν_f, moved as little as the mass matrix allows
// while every row i (a contact's normal or an edge of its friction pyramid, or a joint's stop)
// keeps g_i ν ≥ r_i, each held by a stiff penalty D_i. Its minimiser is the exact solution of
// the constraints with a compliance 1/D_i (a row's impulse is β_i = D_i max(0, r_i − g_i ν) and
// M (ν − ν_f) = Σ_i β_i g_iᵀ), so a row is kept to within β_i / D_i of its target. The cost is
// strictly convex in ν (M > 0) and piecewise quadratic: Newton steps with an exact line search
// reach its minimiser in a few steps, and exactly once the set of active rows is right. Unlike
// Gauss–Seidel over the impulses it does not slow down where the rows are many and dependent (a
// lying robot's contacts and stops share its ~30 coordinates): redundancy makes the impulses
// ambiguous, never ν. MuJoCo's Newton solver (Todorov 2014, "Convex and analytically-invertible
// dynamics with contacts and constraints") works on the same cost, there with soft rows.
//
// Storage: the workspace grows to the largest problem seen and is reused (in-place Cholesky, no
// temporaries), so a solve allocates only when the problem grows.
#pragma once

#include <Eigen/Dense>
#include <vector>

namespace cga_rigid_sim {
namespace sim {

struct TreeNewton {
  /// The rows, set by the caller with resize() then the fields below: g (m × nv, row i the
  /// row's Jacobian on ν), r, D. Rows on one coordinate alone (the joints' stops: g = ±e_k)
  /// are kept sparse in `single`.
  struct Single {
    int index = 0;    ///< the coordinate
    double sign = 1;  ///< +1: ν_k ≥ r; −1: −ν_k ≥ r
    double r = 0, D = 0;
    double beta = 0;  ///< its impulse, after solve()
  };
  Eigen::MatrixXd g;
  Eigen::VectorXd r, D, beta;  ///< beta: the rows' impulses after solve()
  std::vector<Single> single;
  int rows = 0, nv = 0, n_single = 0;

  /// Sizes the workspace for m dense and s single rows on nv coordinates (growing only).
  void resize(int m, int s, int nv);
  /// Solves the rows with the augmented Lagrangian method (Hestenes, Powell): round after
  /// round minimises the cost with each row's target shifted by its impulse so far,
  /// r_i + β_i / D_i, and takes β_i = max(0, β_i + D_i (r_i − g_i ν)) as its new impulse;
  /// the impulses converge to those of the rigid rows (D → ∞) with a moderate D, which keeps
  /// the Newton steps well conditioned. β (and Single::beta) hold the warm start on entry (the
  /// last step's impulses: a resting tree's first round is then its last) and the impulses on
  /// return, ν the start and the solution. Stops when a round moves no row's velocity by more
  /// than `tolerance` off its target, or when the rounds stop converging; returns the Newton
  /// steps taken, or −1 when a Hessian was not positive definite or a round took max_steps
  /// without reaching its minimiser (ν is then left part way: the caller restores it).
  int solve(const Eigen::MatrixXd& M, const Eigen::VectorXd& nu_f, Eigen::VectorXd& nu,
            double tolerance, int max_steps, int max_rounds);

  /// Rows entering or leaving the active set between two Newton steps of a solve are added to
  /// or removed from the Hessian's factor one by one (rank-one updates and downdates) while
  /// they are at most this many; more, and the Hessian is rebuilt and factored whole. 0: always
  /// whole (the same minimiser to round-off; a test compares the two).
  int max_rank_updates = 8;
  /// Counts since construction: Hessians factored whole, rows updated into or out of a factor.
  long factorisations = 0, rank_updates = 0;

 private:
  // Row-major: the factorisation, its updates and solves all walk a row of L (a coordinate's
  // entries left of the diagonal).
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> H_;
  Eigen::MatrixXd S_;
  Eigen::VectorXd dg_;  // factorActive: a row's D_i g_i on its nonzeros
  Eigen::VectorXd grad_, delta_, z_, gd_, re_, work_, dnu_, start_;
  Eigen::VectorXd mdnu_;  // M (ν − ν_f) at the Newton step's ν
  // One round: Newton steps on the cost with the targets re_ until a step moves no row's
  // velocity by more than `tolerance` (or max_steps); the steps taken, −1 on failure. With
  // from_impulses it starts with predict().
  int minimise(const Eigen::MatrixXd& M, const Eigen::VectorXd& nu_f, Eigen::VectorXd& nu,
               double tolerance, int max_steps, bool from_impulses);
  // H_ = M + Σ D_i g_iᵀ g_i over the rows active_ marks, factored; false when not positive
  // definite.
  bool factorActive(const Eigen::MatrixXd& M);
  // The factor of H_ ± D_i g_iᵀ g_i from H_'s, for each row i listed in changed_ (+ where it
  // became active, − where it left); false when a downdate would cancel a pivot to below
  // kMinPivotRatio of its square (the factor is then spoilt: the caller factors whole).
  bool updateFactor();
  // H_ ± x_ x_ᵀ on the factor, x_ nonzero at coordinates ≤ top (and zero again on return).
  bool rankOne(int top, double sign);
  // z_ = the rows' residuals g_i ν − re_i.
  void residuals(const Eigen::VectorXd& nu);
  // grad_ += Σ over the active rows D_i z_i g_iᵀ (the dense rows as one product Gᵀ w).
  void addRowsGradient();
  Eigen::VectorXd weighted_;  // w_i = D_i z_i on the active dense rows, else 0
  // The cost at ν with the targets re_ (z_ left at ν, M (ν − ν_f) in work_).
  double cost(const Eigen::MatrixXd& M, const Eigen::VectorXd& nu_f, const Eigen::VectorXd& nu);
  // A start from the impulses: ν moved to the minimiser of the quadratic the rows with β_i > 0
  // make, all taken active whatever their residual at ν (a resting tree's rows stay those of
  // the last step, whose residuals the new step's small changes put on either side of their
  // kinks, each of which would cost a Newton step), when that lowers the cost. Returns 1 (a
  // factorisation made), 0 (no impulse: nothing done), −1 (H not positive definite).
  int predict(const Eigen::MatrixXd& M, const Eigen::VectorXd& nu_f, Eigen::VectorXd& nu);
  // H_ = Lᵀ L in place (L in H_'s lower triangle), eliminating from the last coordinate in and
  // skipping L's zeros: M is zero but where one coordinate is an ancestor of the other (the
  // children come after their parents), so taking the leaves first makes no fill-in, and a
  // contact row adds only its own path's (or, between two links, its two paths') (Featherstone,
  // Rigid Body Dynamics Algorithms, §6.5). False when H_ is not positive definite.
  bool factorHessian();
  // x ← H⁻¹ x with that factor.
  void solveHessian(Eigen::VectorXd& x) const;
  Eigen::VectorXd inv_diag_;        // 1 / L_kk
  std::vector<int> nz_, nz_count_;  // per row k of L: the columns j < k it holds, from k nv on
  // Per row of g its nonzero columns (row i: row_nz_[row_nz_begin_[i]] up to
  // row_nz_[row_nz_begin_[i + 1]]), found once per solve (trees of at most kSparseMax coordinates).
  std::vector<int> row_nz_, row_nz_begin_;
  std::vector<char> active_;  // the rows active in H_'s factor
  std::vector<int> changed_;  // the rows whose activity changed at this Newton step
  Eigen::VectorXd x_;         // rankOne's vector, zero between calls
  bool factored_ = false;     // H_'s lower triangle holds the factor for active_
  // φ'(α) of the line search along delta_ (z_, gd_ the rows' residuals and rates along it)
  // and φ'' there. splitRows() sums once the rows that stay on one side of their kink for
  // every α ≥ 0 (most: the stops far from their limits, the loaded edges pressed further) and
  // lists the others, the only ones slope() then visits.
  void splitRows(double dMd, double dMx);
  double slope(double alpha, double* curvature) const;
  std::vector<int> crossing_;
  double fixed_slope_ = 0, fixed_curvature_ = 0;
};

}  // namespace sim
}  // namespace cga_rigid_sim
