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
// With mimic joints the same scheme runs on the independent coordinates (articulated_body.h):
// ν̄ = G ν̄_r, p and the residual are Gᵀ of the joints' (the momenta and forces conjugate to the
// independent positions), the matrix Gᵀ (M + ½hC) G; the followers' positions are set from their
// leaders' after each step. A fixed base stays symplectic: these are canonical coordinates of
// the constrained system.
//
// This file: the step (the iteration and the step's end) and its halving; the class and its
// state: tree_midpoint.h; the iteration's starting guess: tree_midpoint_guess.h.
#include <algorithm>
#include <cmath>

#include "tree/tree_integrators.h"
#include "tree/tree_midpoint.h"
#include "tree/tree_midpoint_guess.h"

namespace cga_rigid_sim {
namespace dynamics {

namespace {

// The iteration is a simplified Newton method: its matrix is M + ½hC at the step's start, its
// residual is evaluated at the midpoint with the O(n) momentum recursion.
// Iterations stop when ν̄ changes by less than this (relative to 1 + |ν̄|∞), or stops
// shrinking: the round-off floor of the solve is a few ulps of |ν̄|.
constexpr double kTolerance = 4e-15;
// A ratio of two corrections is measured when the second is above this (relative): ten times
// the tolerance, so that round-off (a few ulps) changes it by a few per cent at most. It is
// used with a factor of two to spare.
constexpr double kRatioFloor = 10 * kTolerance, kRatioMargin = 2.0;
constexpr int kMaxIterations = 40;
// A step whose last correction is above this (relative) did not converge: it is halved.
// Stagnation at round-off ends far below it (≈ 1e-13 for ill-conditioned chains).
constexpr double kConverged = 1e-9;
constexpr int kMaxHalvings = 10;
// At most this many substep attempts per step, halvings included: a state no step size can
// resolve (joints whipping at thousands of rad/s after an extreme impulse) costs a bounded
// ~kMaxAttemptsPerStep·kMaxIterations iterations per step instead of 2^(kMaxHalvings+1) attempts
// (the libFuzzer world-inputs target found such a stall, fuzz/findings/).
constexpr int kMaxAttemptsPerStep = 64;

inline void Midpoint::step(const ArticulatedBody& tree, const TreeLoads& loads, double h,
                           TreeState& state) {
  iterations_ = 0;
  attempts_ = 0;
  dissipated_ = 0.0;
  limited_ = false;
  solved_ = true;
  if (!fourth_order_) return robustSubstep(tree, loads, h, state, 0);
  // Yoshida: h γ1, h γ2, h γ1 with γ1 = 1/(2 − 2^{1/3}), γ2 = 1 − 2 γ1.
  const double g1 = 1.0 / (2.0 - std::cbrt(2.0)), g2 = 1.0 - 2.0 * g1;
  robustSubstep(tree, loads, g1 * h, state, 0);
  robustSubstep(tree, loads, g2 * h, state, 0);
  robustSubstep(tree, loads, g1 * h, state, 0);
}

// M at the pose of `kin_` (velocities from momenta, the metric of the stop impulses).
// `at_end_pose`: a fixed base's M from the frames of residual_.endPose(). `factor`: M factored
// too (not needed at a step's start when the iteration's matrix is M + ½hC).
inline void Midpoint::factorMass(const ArticulatedBody& tree, bool at_end_pose, bool factor) {
  if (at_end_pose)
    residual_.massMatrix(M_);
  else
    massMatrix(tree, kin_, M_, work_);
  if (!factor) return;
  if (!tree.hasMimic()) return llt_.compute(M_);
  reduceMatrix(tree, M_, Mr_, work_);  // mimic joints: the step solves on ν_r
  llt_.compute(Mr_);
}

// M + ½hC from the M of factorMass(): the matrix of the iteration and the metric of its joint
// rows; M's own factor when no joint is damped.
inline const tree_math::TreeCholesky& Midpoint::iterationMatrix(const ArticulatedBody& tree,
                                                                const TreeLoads& loads, double h) {
  const bool servos = loads.servos.active();
  if (!damped(tree) && !servos) return llt_;
  Md_ = M_;
  for (int k = 0; k < tree.jointCount(); ++k)
    Md_(tree.velocityIndex(k), tree.velocityIndex(k)) += 0.5 * h * tree.joints()[k].damping;
  // The servo's torque at the midpoint changes with ν̄ by −(½h kp + kd) per unit (q̄ = q + ½h ν̄):
  // times ½h in the residual, ¼h² kp + ½h kd on the diagonal (doc/articulated.md (S1)).
  if (servos)
    for (int k = 0; k < tree.jointCount(); ++k)
      Md_(tree.velocityIndex(k), tree.velocityIndex(k)) +=
          0.25 * h * h * loads.servos.kp[k] + 0.5 * h * loads.servos.kd[k];
  if (!tree.hasMimic()) {
    llt_damped_.compute(Md_);
  } else {
    reduceMatrix(tree, Md_, Mdr_, work_);
    llt_damped_.compute(Mdr_);
  }
  return llt_damped_;
}

inline const Eigen::VectorXd& Midpoint::midpointEffort(const ArticulatedBody& tree,
                                                       const TreeLoads& loads,
                                                       const Eigen::VectorXd& q, double h,
                                                       const Eigen::VectorXd& nu_all) {
  if (!loads.servos.active()) return loads.effort;
  const int n = tree.jointCount();
  effort_.resize(n);
  for (int k = 0; k < n; ++k) {
    const double v = nu_all[tree.velocityIndex(k)];
    effort_[k] = servoedEffort(loads.servos, k, loads.effort[k], q[k] + 0.5 * h * v, v,
                               tree.joints()[k].effort_limit);
  }
  return effort_;
}

// A step the iteration cannot solve (it stops converging when h times the tree's fastest
// rate nears 1: a whipping chain at a large dt) is done as two steps of h/2, recursively down
// to h/2^kMaxHalvings and within kMaxAttemptsPerStep attempts (past either, the last attempt
// stands). Two midpoint steps are again a symmetric, symplectic step, so the
// method keeps its properties; only the cost grows.
inline void Midpoint::robustSubstep(const ArticulatedBody& tree, const TreeLoads& loads, double h,
                                    TreeState& state, int depth) {
  // One saved slot per depth, kept across steps: saving copies into vectors of the same
  // size, so a step does not allocate once the slots exist.
  if (static_cast<int>(saved_.size()) <= depth) saved_.resize(depth + 1);
  Saved& saved = saved_[depth];
  save(state, saved);
  ++attempts_;
  const bool solved = substep(tree, loads, h, state);
  if (solved || depth >= kMaxHalvings || attempts_ >= kMaxAttemptsPerStep) {
    solved_ = solved_ && solved;
    if (!slots_sized_) {  // every slot sized once the first step has sized the members
      saved_.resize(kMaxHalvings + 1);
      for (Saved& slot : saved_) save(state, slot);
      slots_sized_ = true;
    }
    return;
  }
  restore(saved, state);
  ++halvings_;
  robustSubstep(tree, loads, 0.5 * h, state, depth + 1);
  robustSubstep(tree, loads, 0.5 * h, state, depth + 1);
}

inline void Midpoint::save(const TreeState& s, Saved& v) const {
  v.state = s;
  v.T = T_;
  v.p = p_;
  v.Pi = Pi_;
}

inline void Midpoint::restore(const Saved& v, TreeState& s) {
  s = v.state;
  T_ = v.T;
  mass_at_last_ = false;   // M_ may belong to the failed attempt
  start_at_last_ = false;  // and so may the residual's start
  // The history of ν̄ restarts: the halves have another h, so that the next step is not
  // extrapolated (guess_ and differences_ need no saving).
  history_filled_ = 0;
  contraction_ = 0.0;
  p_ = v.p;
  Pi_ = v.Pi;
}

// One midpoint step; false when the iteration did not converge (or left finite numbers).
inline bool Midpoint::substep(const ArticulatedBody& tree, const TreeLoads& loads, double h,
                              TreeState& state) {
  const int n = tree.jointCount(), nv = tree.reducedCount();  // nv: the space the step solves in
  const int nj = nv - (tree.floating() ? 6 : 0);  // its joint coordinates (n without mimic)
  const bool mimic = tree.hasMimic();
  const double lambda = tree.lambda();
  kin_at_state_ = false;
  factorParents(tree);
  const bool fresh = sameAsCached(state);
  // The kinematics (and M) startFrom() gave for this state, else none: taken once.
  const bool hinted = !fresh && startsAtHint(state);
  const bool hinted_mass = hinted && hint_mass_ && !mimic;
  start_hint_ = false;
  if (!fresh) {  // momenta of a state set from outside
    if (!hinted) treeKinematics(tree, state, kin_);
    if (hinted_mass) {  // M ν with the hint's M: the momenta the recursion gives, to round-off
      drift_start_.resize(nv);
      if (tree.floating()) drift_start_.head<6>() = tree_math::vec(state.omega_0);
      drift_start_.tail(n) = state.v;
      pm_.noalias() = M_ * drift_start_;
      T_ = 0.5 * drift_start_.dot(pm_);
    } else {
      T_ = kineticEnergy(tree, kin_);
      momentumAndGradient(tree, kin_, zero_moments(tree), pm_, nullptr, work_);
    }
    f_ext_.resize(tree.bodyCount());  // sized now, so the steps after this one do not allocate
    mid_ = state;
    differences_.resize(static_cast<std::size_t>(nv) * kDifferences);
    if (mimic) {
      p_.resize(nj);
      reduceJointForce(tree, pm_.tail(n), p_);
    } else {
      p_ = pm_.tail(n);
    }
    if (tree.floating()) Pi_ = state.M_W0.apply(tree_math::moment(pm_.head<6>()), lambda);
  }
  // Start from the extrapolated midpoint velocity when the last step had the same h, else from
  // ν. The iteration matrix is M + ½hC at the step's start: the previous step factored M
  // there for its velocities, so a run of steps factors M once per step (and needs no more
  // iterations than a fresh matrix at the predicted midpoint: doc/decisions.md).
  const bool extrapolated = fresh && h == last_h_;
  if (!extrapolated) contraction_ = 0.0;  // measured anew in this run of steps
  if (extrapolated) {
    nu_bar_ = guess_;  // (not a conditional expression: that would copy into a temporary)
  } else if (!mimic) {
    nu_bar_.resize(nv);
    if (tree.floating()) nu_bar_.head<6>() = tree_math::vec(state.omega_0);
    nu_bar_.tail(n) = state.v;
  } else {
    reduceVelocity(tree, velocityVector(tree, state), nu_bar_);
  }
  // A contact step's drift starts from the state its kick and impulses left (startFrom), whose
  // ν̄ − ν changes little from one contact step to the next: the last drift's, added to ν, is
  // the closer start (the iteration converges to the same root from either).
  const bool drift_warm =
      hinted && !extrapolated && drift_offset_valid_ && h == drift_h_ && drift_offset_.size() == nv;
  if (hinted && !hinted_mass) drift_start_ = nu_bar_;  // (with the hint's M: made above)
  if (drift_warm) nu_bar_ += drift_offset_;
  drift_offset_valid_ = false;  // until this step converges from its hint
  // M's own factor at the start serves as the iteration's matrix only without damping and
  // servos; else the iteration factors M + ½hC (iterationMatrix) and M's is not needed.
  const bool iterate_on_M = !damped(tree) && !loads.servos.active();
  if (hinted_mass) {  // M at this pose, from startFrom()
    if (iterate_on_M) llt_.compute(M_);
  } else if (!fresh || !mass_at_last_) {
    if (fresh) treeKinematics(tree, state, kin_);  // (a state set from outside has them now)
    factorMass(tree, false, iterate_on_M);
  }
  const tree_math::TreeCholesky& A = iterationMatrix(tree, loads, h);
  rows_.newMatrix();
  servoed_ = loads.servos.active();
  y_.setZero(nv);
  r_.resize(nv);
  cga::Moment W;
  double last_change = INFINITY, final_change = 0.0, final_scale = 1.0;
  // Iterate ν̄ ← ν̄ + A (r(ν̄) + y), A = (M + ½hC)⁻¹ at the step's start, r the residual of the
  // midpoint equations (M(q̄)ν̄ from the momentum recursion, O(n)); then the joint rows.
  // A fixed base under gravity alone (the common case) and a floating base without gravity or
  // loads (a contact step's drift) take the fused passes of MidpointResidual, which need no
  // world poses; the general path evaluates kinematics, loads and momenta in turn.
  const bool fused = MidpointResidual::applies(tree, loads);
  if (!fused) mid_ = state;  // the general path's midpoint state
  const bool loaded =
      !loads.gravity_W.isZero(0.0) || std::any_of(loads.applied.begin(), loads.applied.end(),
                                                  [](const Loads* l) { return l != nullptr; });
  double load_power = 0.0;  // of the external moments at the midpoint
  // A fixed base's end pose comes from the residual's constants (MidpointResidual::endPose),
  // which leaves the sines and cosines of the next step's start behind.
  const bool fixed = !tree.floating();
  if (fixed || fused) residual_.prepare(tree);
  if (fused && !(fresh && start_at_last_)) residual_.startAt(state.q);
  start_at_last_ = false;
  for (int it = 0; it < kMaxIterations; ++it) {
    ++iterations_;
    // The midpoint rates of every joint (with mimic joints, expanded from ν̄_r).
    if (mimic) expandVelocity(tree, nu_bar_, nu_full_);
    const Eigen::VectorXd& nu_all = mimic ? nu_full_ : nu_bar_;
    if (fused) {
      // (A floating base's fused passes have no gravity: its axes at the midpoint serve only
      // the momentum's equation below.)
      if (tree.floating())
        mid_.M_W0 = state.M_W0 * cga::exp(tree_math::bivector(nu_all.head<6>()) * (-0.25 * h));
      residual_.evaluate(state.q, loads.gravity_W, h, nu_all, pm_, grad_);
    } else {
      mid_.q = state.q + (0.5 * h) * nu_all.tail(n);
      setVelocityVector(tree, nu_all, mid_);
      if (tree.floating())
        mid_.M_W0 = state.M_W0 * cga::exp(tree_math::bivector(nu_all.head<6>()) * (-0.25 * h));
      treeKinematics(tree, mid_, kin_);
      externalMoments(tree, kin_, loads, f_ext_);
      momentumAndGradient(tree, kin_, f_ext_, pm_, &grad_, work_);
    }
    const Eigen::VectorXd& effort = midpointEffort(tree, loads, state.q, h, nu_all);
    if (!mimic) {
      r_.tail(n) = p_ + (0.5 * h) * (grad_ + effort) - pm_.tail(n);
    } else {  // Gᵀ of the joints' residual, plus the reduced momenta
      joint_r_ = (0.5 * h) * (grad_ + effort) - pm_.tail(n);
      if (damped(tree))
        for (int k = 0; k < n; ++k)
          joint_r_[k] -= 0.5 * h * tree.joints()[k].damping * nu_all[tree.velocityIndex(k)];
      reduceJointForce(tree, joint_r_, r_.tail(nj));
      r_.tail(nj) += p_;
    }
    if (damped(tree) && !mimic)
      for (int k = 0; k < n; ++k)
        r_[tree.velocityIndex(k)] -=
            0.5 * h * tree.joints()[k].damping * nu_bar_[tree.velocityIndex(k)];
    if (tree.floating()) {
      // Without loads (a contact step's drift) every moment is a signed zero and W stays +0.
      W = cga::Moment();
      if (loaded)
        for (int b = 0; b < tree.bodyCount(); ++b) W += kin_.M_W[b].apply(f_ext_[b], lambda);
      r_.head<6>() =
          tree_math::vec(mid_.M_W0.reverse().apply(Pi_ + W * (0.5 * h), lambda)) - pm_.head<6>();
    }
    // ν̄ + A r is the unconstrained solution (ν̄ holds the last impulses, r does not); the
    // rows then add the impulses anew.
    nu_new_ = r_;
    A.solveInPlace(nu_new_);
    nu_new_ += nu_bar_;
    rows_.solve(tree, A, state.q, h, nu_new_);
    rows_.impulses(y_);
    const double change = nv == 0 ? 0.0 : (nu_new_ - nu_bar_).cwiseAbs().maxCoeff();
    const double scale = 1.0 + (nv == 0 ? 0.0 : nu_new_.cwiseAbs().maxCoeff());
    nu_bar_.swap(nu_new_);
    // The error left in ν̄: the next correction, estimated from the ratio of the last two.
    final_change = it > 0 ? std::min(change, change * (change / last_change)) : change;
    final_scale = scale;
    // Linear convergence with ratio change/last_change: stop when the next correction would
    // be below the tolerance, or when the corrections stop shrinking (round-off). The ratio
    // is kept while a correction is well above round-off (below, its noise would spoil it).
    if (change <= kTolerance * scale) break;
    if (it > 0 && change > kRatioFloor * scale) contraction_ = change / last_change;
    if (it > 0 && change * (change / last_change) <= kTolerance * scale) break;
    // After the first pass of a run of equal steps, the ratio of the steps before predicts
    // the next correction (the iteration's matrix and its error change by O(h) from step to
    // step): twice it times this correction below the tolerance, and no joint row acting
    // (their impulses move with ν̄), and the step has converged with one residual pass.
    if (it == 0 && extrapolated && contraction_ > 0.0 &&
        change * (kRatioMargin * contraction_) <= kTolerance * scale && y_.isZero(0.0)) {
      final_change = change * (kRatioMargin * contraction_);
      break;
    }
    if (it > 2 && change >= last_change) break;
    last_change = change;
  }
  if (!(final_change <= kConverged * final_scale) || !finite(nu_bar_)) return false;
  if (mimic) expandVelocity(tree, nu_bar_, nu_full_);  // the converged ν̄ on every joint
  const Eigen::VectorXd& nu_all = mimic ? nu_full_ : nu_bar_;
  // The power of the loads and efforts at the midpoint (the general path's kin_ holds it), for
  // the energy check.
  if (fused) load_power = residual_.gravityPower();
  if (!fused)
    for (int b = tree.floating() ? 0 : 1; b < tree.bodyCount(); ++b)
      load_power += tree_math::pairing(f_ext_[b], kin_.omega[b]);
  const Eigen::VectorXd& effort = midpointEffort(tree, loads, state.q, h, nu_all);
  const double power = load_power + effort.dot(nu_all.tail(n));
  const double T_start = T_;
  // p_{k+1} = p_k + h (∂L/∂q + Q + τ − C q̄̇) + 2y: the discrete momentum balance itself.
  grad_ += effort;
  if (damped(tree))
    for (int k = 0; k < n; ++k)
      grad_[k] -= tree.joints()[k].damping * nu_all[tree.velocityIndex(k)];
  if (!mimic) {
    p_ += h * grad_ + 2.0 * y_.tail(n);
  } else {
    grad_r_.resize(nj);
    reduceJointForce(tree, grad_, grad_r_);
    p_ += h * grad_r_ + 2.0 * y_.tail(nj);
  }
  state.q += h * nu_all.tail(n);
  rows_.clampPositions(tree, state.q);
  if (tree.floating()) {
    Pi_ += W * h;
    state.M_W0 =
        (state.M_W0 * cga::exp(tree_math::bivector(nu_bar_.head<6>()) * (-0.5 * h))).normalized();
  }
  // Velocities at the new pose: M(q) ν = (M_W0⁻¹ Π, p).
  if (fixed)
    residual_.endPose(state.q, kin_);
  else
    treePoses(tree, state, kin_);
  factorMass(tree, fixed);
  mass_at_last_ = false;  // until this step is accepted
  rhs_.resize(nv);
  rhs_.tail(nj) = p_;
  if (tree.floating()) rhs_.head<6>() = tree_math::vec(state.M_W0.reverse().apply(Pi_, lambda));
  nu_end_ = rhs_;
  llt_.solveInPlace(nu_end_);
  // A converged iteration can still have found a spurious root of the midpoint equations when
  // h is large against the motion (a whipping chain): its kinetic energy jumps by far more
  // than the loads' work. Such a step is refused and halved. A true step changes T by
  // h·power up to its O((hω)²) error: 5 % of the kinetic energy plus half the work bound
  // that generously (the work term covers a start from rest, where T itself is O(h²)).
  T_ = 0.5 * nu_end_.dot(rhs_);  // ½ νᵀ M ν with M ν = rhs
  const double growth = T_ - T_start - h * power;
  if (growth > 0.05 * (T_ + T_start) + 0.5 * std::abs(h * power) + 1e-12) return false;
  // What the joints took over the substep: the momentum balance's non-conservative terms,
  // damping −h C q̄̇ and friction's impulses 2y, paired with ν̄ (doc/articulated.md#energy).
  // A limit's stop is booked by the World from the energies before and after the step.
  const bool limited = rows_.limitActed();
  double taken = limited ? 0.0 : -2.0 * y_.dot(nu_bar_);
  if (damped(tree))
    for (int k = 0; k < n; ++k) {
      const double v = nu_bar_[tree.velocityIndex(k)];
      taken += h * tree.joints()[k].damping * v * v;
    }
  // Joints held by a limit or by friction end the step at rest (inelastic, doc/articulated.md):
  // the kinetic energy that stop takes is taken too.
  if (rows_.stopHeld(tree, llt_, nu_end_)) {
    Mnu_.noalias() = (mimic ? Mr_ : M_) * nu_end_;
    p_ = Mnu_.tail(nj);
    const double T_stopped = 0.5 * nu_end_.dot(Mnu_);
    taken += T_ - T_stopped;
    T_ = T_stopped;
  }
  if (hinted) {  // the next contact step's drift starts from this one's ν̄ − ν
    drift_offset_ = nu_bar_ - drift_start_;
    drift_h_ = h;
    drift_offset_valid_ = true;
  }
  if (!extrapolated) history_filled_ = 0;  // this step starts a run of equal steps
  predictNext(nv);
  if (mimic) {
    expandVelocity(tree, nu_end_, nu_full_);
    setVelocityVector(tree, nu_full_, state);
  } else {
    setVelocityVector(tree, nu_end_, state);
  }
  // kin_ holds the new poses: with the new velocities it is the kinematics of the new state.
  if (fixed)
    residual_.velocities(state.v, kin_);
  else
    treeVelocities(tree, state, kin_);
  if (!finite(state.q) || !finite(state.v) || !state.M_W0.allFinite() || !state.omega_0.allFinite())
    return false;
  kin_at_state_ = true;
  kin_exact_ = !fixed;
  dissipated_ += taken;
  limited_ = limited_ || limited;
  last_ = state;
  last_h_ = h;
  cached_ = true;
  mass_at_last_ = true;
  start_at_last_ = fixed;
  return true;
}

}  // namespace

std::unique_ptr<TreeIntegrator> makeMidpointTreeIntegrator(bool fourth_order) {
  return std::make_unique<Midpoint>(fourth_order);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
