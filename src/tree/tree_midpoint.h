// The variational midpoint for trees (`cga2`, `auto`) and its triple-jump composition (`cga4`):
// the integrator's class, its state between steps and its scratch. Internal: included by
// tree_integrator_midpoint.cc (the scheme, the step and its halving) and tree_midpoint_guess.h
// (the iteration's starting guess), which make one translation unit, so that the step's parts
// stay local and inline into one another as one file's would (its members defined out of the
// class are marked inline, as those defined in it are).
#pragma once

#include <Eigen/Core>
#include <cmath>
#include <vector>

#include "cga_rigid_sim/tree/tree_integrator.h"
#include "tree/joint_rows.h"
#include "tree/tree_factor.h"
#include "tree/tree_integrator_residual.h"
#include "tree/tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

class Midpoint final : public TreeIntegrator {
 public:
  explicit Midpoint(bool fourth_order) : fourth_order_(fourth_order) {}
  const char* name() const override { return fourth_order_ ? "cga4" : "cga2"; }
  void reset() override {
    cached_ = false;
    start_at_last_ = false;
    kin_at_state_ = false;
    start_hint_ = false;
  }
  void startFrom(const TreeState& state, const TreeKinematics& kin,
                 const Eigen::MatrixXd* M) override {
    reset();
    hint_state_ = state;  // (copies into storage of the same size: no allocation)
    kin_ = kin;
    if (M) M_ = *M;
    start_hint_ = true;
    hint_mass_ = M != nullptr;
  }
  int lastIterations() const override { return iterations_; }
  double lastDissipated() const override { return dissipated_; }
  bool lastLimited() const override { return limited_; }
  bool lastSolved() const override { return solved_; }
  bool conservesMomentum() const override { return true; }
  const TreeKinematics* lastKinematics() const override { return kin_at_state_ ? &kin_ : nullptr; }
  // A floating base's end poses come from treePoses, a fixed base's from the residual's
  // formulas (substep).
  const TreeKinematics* lastExactKinematics() const override {
    return kin_at_state_ && kin_exact_ ? &kin_ : nullptr;
  }
  // factorMass() at the end pose of an accepted step with a floating base: massMatrix on kin_.
  const Eigen::MatrixXd* lastMass() const override {
    return kin_at_state_ && kin_exact_ && mass_at_last_ ? &M_ : nullptr;
  }
  const Eigen::VectorXd* lastEffort() const override { return servoed_ ? &effort_ : nullptr; }

  void step(const ArticulatedBody& tree, const TreeLoads& loads, double h,
            TreeState& state) override;
  int lastHalvings() const { return halvings_; }

 private:
  bool sameAsCached(const TreeState& s) const { return cached_ && identical(s, last_); }
  // Whether the step starts from the state startFrom() was given (its kinematics in kin_).
  bool startsAtHint(const TreeState& s) const { return start_hint_ && identical(s, hint_state_); }
  // No NaN or infinity (a loop: Eigen's allFinite compares x − x with itself through a call).
  static bool finite(const Eigen::VectorXd& x) {
    for (Eigen::Index i = 0; i < x.size(); ++i)
      if (!std::isfinite(x[i])) return false;
    return true;
  }

  // M at the pose of `kin_` or at a fixed base's end pose, factored.
  void factorMass(const ArticulatedBody& tree, bool at_end_pose = false, bool factor = true);
  // Whether a joint of the tree is damped (kept per tree: an integrator belongs to one tree).
  bool damped(const ArticulatedBody& tree) {
    if (&tree != damped_tree_) {
      damped_tree_ = &tree;
      damped_ = false;
      for (const TreeJoint& j : tree.joints()) damped_ = damped_ || j.damping != 0.0;
    }
    return damped_;
  }
  // The factors' coordinate parents (tree_factor.h), set once per tree.
  void factorParents(const ArticulatedBody& tree) {
    if (&tree == factor_tree_) return;
    factor_tree_ = &tree;
    const std::vector<int> parent = tree_math::coordinateParents(tree);
    llt_.setParents(parent);
    llt_damped_.setParents(parent);
  }
  // M + ½hC (+ ½h Kd + ¼h² Kp with servos), the iteration's matrix, factored.
  const tree_math::TreeCholesky& iterationMatrix(const ArticulatedBody& tree,
                                                 const TreeLoads& loads, double h);
  // The effort the joints take at the midpoint (q + ½h ν̄, ν̄): the loads' own, or with servos
  // effort plus servo, clamped, into effort_.
  const Eigen::VectorXd& midpointEffort(const ArticulatedBody& tree, const TreeLoads& loads,
                                        const Eigen::VectorXd& q, double h,
                                        const Eigen::VectorXd& nu_all);

