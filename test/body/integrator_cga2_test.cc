// Tests of cga2 (integrator_cga2.h): that a step is the splitting it documents, and the
// properties that follow from it. The hard cases (tennis racket, symmetric top, thin rod,
// convergence order, …) are in hard_cases_test.cc.
#include "cga_rigid_sim/body/integrator_cga2.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdio>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/body/free_flow.h"
#include "common/cga_embedding.h"
#include "common/dynamics_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace integrator_cga2_test {

using Eigen::Quaterniond;
using Eigen::Vector3d;
using testing::maxDiff;
using testing::principal;

constexpr double kEps = 2.220446049250313e-16;

Loads someLoads() {
  Loads loads;
  loads.setGravity(Vector3d(0.3, -0.1, -9.81));
  AppliedLoad push;
  push.axes = Axes::kWorld;
  push.F = cga::Force(Vector3d(1, -2, 0.5));
  push.point_B = Vector3d(0.1, 0.2, -0.3);
  push.couple = Vector3d(0.2, 0, 0.1);
  loads.add(push);
  AppliedLoad thruster;
  thruster.axes = Axes::kBody;
  thruster.F = cga::Force(Vector3d(0, 0.3, 1));
  thruster.point_B = Vector3d(-0.2, 0, 0.1);
  loads.add(thruster);
  return loads;
}

// Loads that are all fixed in the world and act at the centre of mass: the kicks take them from
// their world sums (Loads::worldSums) instead of a pass over the loads at each kick.
Loads worldLoadsAtTheCentre() {
  Loads loads;
  loads.setGravity(Vector3d(0.3, -0.1, -9.81));
  loads.add(testing::appliedLoad(Axes::kWorld, Vector3d(1, -2, 0.5)));
  loads.add(testing::appliedLoad(Axes::kWorld, Vector3d::Zero(), Vector3d::Zero(),
                                 Vector3d(0.2, -0.4, 0.1)));
  return loads;
}

// The splitting written literally from its definition with the general motor exponential and
// Eigen rotations (integrator_cga2.h; axes sorted J1 ≤ J2 ≤ J3, reference J_r = J2,
// κ_i = 1 − J_i/J2): K(h/2) D(h/2) C(h) R1(κ1 h/2) R3(κ3 h) R1(κ1 h/2) D(h/2) K(h/2), with
//   D(τ):   M ← M exp(−½ τ u∧n)        (Bivelocity(0, −½ τ u)),
//   C(τ):   θ = τ |L|/J2 about n = L_B/|L|, M ← M exp(−½ θ I3 n), v_B ← Rot(n, −θ) (L_B stays),
//   R_i(τ): φ = τ L_i/J_i, M ← M exp(−½ φ I3 e_i) (Bivelocity(−½ φ e_i, 0)), L_B, v_B ← Rot(e_i,
//   −φ), K(τ):   Ω_B += τ (I∧n)⁻¹ T(M).
void literalStep(const Inertia& I, const Loads& loads, double lambda, double h, BodyState& s) {
  auto kick = [&](double tau) {
    const cga::Moment T =
        loads.appliedMoment_B(s.M_WB, lambda) + loads.gravityMoment_B(I.mass(), s.M_WB, lambda);
    s.omega_B += tau * I.solve(T, lambda);
  };
  const Vector3d& J = I.principalMoments();
  const Vector3d kappa = Vector3d::Ones() - J / J[1];
  Vector3d L = J.cwiseProduct(s.omega_B.rot), u = s.omega_B.trans;
  auto drift = [&](double tau) {
    s.M_WB = s.M_WB * cga::exp(cga::Bivelocity(Vector3d::Zero(), -0.5 * tau * u));
  };
  auto casimir = [&](double tau) {
    const double theta = tau * L.norm() / J[1];
    const Vector3d n = L.normalized();
    s.M_WB = s.M_WB * cga::exp(cga::Bivelocity(-0.5 * theta * n, Vector3d::Zero()));
    u = Eigen::AngleAxisd(-theta, n) * u;
  };
  auto rotate = [&](int i, double tau) {
    const double phi = tau * kappa[i] * L[i] / J[i];
    const Vector3d e = Vector3d::Unit(i);
    s.M_WB = s.M_WB * cga::exp(cga::Bivelocity(-0.5 * phi * e, Vector3d::Zero()));
    const Eigen::AngleAxisd back(-phi, e);
    L = back * L;
    u = back * u;
  };
  kick(0.5 * h);
  L = J.cwiseProduct(s.omega_B.rot);
  u = s.omega_B.trans;
  drift(0.5 * h);
  casimir(h);
  rotate(0, 0.5 * h);
  rotate(2, h);
  rotate(0, 0.5 * h);
  drift(0.5 * h);
  s.omega_B = cga::Bivelocity(L.cwiseQuotient(J), u);
  kick(0.5 * h);
}

