// Tests of the tree algorithms (tree/articulated_body.h) on random trees, fixed and floating:
// ABA against RNEA, the mass matrix against the momentum map and the kinetic energy, the
// Lagrangian gradient against finite differences and against Lagrange's equations along the
// motion ABA gives, the adjoint matrix against the motor sandwich, and the simple pendulum.
#include "cga_rigid_sim/tree/articulated_body.h"

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "common/random_trees.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace articulated_body_test {

using Eigen::Vector3d;
using Eigen::VectorXd;

constexpr double kLambda = 0.7;  // not 1, so a misplaced λ shows

Vector3d randomVector(std::mt19937& rng, double scale) { return testing::randomVector(rng, scale); }
cga::Motor randomMotor(std::mt19937& rng, double reach) {
  return testing::randomMotor(rng, reach, kLambda);
}
ArticulatedBody randomTree(std::mt19937& rng, int n, bool floating) {
  return testing::randomTree(rng, n, floating, kLambda);
}

TreeState randomState(std::mt19937& rng, const ArticulatedBody& tree) {
  TreeState s;
  if (tree.floating()) {
    s.M_W0 = randomMotor(rng, 2.0);
    s.omega_0 = cga::Bivelocity(randomVector(rng, 2), randomVector(rng, 2));
  }
  const int n = tree.jointCount();
  s.q = VectorXd::Random(n) * 2.0;
  s.v = VectorXd::Random(n) * 2.0;
  return s;
}

BodyMoments randomMoments(std::mt19937& rng, const ArticulatedBody& tree) {
  BodyMoments f(tree.bodyCount());
  for (auto& m : f) m = cga::Moment(randomVector(rng, 3), randomVector(rng, 3));
  if (!tree.floating()) f[0] = cga::Moment();
  return f;
}

struct TreeCase {
  int joints;
  bool floating;
};

class RandomTree : public ::testing::TestWithParam<TreeCase> {};

// treeKinematics against (A0) and (A2) written with the algebra's own operations: the motor
// M_PJ exp(−½ q S) M_JC (cga::exp, motor products), its adjoint blocks (adjointMatrix) and the
// velocity M̃_pb Ω_p M_pb + q̇ s (Motor::apply). The code takes the exponential in the child's
// frame in closed form and changes frames with 3×3 blocks; both agree to round-off (unit
// motors, coefficients O(1)).
TEST_P(RandomTree, KinematicsIsTheMotorDefinition) {
  std::mt19937 rng(3 + GetParam().joints);
  for (int trial = 0; trial < 20; ++trial) {
    const ArticulatedBody tree = randomTree(rng, GetParam().joints, GetParam().floating);
    const TreeState s = randomState(rng, tree);
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    for (int k = 0; k < tree.jointCount(); ++k) {
      const TreeJoint& j = tree.joints()[k];
      const int b = k + 1;
      const cga::Motor M = j.M_PJ * cga::exp(tree.screwInJoint(k) * (-0.5 * s.q[k])) * j.M_JC;
      const auto got = kin.M_P[b].coefficients(), want = M.coefficients();
      for (int c = 0; c < 8; ++c) EXPECT_NEAR(got[c], want[c], 1e-14) << "joint " << k;
      const Eigen::Matrix<double, 6, 6> X = adjointMatrix(M, kLambda);
      Eigen::Matrix3d t_cross;
      const Vector3d& t = kin.t_P[b];
      t_cross << 0, -t.z(), t.y(), t.z(), 0, -t.x(), -t.y(), t.x(), 0;
      EXPECT_LT((X.topLeftCorner<3, 3>() - kin.R_P[b]).cwiseAbs().maxCoeff(), 1e-14);
      EXPECT_LT((X.bottomLeftCorner<3, 3>() - t_cross * kin.R_P[b]).cwiseAbs().maxCoeff(), 1e-13);
      const cga::Bivelocity omega =
          M.reverse().apply(kin.omega[j.parent]) + tree.screwInChild(k) * s.v[k];
      EXPECT_LT((omega.rot - kin.omega[b].rot).norm() + (omega.trans - kin.omega[b].trans).norm(),
                1e-12)
          << "joint " << k;
      const cga::Motor MW = kin.M_W[j.parent] * M;
      const auto gw = kin.M_W[b].coefficients(), ww = MW.coefficients();
      for (int c = 0; c < 8; ++c) EXPECT_NEAR(gw[c], ww[c], 1e-12) << "joint " << k;
    }
  }
}

