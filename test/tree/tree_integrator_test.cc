// Tests of the tree integrators (tree/tree_integrator.h) against analytic solutions and
// conservation laws: the large-amplitude pendulum period, the energy of an undamped double
// pendulum over 10⁶ steps, the momentum of a floating tree in zero gravity, implicit damping,
// Coulomb friction, position limits, a floating base without joints against the free-body
// integrator, and the methods against each other.
#include "cga_rigid_sim/tree/tree_integrator.h"

#include <gtest/gtest.h>

#include <boost/math/special_functions/ellint_1.hpp>
#include <cmath>
#include <cstdio>

#include "cga_rigid_sim/body/integrator.h"
#include "common/random_trees.h"
#include "common/tree_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace tree_integrator_test {

using Eigen::Vector3d;
using Eigen::VectorXd;

constexpr double kLambda = 1.0;
constexpr double kG = 9.81;

// A rod of mass m and length ℓ hinged at one end about y, hanging along −z from (0, 0, z0).
TreeJoint rodJoint(int parent, const cga::Motor& M_PJ, double m, double l) {
  TreeJoint j;
  j.parent = parent;
  j.axis = Vector3d::UnitY();
  j.M_PJ = M_PJ;
  j.M_JC = cga::Motor::translator({0, 0, -l / 2}, kLambda);
  const double r = 0.02, J = m * l * l / 12 + m * r * r / 4;
  j.inertia = Inertia::fromPrincipal("rod", m, {J, J, m * r * r / 2}).value();
  return j;
}

ArticulatedBody doublePendulum() {
  return ArticulatedBody(std::nullopt,
                         {rodJoint(0, cga::Motor::translator({0, 0, 2}, kLambda), 1.0, 1.0),
                          rodJoint(1, cga::Motor::translator({0, 0, -0.5}, kLambda), 1.0, 1.0)},
                         kLambda);
}

TreeLoads gravityOnly(const ArticulatedBody& tree, double g = kG) {
  TreeLoads loads;
  loads.gravity_W = {0, 0, -g};
  loads.effort = VectorXd::Zero(tree.jointCount());
  return loads;
}

TreeState jointState(std::initializer_list<double> q, std::initializer_list<double> v) {
  TreeState s;
  s.q = Eigen::Map<const VectorXd>(q.begin(), static_cast<Eigen::Index>(q.size()));
  s.v = Eigen::Map<const VectorXd>(v.begin(), static_cast<Eigen::Index>(v.size()));
  return s;
}

const auto energy = testing::treeEnergy;
const auto make = testing::treeIntegrator;

// Period of a compound pendulum at amplitude θ0: T = 4 √(I_p/(m g d)) K(sin(θ0/2)), I_p its
// moment about the pivot, d the pivot–CoM distance (the simple pendulum with L = I_p/(m d)).
TEST(TreeIntegrator, LargeAmplitudePendulumKeepsTheExactPeriod) {
  const double m = 1.0, l = 1.0;
  const ArticulatedBody tree(std::nullopt, {rodJoint(0, cga::Motor(), m, l)}, kLambda);
  const double Ip = tree.joints()[0].inertia.principalMoments().y() + m * l * l / 4;
  const double theta0 = 2.5;  // 143°: far from the small-angle period (by 36 %)
  const double exact =
      4 * std::sqrt(Ip / (m * kG * l / 2)) * boost::math::ellint_1(std::sin(theta0 / 2));
  for (const char* name : {"cga2", "cga4", "rk4"}) {
    auto integ = make(name);
    TreeState s = jointState({theta0}, {0.0});
    const double h = 1e-3;
    // Time of the 4th downward zero crossing = 3.75 periods after release… use crossings of
    // θ = 0 with θ̇ < 0: the first at T/4, the (k+1)-th at T/4 + kT.
    std::vector<double> crossings;
    for (int step = 0; step < 40000 && crossings.size() < 5; ++step) {
      const double q0 = s.q[0];
      integ->step(tree, gravityOnly(tree), h, s);
      if (q0 > 0 && s.q[0] <= 0)  // linear interpolation: θ'' = 0 at θ = 0, error O(h³)
        crossings.push_back((step + q0 / (q0 - s.q[0])) * h);
    }
    ASSERT_EQ(crossings.size(), 5u) << name;
    const double period = (crossings[4] - crossings[0]) / 4;
    // Second-order methods: phase error ≈ (ω h)²/12 per radian of phase, ≈ 1e-6 relative here;
    // the fourth-order ones reach the interpolation error (≈ 1e-9).
    const double tol = std::string(name) == "cga2" ? 3e-6 : 2e-9;
    EXPECT_NEAR(period / exact, 1.0, tol) << name << ": period " << period << " exact " << exact;
  }
}