// Truth: the definition of the method (literalStep above, built from cga::exp, which test/cga
// checks against the reference algebra). The fast step merges the drifts, composes the rotors
// sparsely and sums the series itself: the two differ by round-off only. Per step each motor
// coefficient (size ≤ |x|/λ ≈ 3) carries a few ε; after 100 steps (errors random) the bound
// 1e-12 absolute is ≈ 20× the expected ~5e-14. Five kinds of loads: none, general ones (a
// world push off the centre, a body-axes thruster), world-axes loads at the centre with a couple
// (the kicks' world-sums path), and gravity alone or with a world push through the centre (the
// centre's parabola in closed form, the turning free).
TEST(Cga2, StepIsTheDocumentedSplittingOfExactMotorExponentials) {
  testing::Rng rng(7);
  for (int trial = 0; trial < 10; ++trial) {
    const int kind = trial % 5;
    const double lambda = trial < 5 ? 1.0 : 2.5;
    const Inertia I = principal(Vector3d(0.7, 1.1, 1.6) + rng.vec(0.2).cwiseAbs(), 1.7);
    Loads loads = kind == 0 ? Loads() : kind == 1 ? someLoads() : worldLoadsAtTheCentre();
    if (kind >= 3) {
      loads = Loads();
      loads.setGravity(Vector3d(0.3, -0.1, -9.81));
      if (kind == 4) loads.add(testing::appliedLoad(Axes::kWorld, Vector3d(1, -2, 0.5)));
    }
    BodyState fast;
    fast.M_WB = rng.motor(2.0, lambda);
    fast.omega_B = cga::Bivelocity::fromVelocities(rng.vec(3.0), rng.vec(2.0), lambda);
    BodyState literal = fast;
    Cga2Integrator cga2;
    const double h = 0.01 * (1 + trial % 6);  // angles per piece up to ~0.2 rad: both tiers
    for (int k = 0; k < 100; ++k) {
      cga2.step(I, loads, lambda, h, fast);
      literalStep(I, loads, lambda, h, literal);
    }
    EXPECT_LE(maxDiff(fast.M_WB, literal.M_WB), 1e-12) << "trial " << trial;
    EXPECT_LE((fast.omega_B.rot - literal.omega_B.rot).norm(), 1e-12) << "trial " << trial;
    EXPECT_LE((fast.omega_B.trans - literal.omega_B.trans).norm(), 1e-12) << "trial " << trial;
  }
}

// Large angles per piece (> 0.5 rad: the library sin/cos branch) and a negative step take the
// same path through the definition. Same truth and bound as above, 20 steps.
TEST(Cga2, LargeAnglesAndNegativeStepsFollowTheDefinition) {
  const Inertia I = principal(Vector3d(0.5, 1, 1.2));
  for (double h : {0.3, -0.3, 0.05, -0.05}) {
    BodyState fast;
    fast.M_WB = cga::Motor::fromPose(Quaterniond(Eigen::AngleAxisd(1, Vector3d::UnitY())),
                                     Vector3d(1, 2, 3), 1.0);
    fast.omega_B = cga::Bivelocity(Vector3d(6, -3, 2), Vector3d(1, 0, -1));
    BodyState literal = fast;
    Cga2Integrator cga2;
    for (int k = 0; k < 20; ++k) {
      cga2.step(I, Loads(), 1.0, h, fast);
      literalStep(I, Loads(), 1.0, h, literal);
    }
    EXPECT_LE(maxDiff(fast.M_WB, literal.M_WB), 1e-12) << "h = " << h;
    EXPECT_LE((fast.omega_B.rot - literal.omega_B.rot).norm(), 1e-12) << "h = " << h;
  }
}

