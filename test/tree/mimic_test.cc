// Mimic joints (articulated_body.h, doc/articulated.md#mimic-joints): a follower's position is
// m q_leader + o, exactly, in every tree integrator. Truths: the hand-reduced model (a gear pair
// of pendulums, whose one coordinate obeys I_eff q̈ = −∂V/∂q + τ_l + m τ_f with I_eff = I_l + m²
// I_f, integrated by a fine RK4 as an independent method), the constant-effort motion in closed
// form, energy and momentum conservation, d'Alembert's principle for the accelerations, the limits
// of both joints.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "cga_rigid_sim/tree/articulated_body.h"
#include "cga_rigid_sim/tree/tree_integrator.h"
#include "common/random_trees.h"
#include "common/tree_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace mimic_test {

const char* const kIntegrators[] = {"auto", "cga2", "cga4", "rk4", "euler"};
constexpr double kLambda = 1.0, kG = 9.81;
using Eigen::Vector3d;
using Eigen::VectorXd;

// A rod of mass m and length ℓ hinged at one end about y at `pivot`, hanging along −z.
TreeJoint rod(const Vector3d& pivot, double m, double l) {
  TreeJoint j;
  j.parent = 0;
  j.axis = Vector3d::UnitY();
  j.M_PJ = cga::Motor::translator(pivot, kLambda);
  j.M_JC = cga::Motor::translator({0, 0, -l / 2}, kLambda);
  const double r = 0.02, J = m * l * l / 12 + m * r * r / 4;
  j.inertia = Inertia::fromPrincipal("rod", m, {J, J, m * r * r / 2}).value();
  return j;
}

// Moment of a rod() about its pivot.
double pivotMoment(const TreeJoint& j, double m, double l) {
  return j.inertia.principalMoments().y() + m * l * l / 4;
}

// The gear pair: a leader pendulum (1 kg, 1 m) and, 0.5 m beside it, a follower pendulum
// (0.5 kg, 0.6 m) turned by multiplier m (default −2) and offset o.
ArticulatedBody gearPair(double m = -2.0, double o = 0.0) {
  TreeJoint leader = rod({0, 0, 0}, 1.0, 1.0);
  TreeJoint follower = rod({0.5, 0, 0}, 0.5, 0.6);
  follower.mimic = 0;
  follower.mimic_multiplier = m;
  follower.mimic_offset = o;
  return ArticulatedBody(std::nullopt, {leader, follower}, kLambda);
}

TreeLoads loadsOf(const ArticulatedBody& tree, double g = kG) {
  TreeLoads loads;
  loads.gravity_W = {0, 0, -g};
  loads.effort = VectorXd::Zero(tree.jointCount());
  return loads;
}

// The state of the pair with the leader at (q, v): the follower where the constraint puts it.
TreeState pairState(const ArticulatedBody& tree, double q, double v) {
  TreeState s;
  s.q = VectorXd::Zero(tree.jointCount());
  s.v = VectorXd::Zero(tree.jointCount());
  s.q[0] = q;
  s.v[0] = v;
  applyMimic(tree, s);
  return s;
}

const auto make = testing::treeIntegrator;
const auto energy = testing::treeEnergy;

// |q_f − (m q_l + o)| and |q̇_f − m q̇_l| over every follower, in units of the rounding of
// m q_l + o (one ulp of the larger of |m q_l| and |o|, at least the smallest normal number).
double constraintUlps(const ArticulatedBody& tree, const TreeState& s) {
  double worst = 0.0;
  for (int k = 0; k < tree.jointCount(); ++k) {
    const TreeJoint& j = tree.joints()[k];
    if (j.mimic < 0) continue;
    const double mq = j.mimic_multiplier * s.q[j.mimic], mv = j.mimic_multiplier * s.v[j.mimic];
    const double ulp_q =
        std::max(std::abs(mq), std::abs(j.mimic_offset)) * std::numeric_limits<double>::epsilon();
    const double ulp_v = std::abs(mv) * std::numeric_limits<double>::epsilon();
    worst = std::max(worst, std::abs(s.q[k] - (mq + j.mimic_offset)) /
                                std::max(ulp_q, std::numeric_limits<double>::min()));
    worst = std::max(worst,
                     std::abs(s.v[k] - mv) / std::max(ulp_v, std::numeric_limits<double>::min()));
  }
  return worst;
}

