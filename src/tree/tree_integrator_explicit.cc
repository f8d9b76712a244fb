// The baselines for trees: classical RK4 and explicit Euler on (M_W0, Ω_0, q, q̇) with the
// accelerations of forward dynamics (tree_integrator.h): for a fixed base under gravity alone
// MidpointResidual::accelerations (CRBA, RNEA bias, Cholesky on scalar frames), else ABA.
// Damping and friction enter as explicit forces (friction −F sign q̇, so it chatters about zero:
// a baseline); limits by projection after the step (position clamped, the rate into the limit
// stopped by an impulse on the joint in the metric of M, which keeps a floating tree's
// momentum). What damping and friction take is booked as the forces' work at the mean of the
// rates before and after; a step with a stop is booked by the World from its energies. With
// mimic joints the accelerations are those the constraints allow (forwardDynamics), so every
// stage moves the followers with their leaders; after the step the limits are projected on the
// independent coordinates (the stop in the metric of M_r = Gᵀ M G) and the followers set from
// their leaders.
#include <algorithm>
#include <array>
#include <cstring>

#include "cga_rigid_sim/tree/tree_integrator.h"
#include "tree/joint_rows.h"
#include "tree/tree_integrator_residual.h"
#include "tree/tree_integrators.h"
#include "tree/tree_math.h"

namespace cga_rigid_sim {
namespace dynamics {

namespace {

using Coeffs = std::array<double, 8>;

// Ṁ = −½ M Ω as motor coefficients (Ω as the even element with those bivector blades).
Coeffs motorRate(const cga::Motor& M, const cga::Bivelocity& omega) {
  const cga::Motor O =
      cga::Motor::fromCoefficients({0, omega.rot.x(), omega.rot.y(), omega.rot.z(), omega.trans.x(),
                                    omega.trans.y(), omega.trans.z(), 0});
  Coeffs c = (M * O).coefficients();
  for (double& x : c) x *= -0.5;
  return c;
}

class Explicit final : public TreeIntegrator {
 public:
  explicit Explicit(bool rk4) : rk4_(rk4) {}
  const char* name() const override { return rk4_ ? "rk4" : "euler"; }
  double lastDissipated() const override { return dissipated_; }
  bool lastLimited() const override { return !held_.empty(); }
  void reset() override {
    kin_at_state_ = false;
    compensated_ = false;
  }
  const TreeKinematics* lastKinematics() const override {
    return kin_at_state_ ? &end_kin_ : nullptr;
  }
  const Eigen::VectorXd* lastEffort() const override { return servoed_ ? &effort_ : nullptr; }