// Truth: the splitting is symmetric, S(−h) = S(h)⁻¹, with and without loads. Round-off only:
// 1e3 steps forward and back, state of size ~10: bound 1e-11.
TEST(Cga2, TimeReversible) {
  const Inertia I = principal(Vector3d(1, 2, 3), 2.0);
  for (bool loaded : {false, true}) {
    const Loads loads = loaded ? someLoads() : Loads();
    BodyState s;
    s.M_WB =
        cga::Motor::fromPose(Quaterniond(Eigen::AngleAxisd(0.4, Vector3d(1, 1, 0).normalized())),
                             Vector3d(0.5, -1, 2), 1.0);
    s.omega_B = cga::Bivelocity(Vector3d(0.3, 2, -1), Vector3d(1, 2, 0.5));
    const BodyState s0 = s;
    Cga2Integrator cga2;
    for (int k = 0; k < 1000; ++k) cga2.step(I, loads, 1.0, 0.01, s);
    for (int k = 0; k < 1000; ++k) cga2.step(I, loads, 1.0, -0.01, s);
    EXPECT_LE(maxDiff(s.M_WB, s0.M_WB), 1e-11) << "loaded " << loaded;
    EXPECT_LE((s.omega_B.rot - s0.omega_B.rot).norm(), 1e-11) << "loaded " << loaded;
    EXPECT_LE((s.omega_B.trans - s0.omega_B.trans).norm(), 1e-11) << "loaded " << loaded;
  }
}

// Truth: a spin about a principal axis is a relative equilibrium; only the piece about that axis
// turns, and it is the exact flow. After 1e4 steps the attitude equals the rotation by |w| t
// about the axis (angle error ≈ steps·ε·|w|t: bound 1e-10 rad at |w| t = 30 rad), w is
// untouched, and the centre of mass moves on its line.
TEST(Cga2, SpinAboutAPrincipalAxisIsExact) {
  const Inertia I = principal(Vector3d(1, 2, 3));
  for (int axis = 0; axis < 3; ++axis) {
    BodyState s;
    const Vector3d w = 3.0 * Vector3d::Unit(axis), v(1, -2, 0.5);
    s.omega_B = cga::Bivelocity(w, v);
    Cga2Integrator cga2;
    const double h = 1e-3;
    for (int k = 0; k < 10000; ++k) cga2.step(I, Loads(), 1.0, h, s);
    const double t = 10.0;
    const Quaterniond expected(Eigen::AngleAxisd(3.0 * t, Vector3d::Unit(axis)));
    EXPECT_LE(std::min((s.M_WB.rotation().coeffs() - expected.coeffs()).norm(),
                       (s.M_WB.rotation().coeffs() + expected.coeffs()).norm()),
              1e-10)
        << "axis " << axis;
    EXPECT_EQ(s.omega_B.rot, w);
    EXPECT_LE((comPosition_W(s, 1.0) - t * v).norm(), 1e-11 * t * v.norm());
  }
}

// Truth: the conservation laws of the free body — world L and p, |L| (a Casimir) and the rotor
// norm. Every piece is an exact rotation applied in a form whose rounding has no bias (see the
// .cc), so the errors random-walk: 1e5 steps × 4 pieces × ε ≈ √4e5·ε ≈ 1.4e-13 → bound 2e-12
// relative. The energy is not conserved exactly but bounded: O((h|w|)²) ≈ 1e-5 relative here,
// bound 1e-4.
TEST(Cga2, FreeBodyConservesMomentaAndTheRotorNorm) {
  testing::Rng rng(11);
  for (int trial = 0; trial < 3; ++trial) {
    const Inertia I = principal(Vector3d(0.4, 0.9, 1.2) + rng.vec(0.1).cwiseAbs(), 1.3);
    BodyState s;
    s.M_WB = cga::Motor::rotor(rng.rotation());
    s.omega_B = cga::Bivelocity(rng.vec(3.0), rng.vec(1.0));
    const Vector3d L0 = angularMomentumCom_W(I, s), p0 = linearMomentum_W(I, s, 1.0);
    const double E0 = kineticEnergy(I, s, 1.0);
    Cga2Integrator cga2;
    double e_max = 0.0;
    for (int k = 0; k < 100000; ++k) {
      cga2.step(I, Loads(), 1.0, 2e-3, s);
      e_max = std::max(e_max, std::abs(kineticEnergy(I, s, 1.0) / E0 - 1.0));
    }
    EXPECT_LE((angularMomentumCom_W(I, s) - L0).norm(), 2e-12 * L0.norm());
    EXPECT_LE((linearMomentum_W(I, s, 1.0) - p0).norm(), 2e-12 * p0.norm());
    EXPECT_LE(std::abs(I.principalMoments().cwiseProduct(s.omega_B.rot).norm() / L0.norm() - 1),
              2e-12);
    EXPECT_LE(std::abs(s.M_WB.rotation().coeffs().squaredNorm() - 1.0), 2e-12);
    EXPECT_LE(e_max, 1e-4);
    EXPECT_GT(e_max, 0.0);  // the energy error is real but bounded (not an exact method)
  }
}