// A symplectic method keeps the energy of a Hamiltonian system within a band of width O(h²)
// forever, without drift; a chaotic double pendulum is the hard case.
TEST(TreeIntegrator, UndampedDoublePendulumEnergyIsBoundedWithoutDriftOverAMillionSteps) {
  const ArticulatedBody tree = doublePendulum();
  auto integ = make("cga2");
  TreeState s = jointState({1.0, 0.5}, {0.0, 0.0});
  const double E0 = energy(tree, s, {0, 0, -kG});
  const double h = 1e-3;
  const int steps = 1000000;
  double worst = 0.0, early = 0.0, late = 0.0;
  for (int k = 0; k < steps; ++k) {
    integ->step(tree, gravityOnly(tree), h, s);
    if (k % 100 != 0) continue;
    const double e = energy(tree, s, {0, 0, -kG}) - E0;
    worst = std::max(worst, std::abs(e));
    if (k < steps / 10) early = std::max(early, std::abs(e));
    if (k >= steps - steps / 10) late = std::max(late, std::abs(e));
  }
  // The band: O((ω h)²) of the energy scale m g ℓ ≈ 10 J, with ω up to ≈ 10 rad/s in the
  // chaotic motion: ≈ 1e-3·10 J·(1/12)… measured 3.9e-4 J at h = 1 ms. No drift: the last tenth's
  // band is no wider than the first tenth's (a drifting method, e.g. rk4, widens it steadily; a 20
  // % margin covers the chaotic sampling).
  EXPECT_LT(worst, 1e-3);
  EXPECT_LT(late, 1.2 * early + 1e-9) << "early " << early << " late " << late;
}

// rk4 adds each step's increment to q and ν by compensated sums (tree_integrator_explicit.cc),
// so that over many small steps their roundings do not add up. Truth: the energy, which the
// exact flow keeps; rk4's own energy error is its O(h⁴) truncation, ≈ 1e-15 relative over these
// 5 s at h = 5e-5 s (3.9e-10 over 10 s at h = 1 ms, scaled by h⁴ and halved). Measured over the
// 1e5 steps: 4.6e-16 with the compensation, 7.1e-15 with plain sums (the roundings of q and ν
// adding up). Bound: 2e-15, twice the truncation's estimate and a third of the plain sums'.
TEST(TreeIntegrator, Rk4RoundOffDoesNotAddUpOverManySmallSteps) {
  const ArticulatedBody tree = doublePendulum();
  auto integ = make("rk4");
  TreeState s = jointState({1.0, 0.5}, {0.0, 0.0});
  const double E0 = energy(tree, s, {0, 0, -kG});
  double worst = 0.0;
  for (int k = 1; k <= 100000; ++k) {
    integ->step(tree, gravityOnly(tree), 5e-5, s);
    if (k % 1000 == 0)
      worst = std::max(worst, std::abs(energy(tree, s, {0, 0, -kG}) - E0) / std::abs(E0));
  }
  std::printf("[ info ] rk4, 1e5 steps of 5e-5 s: energy drift %.2e relative\n", worst);
  EXPECT_LE(worst, 2e-15);
}