TEST(MimicJoints, TheTreeMapsEachJointToItsLeadersCoordinate) {
  const ArticulatedBody tree = gearPair(-2.0, 0.1);
  EXPECT_TRUE(tree.hasMimic());
  EXPECT_EQ(tree.velocityCount(), 2);
  EXPECT_EQ(tree.reducedCount(), 1);
  EXPECT_EQ(tree.reducedIndex(0), 0);
  EXPECT_EQ(tree.reducedIndex(1), 0);
  EXPECT_EQ(tree.mimicMultiplier(1), -2.0);
  EXPECT_EQ(tree.mimicOffset(1), 0.1);
  // G = (1, −2)ᵀ: Gᵀ M G of a diagonal M, and Gᵀ f.
  Eigen::MatrixXd M(2, 2), M_r;
  M << 3, 1, 1, 5;
  reduceMatrix(tree, M, M_r);
  ASSERT_EQ(M_r.rows(), 1);
  EXPECT_EQ(M_r(0, 0), 3 - 2 * 1 - 2 * 1 + 4 * 5);
  VectorXd f(2), f_r, nu;
  f << 1, 2;
  reduceForce(tree, f, f_r);
  EXPECT_EQ(f_r[0], 1 - 4);
  expandVelocity(tree, VectorXd::Constant(1, 0.5), nu);
  EXPECT_EQ(nu[0], 0.5);
  EXPECT_EQ(nu[1], -1.0);
}

// d'Alembert: the constrained accelerations lie in ν = G ν_r, and the forces the RNEA needs for
// them differ from the efforts by a constraint force that does no work on any allowed motion:
// Gᵀ (RNEA(ν̇) − τ) = 0. Random trees (fixed and floating) with random mimic pairs.
TEST(MimicJoints, ForwardDynamicsObeysDAlembertOnRandomTrees) {
  std::mt19937 rng(36);
  for (int trial = 0; trial < 20; ++trial) {
    const bool floating = trial % 2 == 1;
    const ArticulatedBody plain = testing::randomTree(rng, 6, floating, kLambda);
    std::vector<TreeJoint> joints = plain.joints();
    // Joints 3 and 5 follow 1 (and 1 stays independent).
    std::uniform_real_distribution<double> u(-2, 2);
    for (int k : {3, 5}) {
      joints[k].mimic = 1;
      joints[k].mimic_multiplier = u(rng);
      joints[k].mimic_offset = u(rng);
    }
    const ArticulatedBody tree(plain.baseInertia(), joints, kLambda);
    TreeState s;
    s.q = VectorXd::Random(6);
    s.v = VectorXd::Random(6);
    s.omega_0 = cga::Bivelocity(testing::randomVector(rng, 1), testing::randomVector(rng, 1));
    applyMimic(tree, s);
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    BodyMoments f;
    gravityMoments(tree, kin, {0, 0, -kG}, f);
    const VectorXd tau = VectorXd::Random(6);
    VectorXd nu_dot;
    forwardDynamics(tree, s, kin, tau, f, nu_dot);
    const int base = floating ? 6 : 0;
    for (int k : {3, 5})
      EXPECT_NEAR(nu_dot[base + k], joints[k].mimic_multiplier * nu_dot[base + 1],
                  1e-12 * (1 + nu_dot.cwiseAbs().maxCoeff()));
    VectorXd residual = inverseDynamics(tree, s, kin, nu_dot, f);
    residual.tail(6) -= tau;
    VectorXd reduced;
    reduceForce(tree, residual, reduced);
    // Round-off of forces of order |M ν̇| ≈ 10: a few 1e-14.
    EXPECT_LT(reduced.cwiseAbs().maxCoeff(), 1e-11 * (1 + residual.cwiseAbs().maxCoeff()))
        << "trial " << trial;
  }
}

