// Tests of joint servos in the tree integrators (tree/joint_servos.h, doc/articulated.md#servos):
// the midpoint's discrete response of a servoed slider against the Cayley transform of the
// linear system (the implicit midpoint rule's exact discrete map), its convergence to the
// continuous second-order response as h → 0, stability at gains where RK4's explicit PD
// diverges, the effort limit, and a pendulum held against gravity at the servo's static
// equilibrium.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>

#include "cga_rigid_sim/tree/tree_integrator.h"
#include "common/tree_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace joint_servo_test {

using Eigen::Matrix2d;
using Eigen::Vector2d;
using Eigen::Vector3d;
using Eigen::VectorXd;

constexpr double kLambda = 1.0;

// A block of mass m sliding along x on a fixed base (its inertia matrix is m: no rotation).
ArticulatedBody slider(double m) {
  TreeJoint j;
  j.kind = JointKind::kPrismatic;
  j.axis = Vector3d::UnitX();
  j.inertia = Inertia::fromPrincipal("block", m, {0.1, 0.1, 0.1}).value();
  return ArticulatedBody(std::nullopt, {j}, kLambda);
}

TreeLoads servoLoads(double kp, double kd, double r) {
  TreeLoads loads;  // no gravity: the slider's axis is free of it anyway
  loads.effort = VectorXd::Zero(1);
  loads.servos.resize(1);
  loads.servos.kp[0] = kp;
  loads.servos.kd[0] = kd;
  loads.servos.position[0] = r;
  return loads;
}

TreeState sliderState(double q, double v) {
  TreeState s;
  s.q = VectorXd::Constant(1, q);
  s.v = VectorXd::Constant(1, v);
  return s;
}

// m ë = −kp e − kd ė (e = q − r) is ẋ = A x, x = (e, ė); the implicit midpoint rule maps x to
// (1 − ½hA)⁻¹ (1 + ½hA) x per step. The variational midpoint with the servo at the midpoint is
// that rule here (M constant): after N steps the state must be the N-th power of the map.
TEST(JointServo, MidpointIsTheCayleyMapOfTheServoedSlider) {
  const double m = 2.0, kp = 5e4, kd = 40.0, r = 0.3, h = 1e-3;
  const ArticulatedBody tree = slider(m);
  const TreeLoads loads = servoLoads(kp, kd, r);
  Matrix2d A;
  A << 0, 1, -kp / m, -kd / m;
  const Matrix2d step =
      (Matrix2d::Identity() - 0.5 * h * A).inverse() * (Matrix2d::Identity() + 0.5 * h * A);
  for (const char* name : {"cga2", "auto"}) {
    auto integ = testing::treeIntegrator(name);
    TreeState s = sliderState(0.0, 0.0);
    Vector2d x(-r, 0.0);
    double worst = 0.0;
    for (int k = 0; k < 2000; ++k) {
      integ->step(tree, loads, h, s);
      x = step * x;
      worst = std::max({worst, std::abs(s.q[0] - r - x[0]), std::abs(s.v[0] - x[1]) * h});
    }
    // Round-off: each step rounds e and ė at ~1e-16 relative to 0.3 m and 0.3·ω ≈ 50 m/s
    // (ω = √(kp/m) = 158 rad/s); the map's eigenvalues have modulus < 1, so the errors do not
    // grow: 2000 steps leave them near 1e-14 m. 1e-12 is a hundred times that.
    EXPECT_LT(worst, 1e-12) << name;
    // The applied effort is the servo's at the midpoint: kp (r − q̄) + kd (0 − ν̄), and it is
    // what the integrator reports.
    ASSERT_NE(integ->lastEffort(), nullptr);
  }
}

// As h → 0 the discrete response tends to the continuous one, e(t) = e₀ e^{−ζωt}(cos ω_d t +
// ζω/ω_d sin ω_d t), second order: halving h divides the error at t = 0.05 s by ~4.
TEST(JointServo, MidpointConvergesToTheContinuousResponseAtSecondOrder) {
  const double m = 1.0, kp = 1e4, kd = 20.0, r = 0.1;  // ω = 100 rad/s, ζ = 0.1
  const double w = std::sqrt(kp / m), zeta = kd / (2 * std::sqrt(kp * m));
  const double wd = w * std::sqrt(1 - zeta * zeta), T = 0.05;
  const double exact =
      -r * std::exp(-zeta * w * T) * (std::cos(wd * T) + zeta * w / wd * std::sin(wd * T));
  const ArticulatedBody tree = slider(m);
  double errors[3];
  const double hs[3] = {1e-3, 5e-4, 2.5e-4};
  for (int i = 0; i < 3; ++i) {
    auto integ = testing::treeIntegrator("cga2");
    TreeState s = sliderState(0.0, 0.0);
    const int steps = static_cast<int>(std::lround(T / hs[i]));
    for (int k = 0; k < steps; ++k) integ->step(tree, servoLoads(kp, kd, r), hs[i], s);
    errors[i] = std::abs(s.q[0] - r - exact);
  }
  // The implicit midpoint's phase error is (hω)²/12 per radian: at hω = 0.1 over 5 rad, about
  // 4e-3 rad of phase on an amplitude of 0.06 m, a few 1e-4 m. Second order: ratios near 4
  // (3.5–4.5 allows the O(h⁴) term).
  EXPECT_LT(errors[0], 1e-3);
  EXPECT_GT(errors[0] / errors[1], 3.5);
  EXPECT_LT(errors[0] / errors[1], 4.5);
  EXPECT_GT(errors[1] / errors[2], 3.5);
  EXPECT_LT(errors[1] / errors[2], 4.5);
}