// The midpoint's iteration starts each step from ν̄ extrapolated from the last steps and stops
// once the next correction would be below round-off (tree_integrator_midpoint.cc), estimated
// from the last two corrections or, after one pass, from the ratio measured in earlier steps.
// Whatever the start and however few its passes, each step must be the root of the midpoint
// equations: the same step taken from a copy of the state by a fresh integrator — which starts from
// ν, an O(h) miss, and so iterates to the end (5–6 passes, its last correction ≈ 1e-18) — must
// agree to round-off, over a run long enough for the extrapolation to reach its highest degree. A
// fixed-base random tree (the fused residual) and a floating one (the general path), 7 joints,
// at h = 1 ms.
TEST(TreeIntegrator, EveryStepIsTheConvergedMidpointStepWhateverTheIterationsStart) {
  std::mt19937 rng(11);
  for (const bool floating : {false, true}) {
    const ArticulatedBody tree = testing::randomTree(rng, 7, floating, kLambda);
    auto integ = make("cga2");
    TreeState s;
    s.q = VectorXd::LinSpaced(7, -0.6, 0.6);
    s.v = VectorXd::LinSpaced(7, 1.5, -1.0);
    if (floating) s.omega_0 = cga::Bivelocity({0.2, -0.4, 0.7}, {0.1, 0.05, -0.2});
    const TreeLoads loads = gravityOnly(tree);
    double worst_v = 0.0, worst_q = 0.0;
    int one_pass = 0;
    for (int k = 0; k < 400; ++k) {
      TreeState fresh = s;
      make("cga2")->step(tree, loads, 1e-3, fresh);
      integ->step(tree, loads, 1e-3, s);
      one_pass += integ->lastIterations() == 1;
      const double scale = 1.0 + fresh.v.cwiseAbs().maxCoeff();
      worst_v = std::max(worst_v, (s.v - fresh.v).cwiseAbs().maxCoeff() / scale);
      worst_q = std::max(worst_q, (s.q - fresh.q).cwiseAbs().maxCoeff());
      if (floating)
        worst_v = std::max(worst_v, ((s.omega_0.rot - fresh.omega_0.rot).norm() +
                                     (s.omega_0.trans - fresh.omega_0.trans).norm()) /
                                        scale);
    }
    // Round-off: the rates agree to a few ulps of their scale times the conditioning of the
    // solve (measured 4e-15 fixed, 2.6e-14 floating), the positions to an ulp of |q| ≤ 1 (they
    // move by h ν̄). A step stopped one pass early (after two) misses by 4e-12 and 7e-10.
    EXPECT_LT(worst_v, 1e-13) << "floating " << floating;
    EXPECT_LT(worst_q, 2e-15) << "floating " << floating;
    // And the one-pass stop (the ratio of earlier steps times the first correction below the
    // tolerance) is what most of these steps take — 393 and 378 of 400 when written — so the
    // agreement above covers it.
    EXPECT_GT(one_pass, 300) << "floating " << floating;
  }
}