  // A substep of h, halved while the iteration cannot solve it.
  void robustSubstep(const ArticulatedBody& tree, const TreeLoads& loads, double h,
                     TreeState& state, int depth);
  struct Saved {
    TreeState state;  // (last_, cached_ and last_h_ change only when a substep succeeds)
    double T;
    Eigen::VectorXd p;
    cga::Moment Pi;
  };
  void save(const TreeState& s, Saved& v) const;
  void restore(const Saved& v, TreeState& s);

  // One midpoint step; false when the iteration did not converge.
  bool substep(const ArticulatedBody& tree, const TreeLoads& loads, double h, TreeState& state);

  // The next step's starting ν̄, guess_ (tree_midpoint_guess.h).
  void predictNext(int nv);
  template <int M>
  void updateDifferences(int nv, double* err, int m = M);

  const BodyMoments& zero_moments(const ArticulatedBody& tree) {
    zeros_.assign(tree.bodyCount(), cga::Moment());
    return zeros_;
  }

  bool fourth_order_;
  bool cached_ = false;
  TreeState last_;
  double last_h_ = 0.0;
  int iterations_ = 0;
  double dissipated_ = 0.0;  ///< what the joints took in the step (lastDissipated)
  bool solved_ = true;       ///< every substep of the step converged (lastSolved)
  bool limited_ = false;     ///< a limit acted in the step (lastLimited)
  int halvings_ = 0;
  int attempts_ = 0;  ///< substep attempts in this step (kMaxAttemptsPerStep)
  std::vector<Saved> saved_;
  bool slots_sized_ = false;
  double T_ = 0.0;  // kinetic energy of the state the integrator produced
  const ArticulatedBody* damped_tree_ = nullptr;
  bool damped_ = false;
  bool mass_at_last_ = false;   // M_ and llt_ are M at the pose of last_
  bool start_at_last_ = false;  // residual_ holds the sines and cosines of last_'s ½q
  bool kin_at_state_ = false;   // kin_ is the kinematics of the state the last substep produced
  bool kin_exact_ = false;      // and made by treePoses and treeVelocities
  // startFrom(): kin_ (and with hint_mass_ M_) belong to hint_state_, until a substep starts
  TreeState hint_state_;
  bool start_hint_ = false, hint_mass_ = false;
  // A contact step's drift (a step from a hint): its ν at the start (with the hint's M, also
  // the factor of its momenta M ν), and ν̄ − ν of the last such step of h that converged (kept
  // through reset(): a starting guess only).
  Eigen::VectorXd drift_start_, drift_offset_;
  double drift_h_ = 0.0;
  bool drift_offset_valid_ = false;
  static constexpr int kMaxDegree = 7;
  static constexpr int kDifferences = kMaxDegree + 2;  // ∇^{d+1} to judge degree d
  // ∇^j ν̄ at the last step, j < history_filled_ (coordinate-major: kDifferences per coordinate)
  std::vector<double> differences_;
  int history_filled_ = 0;  // values of ν̄ in the current run of equal steps, ≤ kDifferences
  // The ratio of the iteration's last two corrections measured above round-off in the current
  // run of equal steps (0: none yet).
  double contraction_ = 0.0;
  Eigen::VectorXd Mnu_, p_, guess_, pm_, grad_, r_, y_, nu_bar_, nu_new_, nu_end_, rhs_;
  // Mimic joints: ν̄ and ν on every joint, the joints' residual or force before Gᵀ, and the
  // reduced M and M + ½hC (M_ and Md_ stay on every joint).
  Eigen::VectorXd nu_full_, joint_r_, grad_r_;
  Eigen::VectorXd effort_;  // with servos: the effort applied at the midpoint (lastEffort)
  bool servoed_ = false;    // servos acted in the last step
  Eigen::MatrixXd Mr_, Mdr_;
  cga::Moment Pi_;
  TreeState mid_;
  TreeKinematics kin_;
  TreeWorkspace work_;  // the tree algorithms' work arrays
  BodyMoments f_ext_, zeros_;
  Eigen::MatrixXd M_, Md_;  // M at the last pose factorMass() saw, and M + ½hC
  // Factored on the tree's sparsity (tree_factor.h).
  tree_math::TreeCholesky llt_, llt_damped_;
  const ArticulatedBody* factor_tree_ = nullptr;  // whose parents the factors have
  JointRows rows_;
  MidpointResidual residual_;
};

}  // namespace
}  // namespace dynamics
}  // namespace cga_rigid_sim