TEST_P(RandomTree, AbaAgreesWithRnea) {
  std::mt19937 rng(11 + GetParam().joints);
  for (int trial = 0; trial < 20; ++trial) {
    const ArticulatedBody tree = randomTree(rng, GetParam().joints, GetParam().floating);
    const TreeState s = randomState(rng, tree);
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    const BodyMoments f = randomMoments(rng, tree);
    const VectorXd tau = VectorXd::Random(tree.jointCount()) * 5.0;
    const VectorXd nu_dot = forwardDynamics(tree, s, kin, tau, f);
    const VectorXd back = inverseDynamics(tree, s, kin, nu_dot, f);
    VectorXd expected = VectorXd::Zero(tree.velocityCount());
    expected.tail(tree.jointCount()) = tau;
    // Two independent recursions over the same numbers: they agree to round-off, a few ulps of
    // the largest term (accelerations and forces here are O(10–100)).
    EXPECT_LT((back - expected).cwiseAbs().maxCoeff(), 1e-11 * (1 + nu_dot.norm()))
        << "trial " << trial;
  }
}

// The kick's acceleration at rest (contact_trees.cc): M(q)⁻¹ of forcesAtRest against ABA at
// zero velocity, on the same efforts and external moments. Two independent routes (CRBA, a
// Cholesky factor and the RNEA's inward pass against ABA's three passes): they agree to
// round-off of the largest term (measured ≤ 1.6e-14 over the 140 trees; 1e-12 leaves room for
// other compilers' rounding).
TEST_P(RandomTree, ForcesAtRestGiveAbasAccelerationAtRest) {
  std::mt19937 rng(17 + GetParam().joints);
  for (int trial = 0; trial < 20; ++trial) {
    const ArticulatedBody tree = randomTree(rng, GetParam().joints, GetParam().floating);
    TreeState s = randomState(rng, tree);
    s.v.setZero();
    s.omega_0 = cga::Bivelocity();
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    const BodyMoments f = randomMoments(rng, tree);
    const VectorXd tau = VectorXd::Random(tree.jointCount()) * 5.0;
    TreeWorkspace work;
    VectorXd Q;
    forcesAtRest(tree, kin, tau, f, Q, work);
    Eigen::MatrixXd M;
    massMatrix(tree, kin, M);
    const VectorXd nu_dot = M.llt().solve(Q);
    const VectorXd aba = forwardDynamics(tree, s, kin, tau, f);
    EXPECT_LT((nu_dot - aba).cwiseAbs().maxCoeff(), 1e-12 * (1 + aba.cwiseAbs().maxCoeff()))
        << "trial " << trial;
  }
}

TEST_P(RandomTree, MassMatrixIsSymmetricPositiveDefiniteAndGivesMomentumAndEnergy) {
  std::mt19937 rng(23 + GetParam().joints);
  for (int trial = 0; trial < 20; ++trial) {
    const ArticulatedBody tree = randomTree(rng, GetParam().joints, GetParam().floating);
    const TreeState s = randomState(rng, tree);
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    Eigen::MatrixXd M;
    massMatrix(tree, kin, M);
    EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-13 * M.norm());
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(M);
    EXPECT_GT(eig.eigenvalues().minCoeff(), 0.0);
    const VectorXd nu = velocityVector(tree, s);
    const BodyMoments none(tree.bodyCount());
    // The momentum map (an inward recursion over link momenta) against M ν (CRBA).
    const VectorXd p = momentumAndGradient(tree, kin, none, nullptr);
    EXPECT_LT((p - M * nu).cwiseAbs().maxCoeff(), 1e-12 * (1 + p.norm()));
    // Σ ½ Ω·I(Ω) over the links against ½ νᵀ M ν.
    EXPECT_NEAR(kineticEnergy(tree, kin), 0.5 * nu.dot(M * nu), 1e-12 * (1 + nu.dot(M * nu)));
    // RNEA without velocity and loads is M ν̇.
    TreeState still = s;
    setVelocityVector(tree, VectorXd::Zero(tree.velocityCount()), still);
    TreeKinematics kin0;
    treeKinematics(tree, still, kin0);
    const VectorXd acc = VectorXd::Random(tree.velocityCount());
    EXPECT_LT((inverseDynamics(tree, still, kin0, acc, none) - M * acc).cwiseAbs().maxCoeff(),
              1e-12 * (1 + (M * acc).norm()));
  }
}