// The hand-reduced model of the gear pair: one coordinate q with
//   I_eff q̈ = −m_l g d_l sin q − m_f g d_f m sin(m q + o) + τ_l + m τ_f,  I_eff = I_l + m² I_f,
// (d the pivot–centre distances), integrated by RK4 at h/50 as the truth. Each integrator at
// h = 1 ms follows it to its order (measured after 2 s: cga2 5.4e-6 rad, second order; cga4
// 4.0e-11 and rk4 9.8e-12, fourth; euler 3.8e-3, first); the bounds give each a factor ≥ 4.
TEST(MimicJoints, TheGearPairMovesAsTheHandReducedModel) {
  const double m = -2.0, o = 0.3;
  const ArticulatedBody tree = gearPair(m, o);
  const double I_eff =
      pivotMoment(tree.joints()[0], 1.0, 1.0) + m * m * pivotMoment(tree.joints()[1], 0.5, 0.6);
  const double tau_l = 0.4, tau_f = -0.3;
  const auto accel = [&](double q) {
    return (-1.0 * kG * 0.5 * std::sin(q) - 0.5 * kG * 0.3 * m * std::sin(m * q + o) + tau_l +
            m * tau_f) /
           I_eff;
  };
  const double T = 2.0, h = 1e-3;
  // The truth.
  double q = 0.8, v = 0.0;
  const int fine = 50 * static_cast<int>(std::lround(T / h));
  const double hf = T / fine;
  for (int k = 0; k < fine; ++k) {
    const double k1q = v, k1v = accel(q);
    const double k2q = v + 0.5 * hf * k1v, k2v = accel(q + 0.5 * hf * k1q);
    const double k3q = v + 0.5 * hf * k2v, k3v = accel(q + 0.5 * hf * k2q);
    const double k4q = v + hf * k3v, k4v = accel(q + hf * k3q);
    q += hf / 6 * (k1q + 2 * k2q + 2 * k3q + k4q);
    v += hf / 6 * (k1v + 2 * k2v + 2 * k3v + k4v);
  }
  TreeLoads loads = loadsOf(tree);
  loads.effort << tau_l, tau_f;
  for (const char* name : kIntegrators) {
    auto integ = make(name);
    TreeState s = pairState(tree, 0.8, 0.0);
    for (int k = 0; k < std::lround(T / h); ++k) integ->step(tree, loads, h, s);
    const std::string n = name;
    const double tol = n == "euler" ? 2e-2 : (n == "cga2" || n == "auto") ? 2e-5 : 2e-10;
    EXPECT_NEAR(s.q[0], q, tol) << name;
    EXPECT_NEAR(s.v[0], v, 5 * tol) << name;
    EXPECT_LE(constraintUlps(tree, s), 2.0) << name;
  }
}

// Every integrator holds the constraint to the rounding of m q_l + o at every step of 10 s of a
// swinging gear pair (a floating tree too: the satellite's panels deploying symmetrically), and
// the variational ones keep the energy of the undamped pair in a band without drift.
TEST(MimicJoints, ConstraintHeldToRoundOffAndEnergyKeptOverTenSeconds) {
  const ArticulatedBody tree = gearPair(-2.0, 0.3);
  for (const char* name : kIntegrators) {
    auto integ = make(name);
    TreeState s = pairState(tree, 1.2, 0.5);
    const double E0 = energy(tree, s, {0, 0, -kG});
    double worst_ulps = 0.0, band_early = 0.0, band_late = 0.0;
    const int steps = 10000;
    for (int k = 0; k < steps; ++k) {
      integ->step(tree, loadsOf(tree), 1e-3, s);
      worst_ulps = std::max(worst_ulps, constraintUlps(tree, s));
      const double dE = std::abs(energy(tree, s, {0, 0, -kG}) - E0);
      (k < steps / 10 ? band_early : band_late) =
          std::max(k < steps / 10 ? band_early : band_late, dE);
    }
    EXPECT_LE(worst_ulps, 2.0) << name;
    const std::string n = name;
    if (n == "cga2" || n == "auto" || n == "cga4") {
      // Symplectic: a band of O((ωh)²) (cga4: O((ωh)⁴)) of the energy, no wider at the end than
      // in the first second beyond the sampling of the band. Measured: cga2 4.7e-6 J, cga4
      // 1.8e-10 J (the pair's energy scale m g ℓ ≈ 5 J); the bounds give a factor ≥ 4.
      EXPECT_LT(band_late, n == "cga4" ? 1e-9 : 2e-5) << name;
      EXPECT_LT(band_late, 1.5 * band_early + 1e-12) << name << " early " << band_early;
    }
  }
}