// hω = 10: far past RK4's stability bound on the imaginary axis (2√2). The explicit PD grows
// without bound; the implicit servo settles at r (its map's eigenvalues have modulus < 1 for
// every h when kd > 0, = 1 when kd = 0: bounded).
TEST(JointServo, StiffServoIsStableWhereTheExplicitOneDiverges) {
  const double m = 1.0, kp = 1e8, kd = 2e3, r = 0.2, h = 1e-3;  // ω = 1e4 rad/s, hω = 10
  const ArticulatedBody tree = slider(m);
  const TreeLoads loads = servoLoads(kp, kd, r);
  auto implicit = testing::treeIntegrator("cga2");
  auto explicit_pd = testing::treeIntegrator("rk4");
  TreeState a = sliderState(0.0, 0.0), b = sliderState(0.0, 0.0);
  double worst = 0.0;
  for (int k = 0; k < 200; ++k) {
    implicit->step(tree, loads, h, a);
    worst = std::max(worst, std::abs(a.q[0] - r));
    if (std::isfinite(b.q[0])) explicit_pd->step(tree, loads, h, b);
  }
  // Bounded by the initial error (the discrete energy of the undamped part never grows, the
  // damper only takes), and after 200 steps well inside it.
  EXPECT_LE(worst, r * (1 + 1e-12));
  EXPECT_LT(std::abs(a.q[0] - r), 0.05 * r);
  // RK4's amplification at hω = 10 is ~10³ per step: 200 steps overflow or leave |e| ≫ 1 m.
  EXPECT_TRUE(!std::isfinite(b.q[0]) || std::abs(b.q[0] - r) > 1e3) << b.q[0];
}

// A servo whose torque exceeds <limit effort> applies the limit: from rest the slider moves
// with constant acceleration F/m, which the midpoint integrates exactly (q = ½ (F/m) t²).
TEST(JointServo, EffortLimitClampsTheServo) {
  const double m = 2.0, F = 3.0, h = 1e-3;
  TreeJoint j;
  j.kind = JointKind::kPrismatic;
  j.axis = Vector3d::UnitX();
  j.inertia = Inertia::fromPrincipal("block", m, {0.1, 0.1, 0.1}).value();
  j.effort_limit = F;
  const ArticulatedBody tree(std::nullopt, {j}, kLambda);
  const TreeLoads loads = servoLoads(1e6, 1e3, 10.0);  // r = 10 m away: saturated throughout
  for (const char* name : {"cga2", "rk4"}) {
    auto integ = testing::treeIntegrator(name);
    TreeState s = sliderState(0.0, 0.0);
    for (int k = 0; k < 500; ++k) integ->step(tree, loads, h, s);
    const double t = 500 * h;
    // Constant force: both methods are exact up to round-off of ~500 additions (1e-13 m).
    EXPECT_NEAR(s.q[0], 0.5 * F / m * t * t, 1e-12) << name;
    EXPECT_NEAR(s.v[0], F / m * t, 1e-12) << name;
    ASSERT_NE(integ->lastEffort(), nullptr);
    EXPECT_DOUBLE_EQ((*integ->lastEffort())[0], F) << name;  // RK4: the weights' sum, to ulps
  }
}

// A rod hinged at one end, servoed to θ_r = 0.5 rad under gravity: it settles where the spring
// balances gravity's moment, kp (θ_r − θ) = m g (ℓ/2) sin θ (solved by Newton's method here).
TEST(JointServo, PendulumSettlesAtTheStaticEquilibrium) {
  const double m = 1.5, l = 0.8, g = 9.81, kp = 200.0, kd = 5.0, theta_r = 0.5;
  TreeJoint j;
  j.axis = Vector3d::UnitY();
  j.M_JC = cga::Motor::translator({0, 0, -l / 2}, kLambda);
  j.inertia = Inertia::fromPrincipal("rod", m, {m * l * l / 12, m * l * l / 12, 1e-4}).value();
  const ArticulatedBody tree(std::nullopt, {j}, kLambda);
  TreeLoads loads = servoLoads(kp, kd, theta_r);
  loads.gravity_W = {0, 0, -g};
  // Gravity's moment about +y on a rod hanging along −z rotated by θ about y: its centre at
  // (−(ℓ/2) sin θ, 0, −(ℓ/2) cos θ), so the moment is −m g (ℓ/2) sin θ.
  double theta = theta_r;
  for (int it = 0; it < 50; ++it) {
    const double f = kp * (theta_r - theta) - m * g * l / 2 * std::sin(theta);
    const double df = -kp - m * g * l / 2 * std::cos(theta);
    theta -= f / df;
  }
  auto integ = testing::treeIntegrator("cga2");
  TreeState s = sliderState(0.0, 0.0);
  for (int k = 0; k < 20000; ++k) integ->step(tree, loads, 1e-3, s);
  // ζ = kd / (2 √(kp I_p)) ≈ 0.32 with I_p = m ℓ²/3: after 20 s the transient has decayed by
  // e^{−ζ ω t} < 1e-40; what is left is round-off.
  EXPECT_NEAR(s.q[0], theta, 1e-12);
  EXPECT_NEAR(s.v[0], 0.0, 1e-12);
}

}  // namespace joint_servo_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