// L(q, ν) = T − V for gravity g: the gradient from the recursion against central differences.
TEST_P(RandomTree, LagrangianGradientMatchesFiniteDifferences) {
  std::mt19937 rng(37 + GetParam().joints);
  const Vector3d g(0.3, -1.1, -9.81);
  for (int trial = 0; trial < 10; ++trial) {
    const ArticulatedBody tree = randomTree(rng, GetParam().joints, GetParam().floating);
    const TreeState s = randomState(rng, tree);
    auto lagrangian = [&](const TreeState& x) {
      TreeKinematics k;
      treeKinematics(tree, x, k);
      double V = 0.0;
      for (int b = tree.floating() ? 0 : 1; b < tree.bodyCount(); ++b)
        V -= tree.inertiaOf(b).mass() * g.dot(k.M_W[b].translation(kLambda));
      return kineticEnergy(tree, k) - V;
    };
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    BodyMoments grav;
    gravityMoments(tree, kin, g, grav);
    VectorXd grad;
    momentumAndGradient(tree, kin, grav, &grad);
    for (int k = 0; k < tree.jointCount(); ++k) {
      const double d = 1e-5;
      TreeState plus = s, minus = s;
      plus.q[k] += d;
      minus.q[k] -= d;
      const double fd = (lagrangian(plus) - lagrangian(minus)) / (2 * d);
      // Central difference: truncation O(d² L''') ≈ 1e-10·|L|, round-off ε|L|/d ≈ 1e-11·|L|.
      EXPECT_NEAR(grad[k], fd, 1e-7 * (1 + std::abs(fd))) << "joint " << k;
    }
  }
}