  void step(const ArticulatedBody& tree, const TreeLoads& loads, double h,
            TreeState& state) override {
    // Stages Y_i = Y + c_i h K_{i−1} (Euler: the first alone); the motor is a linear
    // combination of coefficients. Members hold every vector, so a step does not allocate.
    const int stages = rk4_ ? 4 : 1;
    kin_at_state_ = false;
    y0_ = state;
    setVelocity(tree, y0_, nu0_);
    stage_ = y0_;
    const double c[4] = {0.0, 0.5, 0.5, 1.0};
    const double w[4] = {rk4_ ? 1.0 / 6 : 1.0, 2.0 / 6, 2.0 / 6, 1.0 / 6};
    servoed_ = loads.servos.active();
    for (int i = 0; i < stages; ++i) {
      if (i > 0) {
        stage_.q = y0_.q + (c[i] * h) * kq_[i - 1];
        stage_.M_W0 = axpy(y0_.M_W0, c[i] * h, km_[i - 1]);
        nu_ = nu0_ + (c[i] * h) * ka_[i - 1];
        setVelocityVector(tree, nu_, stage_);
      }
      kq_[i] = stage_.v;
      km_[i] = motorRate(stage_.M_W0, stage_.omega_0);
      acceleration(tree, loads, stage_, ka_[i]);
      if (servoed_) {  // the applied effort: the stages' weighted mean (what the step adds)
        if (i == 0)
          effort_ = w[0] * stage_effort_;
        else
          effort_ += w[i] * stage_effort_;
      }
    }
    // The weighted sums of the stages first, then one addition to the state: a position or
    // rate rounded once per step instead of once per stage (over 1e5 steps those roundings,
    // correlated from step to step, would add up to ~1e-12).
    Coeffs dM{};
    dq_ = w[0] * kq_[0];
    dnu_ = w[0] * ka_[0];
    for (int j = 0; j < 8; ++j) dM[j] = w[0] * km_[0][j];
    for (int i = 1; i < stages; ++i) {
      dq_ += w[i] * kq_[i];
      dnu_ += w[i] * ka_[i];
      for (int j = 0; j < 8; ++j) dM[j] += w[i] * km_[i][j];
    }
    // q and ν take the step by compensated (Kahan) sums: the rounding of each addition is kept
    // and subtracted from the next step's increment, so that over 1e4–1e6 steps the roundings of
    // q and ν do not add up (they set the round-off floor of long runs: the double pendulum at
    // h = 5e-5 over 10 s, 4.1e-14 rad without, 1.4e-15 with; arm7 1.9e-13 → 6.0e-14). The
    // compensation carries over only while the state is the one the last step left (bit for
    // bit): any edit, impulse or limit restarts it.
    if (!compensated_ || !sameBits(y0_.q, last_q_) || !sameBits(nu0_, last_nu_)) {
      carry_q_.setZero(dq_.size());
      carry_nu_.setZero(dnu_.size());
    }
    compensatedAdd(y0_.q, h, dq_, carry_q_, state.q);
    compensatedAdd(nu0_, h, dnu_, carry_nu_, nu_);
    state.M_W0 = axpy(y0_.M_W0, h, dM);
    setVelocityVector(tree, nu_, state);
    if (tree.floating()) state.M_W0 = state.M_W0.normalized();
    compensated_ = true;
    // What damping and friction took: their power at the mean of the rates before and after.
    dissipated_ = 0.0;
    for (int k = 0; k < tree.jointCount(); ++k) {
      const TreeJoint& j = tree.joints()[k];
      const double v = 0.5 * (y0_.v[k] + state.v[k]);
      dissipated_ += h * (j.damping * v * v + j.friction * std::abs(v));
    }
    held_.clear();
    for (const JointCoordinate& c : tree.coordinates()) {  // limits by projection
      const int k = c.joint;
      if (state.q[k] < c.lower) {
        state.q[k] = c.lower;
        if (state.v[k] < 0.0) held_.push_back(tree.reducedIndex(k));
        compensated_ = false;
      } else if (state.q[k] > c.upper) {
        state.q[k] = c.upper;
        if (state.v[k] > 0.0) held_.push_back(tree.reducedIndex(k));
        compensated_ = false;
      }
    }
    if (!held_.empty() && state.allFinite()) {  // stopped in the metric of M at the new pose
      const bool mimic = tree.hasMimic();
      applyMimicPositions(tree, state.q);
      treeKinematics(tree, state, kin_);
      massMatrix(tree, kin_, M_, work_);
      if (mimic) reduceMatrix(tree, M_, Mr_, work_);
      llt_.compute(mimic ? Mr_ : M_);
      setVelocity(tree, state, nu_);
      reduceVelocity(tree, nu_, nu_r_);
      stopRates(llt_, held_, nu_r_, stop_);
      expandVelocity(tree, nu_r_, nu_);
      setVelocityVector(tree, nu_, state);
    }
    applyMimic(tree, state);  // followers exactly where their leaders put them
    last_q_ = state.q;
    setVelocity(tree, state, last_nu_);
    // The new state's kinematics, for the World to write the links' states from: from the
    // fused path's frames for less than treeKinematics, when it applies.
    if (!state.allFinite()) return;
    if (fused(tree, loads)) {
      stage_dynamics_.endPose(state.q, end_kin_);
      stage_dynamics_.velocities(state.v, end_kin_);
    } else {
      treeKinematics(tree, state, end_kin_);
    }
    kin_at_state_ = true;
  }

 private:
  // out = x + (h d − carry), rounded, with carry ← the part of h d − carry the sum lost.
  static void compensatedAdd(const Eigen::VectorXd& x, double h, const Eigen::VectorXd& d,
                             Eigen::VectorXd& carry, Eigen::VectorXd& out) {
    out.resize(x.size());
    for (Eigen::Index k = 0; k < x.size(); ++k) {
      const double y = h * d[k] - carry[k];
      const double t = x[k] + y;
      carry[k] = (t - x[k]) - y;
      out[k] = t;
    }
  }
  static bool sameBits(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return a.size() == b.size() &&
           std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<std::size_t>(a.size())) ==
               0;
  }

