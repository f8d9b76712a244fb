// JointRows: the unilateral and frictional joint forces of a tree step — position limits and
// Coulomb friction — as impulses y on the joint rates, solved by projected Gauss–Seidel over the
// few joints concerned (doc/articulated.md#limits-and-friction). Internal to the tree integrators.
//
// Given the step's linear system A⁻¹ ν̄ = r (A⁻¹ = M + ½hC, factored), ν̄ moves to ν̄ + A y with
//   limits:   q + h ν̄_k ≥ lower (y_k ≥ 0), q + h ν̄_k ≤ upper (y_k ≤ 0), complementary;
//   friction: |y_k| ≤ ½ h F_k, opposing ν̄_k, ν̄_k = 0 while |y_k| < ½ h F_k (sticking).
// Joints a limit or friction holds are "held": at the end of the step their rates are set to
// zero by a further impulse (stopHeld), so a stop is inelastic and a stuck joint does not
// jitter. Both impulses are projections in the metric of M: kinetic energy never grows.
// The rows act on the tree's independent coordinates (ArticulatedBody::coordinates(): each
// joint's own without mimic joints), in the space the step solves in (ν, or ν_r with mimic
// joints: llt and ν̄ are then reduced, and q stays the full vector of joint positions).
#pragma once

#include <Eigen/Cholesky>
#include <Eigen/Core>
#include <vector>

#include "cga_rigid_sim/tree/articulated_body.h"
#include "tree/tree_factor.h"
#include "tree/tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

/// Sets the rates ν_k, k in `held` (velocity indices), to zero with the impulse on those joints
/// that does it in the metric of M (llt: M's factor): ν ← ν + A E z, (Eᵀ A E) z = −Eᵀ ν, A = M⁻¹.
/// An impulse on joints only: it keeps a floating tree's momentum and never raises the kinetic
/// energy (a projection in the metric of M).
/// `scratch`: stopRates' working storage, kept by its caller so that a step does not allocate.
struct StopScratch {
  Eigen::MatrixXd AE, G;
  Eigen::VectorXd e, v, dnu;
};
/// (Factor: tree_math::Cholesky or TreeCholesky.)
template <class Factor>
void stopRates(const Factor& llt, const std::vector<int>& held, Eigen::VectorXd& nu,
               StopScratch& scratch);

class JointRows {
 public:
  /// The step's matrix changed: the columns A e_k kept from the solves since the last call are
  /// dropped, and so are the impulses the next solve would start from. Within a step (one llt,
  /// several solves: the midpoint's iterations) each column is made once, and each solve starts
  /// from the impulses of the one before.
  void newMatrix() { ++matrix_; }
  /// Adjusts ν̄ for the limits and friction of the joints at positions q (start of the step),
  /// with llt the matrix of the last newMatrix() call.
  void solve(const ArticulatedBody& tree, const tree_math::TreeCholesky& llt,
             const Eigen::VectorXd& q, double h, Eigen::VectorXd& nu_bar);
  /// Positions within the limits (removes the round-off of q + h ν̄ at a stop); mimic joints'
  /// positions set from their leaders'.
  void clampPositions(const ArticulatedBody& tree, Eigen::VectorXd& q) const;
  /// Sets the rates of held joints to zero with the impulse that does it in the metric of M
  /// (llt: M at the new pose). Returns whether anything was held.
  bool stopHeld(const ArticulatedBody& tree, const tree_math::TreeCholesky& llt,
                Eigen::VectorXd& nu) const;
  /// The impulses of the last solve as a vector over ν (zero where no row acts).
  void impulses(Eigen::VectorXd& y) const {
    y.setZero();
    for (const Row& r : rows_) y[r.index] += r.y;
  }
  /// Joints held in the last solve (velocity indices).
  const std::vector<int>& held() const { return held_; }
  /// Whether a limit (not friction) acted in the last solve.
  bool limitActed() const {
    for (const Row& r : rows_)
      if (r.kind != Kind::kFriction && r.y != 0.0) return true;
    return false;
  }

 private:
  enum class Kind { kLower, kUpper, kFriction };
  struct Row {
    int index;  // velocity index
    Kind kind;
    double target;  // limits: the rate that reaches the limit in h
    double bound;   // friction: ½ h F
    int key;        // 3 × its joint's position in watched_ + 0 friction, 1 lower, 2 upper
    double y = 0.0;
  };
  // Starts each row from its impulse in the last solve if that solve had the row and this
  // matrix. Returns whether any row starts from a nonzero impulse.
  bool warmStart();
  // Projected Gauss–Seidel on the rows' system (G_, w_) from their impulses y until no impulse
  // changes a rate by more than the tolerance (relative to `scale`). Returns the sweeps made.
  int sweep(double scale);
  // Where a coordinate has several rows, a split of their impulses that does not depend on
  // the sweeps' path (only the sum is unique when two rows pin the same rate).
  void canonicalSplit();
  // Joints with friction or limits (those without are never held), of the tree last solved
  // (an integrator, and its rows, belong to one tree). Unlimited bounds are ±∞: no row.
  struct Watched {
    int joint, index;
    double lower, upper, friction;
  };
  const ArticulatedBody* tree_ = nullptr;
  std::vector<Watched> watched_;
  std::vector<Row> rows_;
  std::vector<int> held_;
  // Per velocity index its column A e_k, valid while column_matrix_ is matrix_.
  std::vector<Eigen::VectorXd> columns_;
  std::vector<unsigned> column_matrix_;
  unsigned matrix_ = 1;
  // The sweeps run on the rows' own m × m system: G(r, s) = (A e_{index s})[index r] and the
  // rows' rates w (sized to the most rows yet: a step does not allocate).
  Eigen::MatrixXd G_;
  Eigen::VectorXd w_;
  // The rows of the last solve, and its matrix: the next solve's start (warmStart).
  std::vector<Row> last_rows_;
  unsigned last_matrix_ = 0;
  mutable StopScratch stop_;  // stopHeld's working storage
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