// Truth: the exact free flow (free_flow.h). For a symmetric body (J1 = J2 or J2 = J3) one axis
// piece has κ = 0 and the other is about the symmetry axis, where it commutes with the Casimir
// flow: the splitting is the exact flow, at any step. 200 steps of 0.05 s with |w| ≈ 4 rad/s
// (40 rad of turn): round-off only, a few ε per step on coefficients of size ~3 → bound 1e-12.
TEST(Cga2, SymmetricBodiesMoveExactly) {
  for (const Vector3d& J : {Vector3d(0.8, 0.8, 1.3), Vector3d(0.5, 1.1, 1.1)}) {
    const Inertia I = principal(J, 1.4);
    BodyState s;
    s.M_WB =
        cga::Motor::fromPose(Quaterniond(Eigen::AngleAxisd(0.7, Vector3d(1, 2, 0).normalized())),
                             Vector3d(0.3, -1, 2), 1.0);
    s.omega_B = cga::Bivelocity(Vector3d(1.5, -2, 3), Vector3d(0.4, 0.1, -1));
    BodyState exact = s;
    FreeFlowCache cache;
    exactFreeFlow(I, 1.0, 10.0, exact, cache);
    Cga2Integrator cga2;
    for (int k = 0; k < 200; ++k) cga2.step(I, Loads(), 1.0, 0.05, s);
    EXPECT_LE(maxDiff(s.M_WB, exact.M_WB), 1e-12) << J.transpose();
    EXPECT_LE((s.omega_B.rot - exact.omega_B.rot).norm(), 1e-12) << J.transpose();
  }
}

// Truth: |L| is conserved (a Casimir: every piece turns L_B). A nearly symmetric body (the thin
// rod: J = (1e-3, 1, 1.0005), spun at 100 rad/s about its long axis) at h = 1e-4 s turns its κ3
// piece by ~1e-8 rad a step, where x + s·y − versin·x loses the versin term to rounding and |L|
// would grow by φ²/2 a step; the shears (rotatePiece) keep the roundings unbiased. Measured over
// 10⁶ steps: 1.5e-14 with the shears, 8.2e-12 with the plain turn (kTinyZ = −1). Bound 1e-12:
// a random walk of ~3e6 roundings is ~√3e6 ε ≈ 4e-13.
TEST(Cga2, NearlySymmetricBodyHasNoRoundOffDrift) {
  const Inertia I = principal(Vector3d(1e-3, 1, 1.0005));
  BodyState s;
  s.omega_B = cga::Bivelocity(Vector3d(100, 0.3, 0.2), Vector3d::Zero());
  const double L0 = I.principalMoments().cwiseProduct(s.omega_B.rot).norm();
  Cga2Integrator cga2;
  for (int k = 0; k < 1000000; ++k) cga2.step(I, Loads(), 1.0, 1e-4, s);
  const double drift = I.principalMoments().cwiseProduct(s.omega_B.rot).norm() / L0 - 1.0;
  std::printf("thin rod, 1e6 steps of cga2 at h = 1e-4: |L| relative drift %.3g\n", drift);
  EXPECT_LE(std::abs(drift), 1e-12);
}

// Truth: the motor's norm is 1 and the centre of mass under uniform gravity is on its parabola
// x0 + v0 t + ½ g t², to round-off. At large angles per step (the projectile of the benchmark,
// |w| ≈ 21 rad/s, h = 0.05 s: the Casimir part turns by 1 rad a step) each rotor factor's norm is
// off by a few ε; the step renormalises the motor (M + eM, e = (1 − |r|²)/2), so the norm does
// not walk.
// Measured over 2000 steps: |r|² − 1 = 0 and the CoM 7.6e-10 m (3.2× √N u |x|, u = ε/2) with it;
// 5e-14 and 3.7e-9 m (15×) without. Bounds: 1e-15 for the norm (a few ε of one step), and the
// benchmark's allowance for T5, 10 √N u |x| ≈ 2.4e-9 m.
TEST(Cga2, MotorNormAndParabolaHoldAtLargeAngles) {
  Cga2Integrator cga2;
  const testing::ParabolaRun run = testing::spinningProjectileOnParabola(cga2, 0.05, 2000);
  EXPECT_LE(std::abs(run.end.M_WB.rotation().coeffs().squaredNorm() - 1.0), 1e-15);
  EXPECT_LE(run.com_error, 10.0 * run.random_walk);
}