  static cga::Motor axpy(const cga::Motor& M, double t, const Coeffs& dM) {
    Coeffs c = M.coefficients();
    for (int j = 0; j < 8; ++j) c[j] += t * dM[j];
    return cga::Motor::fromCoefficients(c);
  }

  static void setVelocity(const ArticulatedBody& tree, const TreeState& s, Eigen::VectorXd& nu) {
    nu.resize(tree.velocityCount());
    if (tree.floating()) nu.head<6>() = tree_math::vec(s.omega_0);
    nu.tail(tree.jointCount()) = s.v;
  }

  // A fixed base under gravity alone (the common case) takes MidpointResidual's stage (frames
  // by Rodrigues, CRBA, RNEA bias, Cholesky); the rest ABA on the full kinematics, and a tree
  // with mimic joints forwardDynamics' constrained accelerations.
  static bool fused(const ArticulatedBody& tree, const TreeLoads& loads) {
    return !tree.floating() && MidpointResidual::applies(tree, loads) && !tree.hasMimic();
  }
  void acceleration(const ArticulatedBody& tree, const TreeLoads& loads, const TreeState& s,
                    Eigen::VectorXd& out) {
    Eigen::VectorXd& tau = tau_;
    tau = loads.effort;
    if (loads.servos.active())  // explicit: the servo at this stage's state
      for (int k = 0; k < tree.jointCount(); ++k)
        tau[k] =
            servoedEffort(loads.servos, k, tau[k], s.q[k], s.v[k], tree.joints()[k].effort_limit);
    if (loads.servos.active()) stage_effort_ = tau;
    for (int k = 0; k < tree.jointCount(); ++k) {
      const TreeJoint& j = tree.joints()[k];
      tau[k] -= j.damping * s.v[k];
      if (s.v[k] != 0.0) tau[k] -= (s.v[k] > 0 ? j.friction : -j.friction);
    }
    if (fused(tree, loads)) {
      stage_dynamics_.prepare(tree);
      stage_dynamics_.accelerations(s.q, s.v, loads.gravity_W, tau, out);
      if (general_sized_) return;
      // The general path's scratch is sized now, so that a later step with a load on a link
      // (which takes it) does not allocate: its accelerations here are discarded.
      general_sized_ = true;
      treeKinematics(tree, s, kin_);
      externalMoments(tree, kin_, loads, f_ext_);
      forwardDynamics(tree, s, kin_, tau, f_ext_, scratch_, work_);
      return;
    }
    general_sized_ = true;
    treeKinematics(tree, s, kin_);
    externalMoments(tree, kin_, loads, f_ext_);
    forwardDynamics(tree, s, kin_, tau, f_ext_, out, work_);
  }

  bool rk4_;
  TreeState y0_, stage_;
  Eigen::VectorXd nu0_, nu_, tau_, ka_[4], kq_[4], dq_, dnu_;
  // The compensated sums' carries, valid while the state is (last_q_, last_nu_).
  Eigen::VectorXd carry_q_, carry_nu_, last_q_, last_nu_;
  bool compensated_ = false;
  Coeffs km_[4];
  TreeKinematics kin_;
  TreeWorkspace work_;  // the tree algorithms' work arrays
  BodyMoments f_ext_;
  MidpointResidual stage_dynamics_;
  TreeKinematics end_kin_;  // of the state the last step produced, when kin_at_state_
  bool kin_at_state_ = false;
  bool general_sized_ = false;  // the general path has run once (its scratch has its sizes)
  Eigen::VectorXd scratch_;
  double dissipated_ = 0.0;       // what the joints took in the last step (lastDissipated)
  Eigen::VectorXd effort_;        // with servos: the effort the step applied (lastEffort)
  Eigen::VectorXd stage_effort_;  // with servos: the effort at the last stage
  bool servoed_ = false;
  std::vector<int> held_;   // joints stopped at a limit in the last step
  StopScratch stop_;        // stopRates' working storage
  Eigen::MatrixXd M_, Mr_;  // M, and M_r = Gᵀ M G with mimic joints
  Eigen::VectorXd nu_r_;
  tree_math::Cholesky llt_;
};

}  // namespace

std::unique_ptr<TreeIntegrator> makeExplicitTreeIntegrator(bool rk4) {
  return std::make_unique<Explicit>(rk4);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
