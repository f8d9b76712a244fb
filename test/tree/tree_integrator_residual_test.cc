// The variational midpoint's fused residual passes (src/tree/tree_integrator_residual.h)
// against the general path they replace for fixed-base trees under gravity and floating bases
// without it: treeKinematics at the midpoint, gravityMoments and momentumAndGradient (each
// tested on its own in articulated_body_test.cc), on random trees with revolute and prismatic
// joints.
#include "tree/tree_integrator_residual.h"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "cga_rigid_sim/body/loads.h"
#include "common/random_trees.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace tree_integrator_residual_test {

using Eigen::Vector3d;
using Eigen::VectorXd;

constexpr double kLambda = 0.7;  // not 1, so a misplaced λ shows

ArticulatedBody randomTree(std::mt19937& rng, int n, bool floating) {
  return testing::randomTree(rng, n, floating, kLambda);
}

// At q̄ = q + ½h ν̄ with rates ν̄: momenta, gradient and gravity's power agree with the general
// passes to round-off. Step sizes: small increments ¼hν̄ (the Taylor branch of the half-angle
// sine and cosine) and large ones (past 1/16: std::sin/cos).
TEST(MidpointResidual, IsTheKinematicsGravityAndMomentumPasses) {
  std::mt19937 rng(2026);
  const Vector3d g(0.3, -1.1, -9.81);
  for (const int n : {1, 2, 7, 12}) {
    for (const double h : {1e-3, 0.02, 0.5}) {
      for (int trial = 0; trial < 5; ++trial) {
        const ArticulatedBody tree = randomTree(rng, n, false);
        TreeState start;
        start.q = VectorXd::Random(n) * 3.0;
        const VectorXd nu_bar = VectorXd::Random(n) * 3.0;
        MidpointResidual residual;
        residual.prepare(tree);
        residual.startAt(start.q);
        VectorXd p, grad;
        residual.evaluate(start.q, g, h, nu_bar, p, grad);
        const double power = residual.gravityPower();

        TreeState mid;
        mid.q = start.q + 0.5 * h * nu_bar;
        mid.v = nu_bar;
        TreeKinematics kin;
        treeKinematics(tree, mid, kin);
        BodyMoments f;
        gravityMoments(tree, kin, g, f);
        VectorXd p_ref, grad_ref;
        momentumAndGradient(tree, kin, f, p_ref, &grad_ref);
        double power_ref = 0.0;
        for (int b = 1; b < tree.bodyCount(); ++b)
          power_ref += f[b].rot.dot(kin.omega[b].rot) + f[b].trans.dot(kin.omega[b].trans);
        // Both are O(1)-conditioned sums over ≤ 12 bodies of O(10) terms: round-off ≈ 1e-14;
        // a wrong frame, sign or λ would be off by O(1).
        const double scale = 1.0 + p_ref.cwiseAbs().maxCoeff() + grad_ref.cwiseAbs().maxCoeff();
        EXPECT_LT((p - p_ref).cwiseAbs().maxCoeff(), 1e-12 * scale) << n << " joints, h " << h;
        EXPECT_LT((grad - grad_ref).cwiseAbs().maxCoeff(), 1e-12 * scale)
            << n << " joints, h " << h;
        EXPECT_NEAR(power, power_ref, 1e-12 * (1.0 + std::abs(power_ref)));
      }
    }
  }
}