// Truth: the per-body cache (the ratios of the moments) must follow the inertia it is given. A
// step with new moments after steps with others equals a fresh integrator's step, bit for bit.
TEST(Cga2, CacheFollowsTheInertia) {
  const Inertia A = principal(Vector3d(1, 2, 3)), B = principal(Vector3d(0.5, 0.6, 1));
  BodyState s0;
  s0.omega_B = cga::Bivelocity(Vector3d(1, 2, 3), Vector3d(0, 1, 0));
  Cga2Integrator used, fresh;
  BodyState s = s0;
  used.step(A, Loads(), 1.0, 0.01, s);
  BodyState a = s0, b = s0;
  used.step(B, Loads(), 1.0, 0.01, a);
  fresh.step(B, Loads(), 1.0, 0.01, b);
  EXPECT_EQ(a.M_WB.coefficients(), b.M_WB.coefficients());
  EXPECT_EQ(a.omega_B.coefficients(), b.omega_B.coefficients());
  used.reset();
  EXPECT_STREQ(used.name(), "cga2");
  EXPECT_STREQ(used.path(), "cga2");
}

// Truth: composeStrang's definition, S(γ_1 h) ∘ … ∘ S(γ_s h). A stage count without a merged
// form (here 2) runs stage by stage: bit for bit the cga2 steps of γ_i h, with and without loads.
TEST(Cga2, AnyCompositionIsTheSequenceOfItsStages) {
  const Inertia I = principal(Vector3d(1, 2, 3), 2.0);
  const double gamma[2] = {0.3, 0.7};
  for (bool loaded : {false, true}) {
    const Loads loads = loaded ? someLoads() : Loads();
    BodyState a;
    a.omega_B = cga::Bivelocity(Vector3d(0.3, 2, -1), Vector3d(1, 2, 0.5));
    BodyState b = a;
    splitting::Cache cache;
    Cga2Integrator cga2;
    for (int k = 0; k < 10; ++k) {
      splitting::composeStrang(I, loads, 1.0, 0.05, gamma, 2, cache, a);
      cga2.step(I, loads, 1.0, gamma[0] * 0.05, b);
      cga2.step(I, loads, 1.0, gamma[1] * 0.05, b);
    }
    EXPECT_EQ(a.M_WB.coefficients(), b.M_WB.coefficients()) << "loaded " << loaded;
    EXPECT_EQ(a.omega_B.coefficients(), b.omega_B.coefficients()) << "loaded " << loaded;
  }
}

// Truth: a world couple carried in body axes from step to step (Cache::CarriedCouple) is used
// only for the state, couple and inertia it was formed for. After steps that carried it, a step
// from a state changed outside the integrator without reset() (w, as by an impulse; the rotor, as
// by a pose override), under a new couple, or with a new inertia, equals a fresh integrator's
// step bit for bit: both turn the couple from the world and form |L|² from w. A stale |L|² (the
// w it was carried for) or a stale turned couple would change the step's bits.
TEST(Cga2, CarriedCoupleIsUsedOnlyForTheStateItWasCarriedFor) {
  const Inertia I = principal(Vector3d(1, 2, 3), 2.0), I2 = principal(Vector3d(1, 2, 2.5), 2.0);
  const Loads loads = worldLoadsAtTheCentre();
  Loads other = worldLoadsAtTheCentre();
  other.add(
      testing::appliedLoad(Axes::kWorld, Vector3d::Zero(), Vector3d::Zero(), Vector3d(0, 0, 1e-3)));
  BodyState s0;
  s0.omega_B = cga::Bivelocity(Vector3d(0.5, 1, 1.5), Vector3d(1, 2, 0.5));
  const cga::Motor turn = cga::Motor::fromPose(
      Quaterniond(Eigen::AngleAxisd(1e-3, Vector3d(0, 0, 1))), Vector3d::Zero(), 1.0);
  for (int change = 0; change < 4; ++change) {
    Cga2Integrator used, fresh;
    BodyState s = s0;
    for (int k = 0; k < 5; ++k) used.step(I, loads, 1.0, 1e-3, s);
    const Inertia* inertia = &I;
    const Loads* step_loads = &loads;
    if (change == 0)
      s.omega_B =
          cga::Bivelocity(s.omega_B.angular() + Vector3d(0, 0, 1e-9), s.omega_B.linear(1.0));
    if (change == 1) s.M_WB = s.M_WB * turn;
    if (change == 2) step_loads = &other;
    if (change == 3) inertia = &I2;
    BodyState a = s, b = s;
    used.step(*inertia, *step_loads, 1.0, 1e-3, a);
    fresh.step(*inertia, *step_loads, 1.0, 1e-3, b);
    EXPECT_EQ(a.M_WB.coefficients(), b.M_WB.coefficients()) << "change " << change;
    EXPECT_EQ(a.omega_B.coefficients(), b.omega_B.coefficients()) << "change " << change;
  }
}

