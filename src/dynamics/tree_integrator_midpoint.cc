// The variational midpoint for trees (`cga2`, `auto`) and its triple-jump composition (`cga4`)
// (tree_integrator.h, doc/articulated.md#integrators).
//
// One step of h from (M_W0, q, p, Π) — p the joint momenta, Π the tree's momentum in world
// axes (floating base only):
//   unknown ν̄ (the midpoint velocity); q̄ = q + ½h q̄̇, M̄ = M_W0 exp(−¼ h Ω̄_0);
//   (M(q̄) + ½h C) ν̄ = (M̄⁻¹ Π̄, p + ½h (∂L/∂q + Q + τ)(q̄, ν̄)) + y,  Π̄ = Π + ½h W(q̄),
//   solved by fixed-point iteration on ν̄; y are the limit and friction impulses (joint_rows.h);
//   then q ← q + h q̄̇, M_W0 ← M_W0 exp(−½ h Ω̄_0), p ← 2 M(q̄) ν̄|_q − p, Π ← Π + h W,
//   and ν at the new pose from M(q) ν = (M_W0⁻¹ Π, p).
// For a fixed base this is the implicit midpoint rule on the canonical (q, p): symplectic. W is
// the external wrench about the world origin (gravity, applied loads): Π changes by it alone.
#include <Eigen/Cholesky>
#include <cmath>

#include "cga_rigid_sim/dynamics/tree_integrator.h"
#include "joint_rows.h"
#include "tree_integrators.h"
#include "tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

namespace {

// Iterations stop when ν̄ changes by less than this (relative to 1 + |ν̄|∞), or stops
// shrinking: the round-off floor of the solve is a few ulps of |ν̄|.
constexpr double kTolerance = 4e-15;
constexpr int kMaxIterations = 40;

class Midpoint final : public TreeIntegrator {
 public:
  explicit Midpoint(bool fourth_order) : fourth_order_(fourth_order) {}
  const char* name() const override { return fourth_order_ ? "cga4" : "cga2"; }
  void reset() override { cached_ = false; }
  int lastIterations() const override { return iterations_; }

  void step(const ArticulatedBody& tree, const TreeLoads& loads, double h,
            TreeState& state) override {
    iterations_ = 0;
    if (!fourth_order_) return substep(tree, loads, h, state);
    // Yoshida: h γ1, h γ2, h γ1 with γ1 = 1/(2 − 2^{1/3}), γ2 = 1 − 2 γ1.
    const double g1 = 1.0 / (2.0 - std::cbrt(2.0)), g2 = 1.0 - 2.0 * g1;
    substep(tree, loads, g1 * h, state);
    substep(tree, loads, g2 * h, state);
    substep(tree, loads, g1 * h, state);
  }

 private:
  bool sameAsCached(const TreeState& s) const {
    if (!cached_) return false;
    const auto a = s.M_W0.coefficients(), b = last_.M_W0.coefficients();
    return a == b && s.q == last_.q && s.v == last_.v && s.omega_0.rot == last_.omega_0.rot &&
           s.omega_0.trans == last_.omega_0.trans;
  }