// The end pose from the residual's constants is treePoses' to round-off (and the mass matrix
// and velocities on it massMatrix's and treeVelocities'): the motors M_P and
// M_W (compared by their eight coefficients; a motor and its negative are different
// coefficients, so the sign convention must match too) and the adjoint blocks R_P, t_P. It also
// leaves the sines and cosines of ½q for the next step, which must give evaluate() the same
// result as startAt(q).
TEST(MidpointResidual, EndPoseIsTreePoses) {
  std::mt19937 rng(2027);
  for (const int n : {1, 2, 7, 12}) {
    for (int trial = 0; trial < 5; ++trial) {
      const ArticulatedBody tree = randomTree(rng, n, false);
      TreeState s;
      s.q = VectorXd::Random(n) * 3.0;
      s.v = VectorXd::Zero(n);
      TreeKinematics ref, kin;
      treePoses(tree, s, ref);
      MidpointResidual residual;
      residual.prepare(tree);
      residual.endPose(s.q, kin);
      // Products of ≤ 12 unit motors with O(1) translations: round-off ≈ 1e-15 per factor; a
      // wrong sign, axis or λ is off by O(1).
      for (int b = 1; b <= n; ++b) {
        const auto a = kin.M_W[b].coefficients(), r = ref.M_W[b].coefficients();
        const auto ap = kin.M_P[b].coefficients(), rp = ref.M_P[b].coefficients();
        for (int i = 0; i < 8; ++i) {
          EXPECT_NEAR(a[i], r[i], 1e-13) << n << " joints, body " << b;
          EXPECT_NEAR(ap[i], rp[i], 1e-14) << n << " joints, body " << b;
        }
        EXPECT_LT((kin.R_P[b] - ref.R_P[b]).cwiseAbs().maxCoeff(), 1e-14) << b;
        EXPECT_LT((kin.t_P[b] - ref.t_P[b]).cwiseAbs().maxCoeff(), 1e-14) << b;
      }
      // The mass matrix and the velocities on the kept frames: sums of O(1) products over ≤ 12
      // bodies, round-off ≈ 1e-14 of the largest entry.
      Eigen::MatrixXd M, M_ref;
      massMatrix(tree, ref, M_ref);
      residual.massMatrix(M);
      EXPECT_LT((M - M_ref).cwiseAbs().maxCoeff(), 1e-13 * M_ref.cwiseAbs().maxCoeff()) << n;
      s.v = VectorXd::Random(n) * 2.0;
      treeVelocities(tree, s, ref);
      residual.velocities(s.v, kin);
      for (int b = 1; b <= n; ++b) {
        EXPECT_LT((kin.omega[b].rot - ref.omega[b].rot).cwiseAbs().maxCoeff(), 1e-13) << b;
        EXPECT_LT((kin.omega[b].trans - ref.omega[b].trans).cwiseAbs().maxCoeff(), 1e-13) << b;
      }
      const VectorXd nu_bar = VectorXd::Random(n);
      VectorXd p, grad, p_ref, grad_ref;
      const Vector3d g(0, 0, -9.81);
      residual.evaluate(s.q, g, 1e-3, nu_bar, p, grad);
      MidpointResidual started;
      started.prepare(tree);
      started.startAt(s.q);
      started.evaluate(s.q, g, 1e-3, nu_bar, p_ref, grad_ref);
      EXPECT_EQ(p, p_ref);  // the same sines and cosines: the same numbers
      EXPECT_EQ(grad, grad_ref);
    }
  }
}

// The explicit integrators' stage (CRBA, RNEA bias, Cholesky on the Rodrigues frames) gives
// ABA's accelerations (forwardDynamics with gravityMoments) to round-off, and they satisfy the
// RNEA: inverseDynamics(q̈) returns the efforts. Positions of either branch of the half-angle
// sine and cosine (|½q| beyond π/2 too), rates that make the velocity-product terms O(1).
TEST(MidpointResidual, AccelerationsAreAbasAndSatisfyTheRnea) {
  std::mt19937 rng(2028);
  const Vector3d g(0.3, -1.1, -9.81);
  for (const int n : {1, 2, 7, 12}) {
    for (int trial = 0; trial < 5; ++trial) {
      const ArticulatedBody tree = randomTree(rng, n, false);
      TreeState s;
      s.q = VectorXd::Random(n) * 4.0;
      s.v = VectorXd::Random(n) * 3.0;
      const VectorXd tau = VectorXd::Random(n) * 5.0;
      MidpointResidual residual;
      residual.prepare(tree);
      VectorXd qdd;
      residual.accelerations(s.q, s.v, g, tau, qdd);

      TreeKinematics kin;
      treeKinematics(tree, s, kin);
      BodyMoments f;
      gravityMoments(tree, kin, g, f);
      VectorXd qdd_ref;
      forwardDynamics(tree, s, kin, tau, f, qdd_ref);
      const VectorXd tau_back = inverseDynamics(tree, s, kin, qdd, f);
      // Two solves of the same system in different operation orders: they differ by round-off
      // times the condition of M (measured here: below 1e-13 absolute, on accelerations up
      // to O(100) for 12 joints); 1e-11 of the largest leaves room for worse-conditioned draws.
      // A wrong frame, sign or λ is off by O(1).
      const double scale = 1.0 + qdd_ref.cwiseAbs().maxCoeff();
      EXPECT_LT((qdd - qdd_ref).cwiseAbs().maxCoeff(), 1e-11 * scale) << n << " joints";
      // The RNEA maps them back to the efforts (measured: below 1e-13), the same margin.
      EXPECT_LT((tau_back - tau).cwiseAbs().maxCoeff(), 1e-11 * (1.0 + tau.cwiseAbs().maxCoeff()))
          << n << " joints";
    }
  }
}