// A contact step's drift starts from the state its kick left, handed over with its kinematics
// and M (startFrom), and from the last drift's ν̄ − ν added to ν. Whatever it starts from, the
// drift must be the converged midpoint step: the same step by a fresh integrator, which starts
// from ν itself, agrees to round-off (the tolerances of the test above). A floating random tree
// of 7 joints drifting without gravity, its rates changed before every step as contact impulses
// change them; and the warm start must save passes over the run.
TEST(TreeIntegrator, ContactDriftsFromTheLastDriftsOffsetAreTheConvergedSteps) {
  std::mt19937 rng(5);
  const ArticulatedBody tree = testing::randomTree(rng, 7, true, kLambda);
  auto integ = make("cga2");
  TreeState s;
  s.q = VectorXd::LinSpaced(7, -0.6, 0.6);
  s.v = VectorXd::LinSpaced(7, 1.5, -1.0);
  s.omega_0 = cga::Bivelocity({0.2, -0.4, 0.7}, {0.1, 0.05, -0.2});
  TreeLoads drift;  // no gravity, no efforts: a contact step's drift
  drift.effort = VectorXd::Zero(7);
  std::normal_distribution<double> kick(0.0, 0.01);
  double worst_v = 0.0, worst_q = 0.0;
  int warm_passes = 0, cold_passes = 0;
  TreeKinematics kin;
  Eigen::MatrixXd M;
  for (int k = 0; k < 200; ++k) {
    for (int i = 0; i < 7; ++i) s.v[i] += kick(rng);  // the contact impulses of the step
    treeKinematics(tree, s, kin);
    massMatrix(tree, kin, M);
    TreeState fresh = s;
    auto cold = make("cga2");
    cold->startFrom(fresh, kin, &M);
    cold->step(tree, drift, 1e-3, fresh);
    integ->reset();  // as the World resets it after each contact step
    integ->startFrom(s, kin, &M);
    integ->step(tree, drift, 1e-3, s);
    warm_passes += integ->lastIterations();
    cold_passes += cold->lastIterations();
    const double scale = 1.0 + fresh.v.cwiseAbs().maxCoeff();
    worst_v = std::max(worst_v, (s.v - fresh.v).cwiseAbs().maxCoeff() / scale);
    worst_v = std::max(worst_v, ((s.omega_0.rot - fresh.omega_0.rot).norm() +
                                 (s.omega_0.trans - fresh.omega_0.trans).norm()) /
                                    scale);
    worst_q = std::max(worst_q, (s.q - fresh.q).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(worst_v, 1e-13);
  EXPECT_LT(worst_q, 2e-15);
  EXPECT_LT(warm_passes, cold_passes);
  std::printf("contact drifts: %d passes warm, %d cold over 200 steps\n", warm_passes, cold_passes);
}

ArticulatedBody satellite() {
  // A 100 kg bus with two 10 kg panels hinged about y at its ±x faces.
  const Inertia bus = Inertia::fromPrincipal("bus", 100, Vector3d::Constant(100.0 / 6)).value();
  auto panel = [](double side) {
    TreeJoint j;
    j.parent = 0;
    j.axis = Vector3d::UnitY();
    j.M_PJ = cga::Motor::translator({side * 0.5, 0, 0}, kLambda);
    j.M_JC = cga::Motor::translator({side * 1.0, 0, 0}, kLambda);
    const double m = 10, a = 2, b = 0.8, c = 0.02;
    j.inertia = Inertia::fromPrincipal(
                    "panel", m,
                    {m * (b * b + c * c) / 12, m * (a * a + c * c) / 12, m * (a * a + b * b) / 12})
                    .value();
    return j;
  };
  return ArticulatedBody(bus, {panel(1), panel(-1)}, kLambda);
}

TEST(TreeIntegrator, FloatingTreeInZeroGravityConservesMomentum) {
  const ArticulatedBody tree = satellite();
  for (const char* name : {"cga2", "cga4"}) {
    auto integ = make(name);
    TreeState s = jointState({0.3, -0.2}, {1.5, -2.0});
    s.omega_0 = cga::Bivelocity({0.2, -0.4, 0.7}, {0.1, 0.05, -0.2});
    TreeKinematics kin;
    treeKinematics(tree, s, kin);
    const cga::Moment P0 = worldMomentum(tree, kin);
    const double E0 = kineticEnergy(tree, kin);
    double worst = 0.0;
    for (int k = 0; k < 20000; ++k) {
      integ->step(tree, gravityOnly(tree, 0.0), 1e-3, s);
      treeKinematics(tree, s, kin);
      const cga::Moment P = worldMomentum(tree, kin);
      worst = std::max(worst, (P.rot - P0.rot).norm() + (P.trans - P0.trans).norm());
    }
    // Π is carried unchanged; the reported momentum is recomputed from the velocities solved
    // from it: round-off of that solve (≈ 1e-15 of |Π| ≈ 30) per step, not accumulating.
    EXPECT_LT(worst, 1e-12) << name;
    // Energy is not exactly conserved (no symplectic form with the base), but bounded.
    EXPECT_NEAR(kineticEnergy(tree, kin), E0, 1e-4 * E0) << name;
  }
}

// A joint with viscous damping c and no other load: q̇(t) = q̇0 exp(−c t / I), I the inertia
// about the axis. The midpoint gives the factor (1 − x)/(1 + x), x = c h /(2I), per step: the
// (2,2) Padé approximant of exp(−2x), stable for every h.
TEST(TreeIntegrator, DampedJointDecaysAtTheAnalyticRateAndStaysStableForAnyStep) {
  TreeJoint j = rodJoint(0, cga::Motor(), 2.0, 0.5);
  j.axis = Vector3d::UnitZ();  // spin about the rod: no gravity torque
  j.damping = 0.01;
  const double I = j.inertia.principalMoments().z();
  const ArticulatedBody tree(std::nullopt, {j}, kLambda);
  auto integ = make("cga2");
  TreeState s = jointState({0.0}, {3.0});
  const double h = 1e-3, T = 0.5;
  for (int k = 0; k < 500; ++k) integ->step(tree, gravityOnly(tree), h, s);
  // The method's own solution: the Padé factor to the 500th power, to round-off.
  const double x = j.damping * h / (2 * I);
  EXPECT_NEAR(s.v[0] / (3.0 * std::pow((1 - x) / (1 + x), 500)), 1.0, 1e-12);
  // Against exp(−c T/I): the factor's error is (2x)³/12 per step, 500·(0.025)³/12 = 6.5e-4
  // relative in all (x = 0.0125: the decay time I/c = 40 ms is only 40 steps).
  EXPECT_NEAR(s.v[0] / (3.0 * std::exp(-j.damping * T / I)), 1.0, 7e-4);
  // c h / I = 1e3: explicit Euler would grow by 1e3 per step; the midpoint stays bounded.
  TreeState big = jointState({0.0}, {3.0});
  integ->reset();
  for (int k = 0; k < 100; ++k) integ->step(tree, gravityOnly(tree), 40.0, big);
  EXPECT_LE(std::abs(big.v[0]), 3.0);
  EXPECT_TRUE(big.allFinite());
}

TEST(TreeIntegrator, CoulombFrictionHoldsASmallerTorqueAndYieldsToALargerOne) {
  TreeJoint j = rodJoint(0, cga::Motor(), 2.0, 0.5);
  j.axis = Vector3d::UnitZ();
  j.friction = 0.5;
  const double I = j.inertia.principalMoments().z();
  const ArticulatedBody tree(std::nullopt, {j}, kLambda);
  auto integ = make("cga2");
  TreeLoads loads = gravityOnly(tree);
  TreeState s = jointState({0.2}, {0.0});
  loads.effort[0] = 0.45;  // below the friction 0.5: nothing moves, exactly
  for (int k = 0; k < 1000; ++k) integ->step(tree, loads, 1e-3, s);
  EXPECT_EQ(s.q[0], 0.2);
  EXPECT_EQ(s.v[0], 0.0);
  loads.effort[0] = 0.8;  // above: angular acceleration (0.8 − 0.5)/I
  for (int k = 0; k < 1000; ++k) integ->step(tree, loads, 1e-3, s);
  // Constant acceleration: the midpoint is exact for it (up to round-off).
  EXPECT_NEAR(s.v[0], (0.8 - 0.5) / I * 1.0, 1e-9);
  EXPECT_NEAR(s.q[0], 0.2 + 0.5 * (0.8 - 0.5) / I, 1e-9);
}

// A pendulum released from horizontal with its lower limit at −0.4 rad: it reaches the limit,
// never passes it, stops there (inelastically) and never gains energy.
TEST(TreeIntegrator, PendulumStopsAtItsLimitWithoutPassingItOrGainingEnergy) {
  TreeJoint j = rodJoint(0, cga::Motor(), 1.0, 1.0);
  j.lower = -0.4;
  j.upper = 3.0;
  const ArticulatedBody tree(std::nullopt, {j}, kLambda);
  for (const char* name : {"cga2", "cga4"}) {
    auto integ = make(name);
    TreeState s = jointState({M_PI / 2}, {0.0});
    const double E0 = energy(tree, s, {0, 0, -kG});
    double lowest = s.q[0], E_prev = E0, rise = 0.0;
    for (int k = 0; k < 3000; ++k) {
      integ->step(tree, gravityOnly(tree), 1e-3, s);
      lowest = std::min(lowest, s.q[0]);
      const double E = energy(tree, s, {0, 0, -kG});
      rise = std::max(rise, E - E_prev);
      E_prev = E;
    }
    EXPECT_GE(lowest, j.lower) << name;
    // Between stops the symplectic band (≈ 1e-5 J at h = 1 ms) shows as small rises and falls;
    // the stop itself takes the impact's kinetic energy out.
    EXPECT_LT(rise, 1e-4) << name;
    // Gravity pulls it towards θ = 0 (straight down), i.e. away from −0.4: after the stop it
    // swings back up; the point is it never went past the limit and lost the impact energy.
    EXPECT_LT(E_prev, E0 - 1.0) << name;
  }
}

// A floating base without joints is a free rigid body: the tree integrator and the free-body
// cga2 agree to their common second order (errors ∝ h²), under a couple fixed in the body.
TEST(TreeIntegrator, FloatingBaseWithoutJointsMovesAsTheFreeBodyIntegrator) {
  const Inertia I = Inertia::fromPrincipal("box", 2.0, {0.1, 0.2, 0.3}).value();
  const ArticulatedBody tree(I, {}, kLambda);
  Loads loads;
  loads.setGravity({0, 0, -kG});
  AppliedLoad couple;
  couple.axes = Axes::kBody;
  couple.couple = {0.05, 0.0, -0.02};
  loads.add(couple);
  TreeLoads tl = gravityOnly(tree);
  tl.applied = {&loads};
  TreeState s;
  s.q.resize(0);
  s.v.resize(0);
  s.omega_0 = cga::Bivelocity({1.0, 4.0, 0.3}, {0.5, 0.0, 2.0});
  BodyState body{s.M_W0, s.omega_0};
  auto tree_integ = make("cga4");
  auto free_integ = std::move(makeIntegrator("rk4").value());
  const double h = 1e-4;
  for (int k = 0; k < 10000; ++k) {
    tree_integ->step(tree, tl, h, s);
    free_integ->step(I, loads, kLambda, h, body);
  }
  // Two fourth-order methods at h = 1e-4 over 1 s: both within ≈ 1e-12 of the truth.
  EXPECT_LT((s.M_W0.translation(kLambda) - body.M_WB.translation(kLambda)).norm(), 1e-9);
  EXPECT_LT((s.omega_0.rot - body.omega_B.rot).norm(), 1e-9);
  EXPECT_LT(std::abs(s.M_W0.rotation().angularDistance(body.M_WB.rotation())), 1e-9);
}

// The explicit RK4 (ABA accelerations) and the implicit cga4 (momentum map and gradient) reach
// the same double-pendulum state: two methods sharing only the model.
TEST(TreeIntegrator, Rk4AndCga4AgreeOnTheDoublePendulum) {
  const ArticulatedBody tree = doublePendulum();
  TreeState a = jointState({1.0, 0.5}, {0.3, -0.2}), b = a;
  auto rk4 = make("rk4"), cga4 = make("cga4");
  for (int k = 0; k < 10000; ++k) {
    rk4->step(tree, gravityOnly(tree), 1e-4, a);
    cga4->step(tree, gravityOnly(tree), 1e-4, b);
  }
  // Both fourth order: ≈ (ω h)⁴ T ≈ 1e-13 each; chaos amplifies by ≈ e^{λT}, λ ≈ 1/s here.
  EXPECT_LT((a.q - b.q).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((a.v - b.v).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(TreeIntegrator, ExactIsRefusedForTreesWithAReason) {
  const auto r = makeTreeIntegrator("exact");
  ASSERT_FALSE(r.ok());
  EXPECT_NE(r.error().find("no closed-form flow"), std::string::npos) << r.error();
  EXPECT_FALSE(makeTreeIntegrator("bogus").ok());
}

// An impulse on a floating tree changes its world momentum by exactly the impulse.
TEST(TreeIntegrator, ImpulseOnAFloatingTreeAddsExactlyItsMomentum) {
  const ArticulatedBody tree = satellite();
  TreeState s = jointState({0.3, -0.2}, {0.0, 0.0});
  s.M_W0 = cga::Motor::fromPose(Eigen::Quaterniond(Eigen::AngleAxisd(0.4, Vector3d::UnitX())),
                                {1, 2, 3}, kLambda);
  TreeKinematics kin;
  treeKinematics(tree, s, kin);
  const cga::Moment J_b = cga::Moment::ofForceAt({0, 0, 5.0}, {0.9, 0.3, 0.0}, kLambda);
  const VectorXd dnu = impulseResponse(tree, s, 2, J_b);
  setVelocityVector(tree, velocityVector(tree, s) + dnu, s);
  treeKinematics(tree, s, kin);
  const cga::Moment P = worldMomentum(tree, kin);
  const cga::Moment expected = kin.M_W[2].apply(J_b, kLambda);
  EXPECT_LT((P.rot - expected.rot).norm() + (P.trans - expected.trans).norm(), 1e-12);
}

}  // namespace tree_integrator_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