  void substep(const ArticulatedBody& tree, const TreeLoads& loads, double h, TreeState& state) {
    const int n = tree.jointCount(), nv = tree.velocityCount();
    const double lambda = tree.lambda();
    const bool fresh = sameAsCached(state);
    if (!fresh) {  // momenta of a state set from outside
      treeKinematics(tree, state, kin_);
      const Eigen::VectorXd pm =
          momentumAndGradient(tree, kin_, BodyMoments(tree.bodyCount()), nullptr);
      p_ = pm.tail(n);
      if (tree.floating()) Pi_ = state.M_W0.apply(tree_math::moment(pm.head<6>()), lambda);
    }
    const Eigen::VectorXd nu0 = velocityVector(tree, state);
    // Start from the extrapolated midpoint velocity when the last step had the same h.
    Eigen::VectorXd nu_bar = (fresh && h == last_h_) ? guess_ : nu0;
    TreeState mid = state;
    Eigen::VectorXd grad, rhs(nv), nu_new;
    cga::Moment W;
    double last_change = INFINITY;
    for (int it = 0; it < kMaxIterations; ++it) {
      ++iterations_;
      mid.q = state.q + (0.5 * h) * nu_bar.tail(n);
      setVelocityVector(tree, nu_bar, mid);
      if (tree.floating())
        mid.M_W0 = state.M_W0 * cga::exp(tree_math::bivector(nu_bar.head<6>()) * (-0.25 * h));
      treeKinematics(tree, mid, kin_);
      externalMoments(tree, kin_, loads, f_ext_);
      momentumAndGradient(tree, kin_, f_ext_, &grad);
      massMatrix(tree, kin_, M_);
      rhs.tail(n) = p_ + (0.5 * h) * (grad + loads.effort);
      if (tree.floating()) {
        W = cga::Moment();
        for (int b = 0; b < tree.bodyCount(); ++b) W += kin_.M_W[b].apply(f_ext_[b], lambda);
        rhs.head<6>() = tree_math::vec(mid.M_W0.reverse().apply(Pi_ + W * (0.5 * h), lambda));
      }
      for (int k = 0; k < n; ++k)
        M_(tree.velocityIndex(k), tree.velocityIndex(k)) += 0.5 * h * tree.joints()[k].damping;
      llt_.compute(M_);
      nu_new = llt_.solve(rhs);
      rows_.solve(tree, llt_, state.q, h, nu_new);
      for (int k = 0; k < n; ++k)  // M(q̄) alone below, without the damping term
        M_(tree.velocityIndex(k), tree.velocityIndex(k)) -= 0.5 * h * tree.joints()[k].damping;
      const double change = (nu_new - nu_bar).cwiseAbs().maxCoeff();
      const double scale = 1.0 + nu_new.cwiseAbs().maxCoeff();
      nu_bar = nu_new;
      if (nv == 0 || change <= kTolerance * scale || (it > 2 && change >= last_change)) break;
      last_change = change;
    }
    // Positions and momenta at the end of the step.
    const Eigen::VectorXd p_bar = (M_ * nu_bar).tail(n);
    p_ = 2.0 * p_bar - p_;
    state.q += h * nu_bar.tail(n);
    rows_.clampPositions(tree, state.q);
    if (tree.floating()) {
      Pi_ += W * h;
      state.M_W0 =
          (state.M_W0 * cga::exp(tree_math::bivector(nu_bar.head<6>()) * (-0.5 * h))).normalized();
    }
    // Velocities at the new pose: M(q) ν = (M_W0⁻¹ Π, p).
    treeKinematics(tree, state, kin_);
    massMatrix(tree, kin_, M_);
    llt_.compute(M_);
    Eigen::VectorXd rhs_end(nv);
    rhs_end.tail(n) = p_;
    if (tree.floating())
      rhs_end.head<6>() = tree_math::vec(state.M_W0.reverse().apply(Pi_, lambda));
    Eigen::VectorXd nu_end = llt_.solve(rhs_end);
    // Joints held by a limit or by friction end the step at rest (inelastic, doc/articulated.md).
    if (rows_.stopHeld(tree, llt_, nu_end)) p_ = (M_ * nu_end).tail(n);
    guess_ = 2.0 * nu_end - nu_bar;  // ν(t + 3h/2) ≈ ν(t + h) + (ν(t + h) − ν(t + h/2))
    setVelocityVector(tree, nu_end, state);
    last_ = state;
    last_h_ = h;
    cached_ = true;
  }

  bool fourth_order_;
  bool cached_ = false;
  TreeState last_;
  double last_h_ = 0.0;
  int iterations_ = 0;
  Eigen::VectorXd p_, guess_;
  cga::Moment Pi_;
  TreeKinematics kin_;
  BodyMoments f_ext_;
  Eigen::MatrixXd M_;
  Eigen::LLT<Eigen::MatrixXd> llt_;
  JointRows rows_;
};

}  // namespace

std::unique_ptr<TreeIntegrator> makeMidpointTreeIntegrator(bool fourth_order) {
  return std::make_unique<Midpoint>(fourth_order);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