// The mass matrix is assembled in each base subtree's root frame, not the world's: a tree mounted
// 10 km from the origin keeps the digits of one at the origin (in the world's frame, m t² ≈ 1e8
// per link would leave about 1e-8 of an O(1) entry).
TEST(MidpointResidual, MassMatrixOfATreeFarFromTheOriginKeepsItsDigits) {
  std::mt19937 rng(2029);
  for (int trial = 0; trial < 5; ++trial) {
    const ArticulatedBody near = randomTree(rng, 7, false);
    std::vector<TreeJoint> joints = near.joints();
    for (TreeJoint& j : joints)
      if (j.parent == 0)
        j.M_PJ = cga::Motor::translator(Vector3d(1e4, -2e4, 5e3), kLambda) * j.M_PJ;
    const ArticulatedBody far(std::nullopt, joints, kLambda);
    const VectorXd q = VectorXd::Random(7) * 3.0;
    TreeKinematics kin;
    Eigen::MatrixXd M_near, M_far;
    MidpointResidual a, b;
    a.prepare(near);
    a.endPose(q, kin);
    a.massMatrix(M_near);
    b.prepare(far);
    b.endPose(q, kin);
    b.massMatrix(M_far);
    // The same tree, moved: the same matrix up to the round-off of the joint frames' translation
    // (an ulp of 2e4 m, ≈ 4e-12 m, times O(1) lever arms and masses).
    EXPECT_LT((M_far - M_near).cwiseAbs().maxCoeff(), 1e-10 * M_near.cwiseAbs().maxCoeff());
  }
}

// A floating base without gravity (a contact step's drift): at q̄ = q + ½h ν̄ with the base's
// midpoint bivelocity ν̄_0, the fused passes give the momenta (the base's six: the tree's
// momentum in the base's axes) and the gradient of the general passes to round-off. The
// general passes take the base's world pose, which the fused ones never see: a random one.
TEST(MidpointResidual, FloatingBaseWithoutGravityIsTheKinematicsAndMomentumPasses) {
  std::mt19937 rng(2028);
  for (const int n : {1, 2, 7, 12}) {
    for (const double h : {1e-3, 0.02, 0.5}) {
      for (int trial = 0; trial < 5; ++trial) {
        const ArticulatedBody tree = randomTree(rng, n, true);
        TreeState start;
        start.q = VectorXd::Random(n) * 3.0;
        const VectorXd nu_bar = VectorXd::Random(n + 6) * 3.0;
        MidpointResidual residual;
        residual.prepare(tree);
        residual.startAt(start.q);
        VectorXd p, grad;
        residual.evaluate(start.q, Vector3d::Zero(), h, nu_bar, p, grad);
        EXPECT_EQ(residual.gravityPower(), 0.0);

        TreeState mid;
        mid.q = start.q + 0.5 * h * nu_bar.tail(n);
        mid.M_W0 = cga::Motor::fromPose(Eigen::Quaterniond::UnitRandom(), Vector3d::Random() * 5.0,
                                        kLambda);
        setVelocityVector(tree, nu_bar, mid);
        TreeKinematics kin;
        treeKinematics(tree, mid, kin);
        const BodyMoments none(tree.bodyCount(), cga::Moment());
        VectorXd p_ref, grad_ref;
        momentumAndGradient(tree, kin, none, p_ref, &grad_ref);
        // As for the fixed base: round-off ≈ 1e-14 of O(1)-conditioned sums; a wrong frame, sign
        // or λ, or a link's momentum not gathered into the base's, would be off by O(1).
        const double scale = 1.0 + p_ref.cwiseAbs().maxCoeff() + grad_ref.cwiseAbs().maxCoeff();
        ASSERT_EQ(p.size(), n + 6);
        EXPECT_LT((p - p_ref).cwiseAbs().maxCoeff(), 1e-12 * scale) << n << " joints, h " << h;
        EXPECT_LT((grad - grad_ref).cwiseAbs().maxCoeff(), 1e-12 * scale)
            << n << " joints, h " << h;
      }
    }
  }
}

// The fused passes know gravity only, and a floating base's only without it: a floating base
// under gravity or a load on a link (or on a floating base) takes the general path.
TEST(MidpointResidual, AppliesToFixedBasesUnderGravityAndFloatingBasesWithoutLoads) {
  std::mt19937 rng(7);
  const ArticulatedBody fixed = randomTree(rng, 3, false), floating = randomTree(rng, 3, true);
  TreeLoads loads;
  loads.gravity_W = Vector3d(0, 0, -9.81);
  loads.applied.assign(4, nullptr);
  EXPECT_TRUE(MidpointResidual::applies(fixed, loads));
  EXPECT_FALSE(MidpointResidual::applies(floating, loads));
  loads.gravity_W.setZero();
  EXPECT_TRUE(MidpointResidual::applies(floating, loads));
  Loads pushed;
  AppliedLoad push;
  push.F = cga::Force(Vector3d(1, 0, 0));
  pushed.add(push);
  loads.applied[0] = &pushed;  // on the base: a fixed base's is the world, which takes none
  EXPECT_FALSE(MidpointResidual::applies(floating, loads));
  EXPECT_TRUE(MidpointResidual::applies(fixed, loads));
  loads.applied[2] = &pushed;
  EXPECT_FALSE(MidpointResidual::applies(fixed, loads));
}

}  // namespace tree_integrator_residual_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