TEST(MimicJoints, FloatingTreeWithMimicPanelsConservesMomentumInZeroGravity) {
  const Inertia bus = Inertia::fromPrincipal("bus", 100, Vector3d::Constant(100.0 / 6)).value();
  const auto panel = [](double side) {
    TreeJoint j;
    j.axis = Vector3d::UnitY();
    j.M_PJ = cga::Motor::translator({side * 0.5, 0, 0}, kLambda);
    j.M_JC = cga::Motor::translator({side * 1.0, 0, 0.1}, kLambda);
    const double m = 10, a = 2, b = 0.8, c = 0.02;  // a 2 × 0.8 × 0.02 m plate
    j.inertia = Inertia::fromPrincipal(
                    "panel", m,
                    {m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12})
                    .value();
    return j;
  };
  TreeJoint right = panel(-1);
  right.mimic = 0;
  right.mimic_multiplier = -1.0;
  const ArticulatedBody tree(bus, {panel(1), right}, kLambda);
  for (const char* name : {"cga2", "cga4"}) {
    auto integ = make(name);
    TreeState s = pairState(tree, 0.3, 1.5);
    s.omega_0 = cga::Bivelocity({0.2, -0.4, 0.7}, {0.1, 0.05, -0.2});
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    const cga::Moment P0 = worldMomentum(tree, kin);
    double worst = 0.0, worst_ulps = 0.0;
    for (int k = 0; k < 10000; ++k) {
      integ->step(tree, loadsOf(tree, 0.0), 1e-3, s);
      treeKinematics(tree, s, kin);
      const cga::Moment P = worldMomentum(tree, kin);
      worst = std::max(worst, (P.rot - P0.rot).norm() + (P.trans - P0.trans).norm());
      worst_ulps = std::max(worst_ulps, constraintUlps(tree, s));
    }
    // As without mimic joints (tree_integrator_test.cc): Π carried unchanged, the reported
    // momentum recomputed from the velocities solved from it, round-off per step.
    EXPECT_LT(worst, 1e-12) << name;
    EXPECT_LE(worst_ulps, 2.0) << name;
  }
}

// Two discs about parallel z axes 1 m apart, no gravity torque: the leader (J_z 0.2) and a
// follower (J_z 0.03) turned by `multiplier`.
ArticulatedBody discPair(double multiplier, double follower_damping = 0.0) {
  TreeJoint a, b;
  a.axis = b.axis = Vector3d::UnitZ();
  b.M_PJ = cga::Motor::translator({1, 0, 0}, kLambda);
  a.inertia = Inertia::fromPrincipal("a", 2.0, {0.1, 0.1, 0.2}).value();
  b.inertia = Inertia::fromPrincipal("b", 1.0, {0.02, 0.02, 0.03}).value();
  b.mimic = 0;
  b.mimic_multiplier = multiplier;
  b.damping = follower_damping;
  return ArticulatedBody(std::nullopt, {a, b}, kLambda);
}

// A constant effort on the follower alone, no gravity, discs on separate axes: the leader turns
// at q̈ = m τ_f / I_eff, q = ½ q̈ t². The midpoint is exact for constant acceleration (round-off);
// rk4 too (q is a polynomial of degree 2).
TEST(MimicJoints, AnEffortOnTheFollowerMovesTheLeaderThroughTheMultiplier) {
  const ArticulatedBody tree = discPair(3.0);
  const double I_eff = 0.2 + 9 * 0.03, tau_f = 0.5, acc = 3.0 * tau_f / I_eff;
  for (const char* name : {"cga2", "cga4", "rk4"}) {
    auto integ = make(name);
    TreeLoads loads = loadsOf(tree, 0.0);
    loads.effort[1] = tau_f;
    TreeState s = pairState(tree, 0.0, 0.0);
    for (int k = 0; k < 1000; ++k) integ->step(tree, loads, 1e-3, s);
    EXPECT_NEAR(s.q[0], 0.5 * acc, 1e-11) << name;
    EXPECT_NEAR(s.v[0], acc, 1e-11) << name;
    EXPECT_EQ(s.q[1], 3.0 * s.q[0]) << name;
  }
}