// Truth: the carried couple is R̃ c_W turned by the step's rotations, and its numbers are |J w|²,
// (J w)·c and |c|²; the same quantities formed afresh from the state after each step must agree
// to round-off. Each turn adds a few ε, and where the same turn repeats (a fast steady spin) its
// rotor's norm error of a few ε scales c the same way every step: a bias. The couple is turned
// from the world again every CarriedCouple::kMaxSteps = 1024 steps, so the bias is bounded by
// ~1024 steps of it. Measured over 2·10⁵ steps of cga2 and of the three-stage cga4 composition,
// at 1 and 100 rad/s: c ≤ 750 ε, |L|² ≤ 230 ε, L·c ≤ 1.5e3 ε (relative to |L||c|); without the
// turns from the world c was off by 1.4e7 ε (3e-9). Bounds 4e3 ε for c and 1e4 ε for the sums.
TEST(Cga2, CarriedCoupleStaysWithinRoundOffOfTheWorldCouple) {
  const double a = 1.0 / (2.0 - std::cbrt(2.0));
  const double gamma[3] = {a, 1.0 - 2.0 * a, a}, one = 1.0;
  const Inertia I = principal(Vector3d(1, 2, 3), 2.0);
  const Loads loads = worldLoadsAtTheCentre();
  const Vector3d c_W(0.2, -0.4, 0.1);  // worldLoadsAtTheCentre()'s couple
  for (const double spin : {1.0, 100.0}) {
    for (int stages : {1, 3}) {
      BodyState s;
      s.omega_B = cga::Bivelocity(spin * Vector3d(0.5, 1, 1.5), Vector3d(1, 2, 0.5));
      splitting::Cache cache;
      double dc = 0, dLL = 0, dLc = 0;
      for (int k = 0; k < 200000; ++k) {
        splitting::composeStrang(I, loads, 1.0, 1e-3, stages == 1 ? &one : gamma, stages, cache, s);
        const Vector3d c_B = s.M_WB.rotation().conjugate() * c_W;
        const Vector3d L = I.principalMoments().cwiseProduct(s.omega_B.angular());
        const splitting::Cache::CarriedCouple& carried = cache.couple;
        const Vector3d carried_c(carried.c_B[0], carried.c_B[1], carried.c_B[2]);
        dc = std::max(dc, (carried_c - c_B).norm() / c_W.norm());
        dLL = std::max(dLL, std::abs(carried.LL - L.squaredNorm()) / L.squaredNorm());
        dLc = std::max(dLc, std::abs(carried.Lc - L.dot(c_B)) / (L.norm() * c_W.norm()));
      }
      EXPECT_LE(dc, 4e3 * kEps) << "spin " << spin << ", stages " << stages;
      EXPECT_LE(dLL, 1e4 * kEps) << "spin " << spin << ", stages " << stages;
      EXPECT_LE(dLc, 1e4 * kEps) << "spin " << spin << ", stages " << stages;
    }
  }
}

// Round-off per step, in units of ε: a free body stepped with an h that turns each piece by a
// tiny angle keeps the rotor norm to a few ε per step (no O(ε) bias per piece: after 1e5 steps
// the drift is far below the 5e5·ε a biased rotation would leave). Bound 2e3 ε.
TEST(Cga2, RotorNormDoesNotDriftAtSmallAngles) {
  const Inertia I = principal(Vector3d(1, 2, 3));
  BodyState s;
  s.omega_B = cga::Bivelocity(Vector3d(0.01, 0.02, 0.015), Vector3d::Zero());
  Cga2Integrator cga2;
  for (int k = 0; k < 100000; ++k) cga2.step(I, Loads(), 1.0, 1e-3, s);
  EXPECT_LE(std::abs(s.M_WB.rotation().coeffs().squaredNorm() - 1.0), 2e3 * kEps);
  EXPECT_LE(s.M_WB.normDrift(), 2e3 * kEps);
}

}  // namespace integrator_cga2_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
