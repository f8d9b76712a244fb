// The baselines for trees: classical RK4 and explicit Euler on (M_W0, Ω_0, q, q̇) with the
// accelerations of ABA (tree_integrator.h). Damping and friction enter as explicit forces
// (friction −F sign q̇, so it chatters about zero: a baseline); limits by projection after the
// step (position clamped, the rate into the limit removed).
#include <algorithm>
#include <array>

#include "cga_rigid_sim/dynamics/tree_integrator.h"
#include "tree_integrators.h"
#include "tree_math.h"

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

  void step(const ArticulatedBody& tree, const TreeLoads& loads, double h,
            TreeState& state) override {
    if (!rk4_) {
      const Eigen::VectorXd a = acceleration(tree, loads, state);
      const Coeffs dM = motorRate(state.M_W0, state.omega_0);
      TreeState next = state;
      next.q += h * state.v;
      next.M_W0 = axpy(state.M_W0, h, dM);
      setVelocityVector(tree, velocityVector(tree, state) + h * a, next);
      state = next;
    } else {
      // Stages Y_i = Y + c_i h K_{i−1}; the motor is a linear combination of coefficients.
      const TreeState y0 = state;
      const Eigen::VectorXd nu0 = velocityVector(tree, y0);
      Eigen::VectorXd ka[4];
      Coeffs km[4];
      Eigen::VectorXd kq[4];
      TreeState stage = y0;
      const double c[4] = {0.0, 0.5, 0.5, 1.0};
      for (int i = 0; i < 4; ++i) {
        if (i > 0) {
          stage.q = y0.q + (c[i] * h) * kq[i - 1];
          stage.M_W0 = axpy(y0.M_W0, c[i] * h, km[i - 1]);
          setVelocityVector(tree, nu0 + (c[i] * h) * ka[i - 1], stage);
        }
        kq[i] = stage.v;
        km[i] = motorRate(stage.M_W0, stage.omega_0);
        ka[i] = acceleration(tree, loads, stage);
      }
      state.q = y0.q + (h / 6) * (kq[0] + 2 * kq[1] + 2 * kq[2] + kq[3]);
      Coeffs dM;
      for (int j = 0; j < 8; ++j) dM[j] = (km[0][j] + 2 * km[1][j] + 2 * km[2][j] + km[3][j]) / 6;
      state.M_W0 = axpy(y0.M_W0, h, dM);
      setVelocityVector(tree, nu0 + (h / 6) * (ka[0] + 2 * ka[1] + 2 * ka[2] + ka[3]), state);
    }
    if (tree.floating()) state.M_W0 = state.M_W0.normalized();
    for (int k = 0; k < tree.jointCount(); ++k) {  // limits by projection
      const TreeJoint& j = tree.joints()[k];
      if (state.q[k] < j.lower) {
        state.q[k] = j.lower;
        state.v[k] = std::max(0.0, state.v[k]);
      } else if (state.q[k] > j.upper) {
        state.q[k] = j.upper;
        state.v[k] = std::min(0.0, state.v[k]);
      }
    }
  }

 private:
  static cga::Motor axpy(const cga::Motor& M, double t, const Coeffs& dM) {
    Coeffs c = M.coefficients();
    for (int j = 0; j < 8; ++j) c[j] += t * dM[j];
    return cga::Motor::fromCoefficients(c);
  }

  Eigen::VectorXd acceleration(const ArticulatedBody& tree, const TreeLoads& loads,
                               const TreeState& s) {
    treeKinematics(tree, s, kin_);
    externalMoments(tree, kin_, loads, f_ext_);
    Eigen::VectorXd tau = loads.effort;
    for (int k = 0; k < tree.jointCount(); ++k) {
      const TreeJoint& j = tree.joints()[k];
      tau[k] -= j.damping * s.v[k];
      if (s.v[k] != 0.0) tau[k] -= (s.v[k] > 0 ? j.friction : -j.friction);
    }
    return forwardDynamics(tree, s, kin_, tau, f_ext_);
  }

  bool rk4_;
  TreeKinematics kin_;
  BodyMoments f_ext_;
};

}  // namespace

std::unique_ptr<TreeIntegrator> makeExplicitTreeIntegrator(bool rk4) {
  return std::make_unique<Explicit>(rk4);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