// Lagrange: d/dt (M ν) = ∂L/∂q + Q + τ along the motion ABA gives. The time derivative by
// central differences of the momentum map along (q ± δ q̇, ν ± δ ν̇) (base pose along its own
// velocity), so this ties ABA, the momentum map and the gradient together.
TEST_P(RandomTree, MomentumRateIsGradientPlusForces) {
  std::mt19937 rng(41 + GetParam().joints);
  for (int trial = 0; trial < 10; ++trial) {
    const ArticulatedBody tree = randomTree(rng, GetParam().joints, GetParam().floating);
    const TreeState s = randomState(rng, tree);
    const Vector3d g(0.0, 0.0, -9.81);
    const VectorXd tau = VectorXd::Random(tree.jointCount());
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    BodyMoments grav;
    gravityMoments(tree, kin, g, grav);
    const VectorXd nu_dot = forwardDynamics(tree, s, kin, tau, grav);
    VectorXd grad;
    momentumAndGradient(tree, kin, grav, &grad);
    auto momentum_at = [&](double t) {
      TreeState x = s;
      x.q = s.q + t * s.v;
      if (tree.floating()) x.M_W0 = s.M_W0 * cga::exp(s.omega_0 * (-0.5 * t));
      setVelocityVector(tree, velocityVector(tree, s) + t * nu_dot, x);
      TreeKinematics k;
      treeKinematics(tree, x, k);
      const VectorXd p = momentumAndGradient(tree, k, BodyMoments(tree.bodyCount()), nullptr);
      // The base momentum in world axes: its rate is the external wrench (Euler's law).
      if (!tree.floating()) return p;
      VectorXd out = p;
      const cga::Moment Pw = x.M_W0.apply(cga::Moment(p.head<3>(), p.segment<3>(3)), kLambda);
      out.head<3>() = Pw.rot;
      out.segment<3>(3) = Pw.trans;
      return out;
    };
    const double d = 1e-5;
    const VectorXd rate = (momentum_at(d) - momentum_at(-d)) / (2 * d);
    // Second-order difference of smooth functions of size O(10): truncation ≈ 1e-9.
    if (tree.jointCount() > 0) {
      EXPECT_LT((rate.tail(tree.jointCount()) - grad - tau).cwiseAbs().maxCoeff(),
                1e-6 * (1 + rate.norm()));
    }
    if (tree.floating()) {
      // Total gravity wrench about the world origin: Σ (x_b × m_b g, λ m_b g).
      cga::Moment W;
      for (int b = 0; b < tree.bodyCount(); ++b) {
        const double m = tree.inertiaOf(b).mass();
        W += cga::Moment(kin.M_W[b].translation(kLambda).cross(m * g), kLambda * m * g);
      }
      EXPECT_LT((rate.head<3>() - W.rot).cwiseAbs().maxCoeff(), 1e-6 * (1 + rate.norm()));
      EXPECT_LT((rate.segment<3>(3) - W.trans).cwiseAbs().maxCoeff(), 1e-6 * (1 + rate.norm()));
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Trees, RandomTree,
                         ::testing::Values(TreeCase{1, false}, TreeCase{2, false},
                                           TreeCase{7, false}, TreeCase{12, false},
                                           TreeCase{0, true}, TreeCase{3, true},
                                           TreeCase{9, true}));

TEST(AdjointMatrix, IsTheMotorSandwichOnBivectorsAndItsInverseTransposeOnMoments) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 50; ++trial) {
    const cga::Motor M = randomMotor(rng, 3.0);
    const cga::Bivelocity B(randomVector(rng, 2), randomVector(rng, 2));
    const cga::Moment T(randomVector(rng, 2), randomVector(rng, 2));
    const Eigen::Matrix<double, 6, 6> X = adjointMatrix(M, kLambda);
    Eigen::Matrix<double, 6, 1> b, t;
    b << B.rot, B.trans;
    t << T.rot, T.trans;
    const cga::Bivelocity MB = M.apply(B);
    const cga::Moment MT = M.apply(T, kLambda);
    const Eigen::Matrix<double, 6, 1> xb = X * b, xt = X.inverse().transpose() * t;
    EXPECT_LT((xb.head<3>() - MB.rot).norm() + (xb.tail<3>() - MB.trans).norm(), 1e-13);
    EXPECT_LT((xt.head<3>() - MT.rot).norm() + (xt.tail<3>() - MT.trans).norm(), 1e-12);
  }
}

// A rod of mass m, length ℓ hanging from a hinge at one end: θ̈ = −(m g ℓ/2)/(J + m ℓ²/4) sin θ
// (θ from straight down), the textbook compound pendulum.
TEST(Pendulum, AbaGivesTheCompoundPendulumAcceleration) {
  const double m = 1.3, l = 0.9, r = 0.02, g = 9.81;
  const double J = m * l * l / 12 + m * r * r / 4;
  TreeJoint j;
  j.axis = Vector3d::UnitY();
  j.M_PJ = cga::Motor::translator({0, 0, 2.0}, kLambda);
  j.M_JC = cga::Motor::translator({0, 0, -l / 2}, kLambda);  // child frame at the CoM
  j.inertia = Inertia::fromPrincipal("rod", m, {J, J, m * r * r / 2}).value();
  const ArticulatedBody tree(std::nullopt, {j}, kLambda);
  for (double theta : {0.1, 1.0, 2.5}) {
    TreeState s;
    s.q = VectorXd::Constant(1, theta);
    s.v = VectorXd::Constant(1, 0.7);
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    BodyMoments grav;
    gravityMoments(tree, kin, {0, 0, -g}, grav);
    const double qdd = forwardDynamics(tree, s, kin, VectorXd::Zero(1), grav)[0];
    // Rotation by +θ about +y moves the CoM (0, 0, −ℓ/2) towards −x… the sign of sin θ
    // follows: the torque of gravity about +y is −m g (ℓ/2) sin θ.
    EXPECT_NEAR(qdd, -(m * g * l / 2) / (J + m * l * l / 4) * std::sin(theta), 1e-13);
  }
}

}  // namespace articulated_body_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