// The follower's damping c_f acts on the leader's coordinate as m² c_f: with no other load the
// midpoint multiplies the rate by (1 − x)/(1 + x) per step, x = m² c_f h / (2 I_eff).
TEST(MimicJoints, DampingOfTheFollowerActsThroughTheSquaredMultiplier) {
  const ArticulatedBody tree = discPair(-2.0, 0.01);
  const double I_eff = 0.2 + 4 * 0.03, h = 1e-3, x = 4 * 0.01 * h / (2 * I_eff);
  auto integ = make("cga2");
  TreeState s = pairState(tree, 0.0, 3.0);
  for (int k = 0; k < 500; ++k) integ->step(tree, loadsOf(tree, 0.0), h, s);
  EXPECT_NEAR(s.v[0] / (3.0 * std::pow((1 - x) / (1 + x), 500)), 1.0, 1e-12);
  EXPECT_EQ(s.v[1], -2.0 * s.v[0]);
}

// Limits of both joints hold: the follower (m = −2) reaches its limit −0.5 when the leader is at
// 0.25, before the leader's own limit 1; an effort keeps pushing the leader that way.
TEST(MimicJoints, TheLimitsOfLeaderAndFollowerBothHold) {
  TreeJoint leader = rod({0, 0, 0}, 1.0, 1.0), follower = rod({0.5, 0, 0}, 0.5, 0.6);
  leader.lower = -1.0;
  leader.upper = 1.0;
  follower.lower = -0.5;
  follower.upper = 0.5;
  follower.mimic = 0;
  follower.mimic_multiplier = -2.0;
  const ArticulatedBody tree(std::nullopt, {leader, follower}, kLambda);
  ASSERT_EQ(tree.coordinates().size(), 1u);
  EXPECT_EQ(tree.coordinates()[0].lower, -0.25);
  EXPECT_EQ(tree.coordinates()[0].upper, 0.25);
  for (const char* name : kIntegrators) {
    auto integ = make(name);
    TreeLoads loads = loadsOf(tree);
    loads.effort[0] = 20.0;
    TreeState s = pairState(tree, 0.0, 0.0);
    double highest = 0.0, lowest_f = 0.0;
    for (int k = 0; k < 2000; ++k) {
      integ->step(tree, loads, 1e-3, s);
      highest = std::max(highest, s.q[0]);
      lowest_f = std::min(lowest_f, s.q[1]);
    }
    EXPECT_LE(highest, 0.25) << name;
    EXPECT_GE(lowest_f, -0.5) << name;
    // It reaches the stop (cga4: within ½ a (γ2 h)² ≈ 6e-5 rad of it, a ≈ 40 rad/s² the push:
    // the triple jump's middle substep runs backwards, γ2 = −1.70, and leaves the stop a
    // first substep reached).
    EXPECT_NEAR(highest, 0.25, std::string(name) == "cga4" ? 1e-4 : 1e-12) << name;
    EXPECT_LE(constraintUlps(tree, s), 2.0) << name;
  }
}

TEST(MimicJoints, AnImpulseMovesTheTreeWithinTheConstraint) {
  const ArticulatedBody tree = gearPair(-2.0, 0.3);
  const TreeState s = pairState(tree, 0.4, 0.0);
  // A push on the follower's link, and on the leader's.
  for (int body : {1, 2}) {
    const VectorXd dnu = impulseResponse(tree, s, body, cga::Moment({0.1, 0.7, -0.2}, {1, 0, 0}));
    EXPECT_NEAR(dnu[1], -2.0 * dnu[0], 1e-15 * (1 + std::abs(dnu[1])));
    EXPECT_NE(dnu[0], 0.0);
  }
}

}  // namespace mimic_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
