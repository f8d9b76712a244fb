// Tests of the exact torque-free flow (free_flow.h) and of the `exact` integrator.
//
// Truths used: the analytic elliptic period, the conservation laws of the free rigid body, an
// independent classical RK4 on (quaternion, w) written here (no library code), the exact
// ballistic parabola, and the flow's own semigroup property (N steps of h = one step of N h).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <boost/math/special_functions/ellint_rf.hpp>
#include <cmath>
#include <random>
#include <vector>

#include "cga_rigid_sim/body/derived.h"
#include "cga_rigid_sim/body/free_flow.h"
#include "cga_rigid_sim/body/integrator_exact.h"
#include "common/dynamics_fixtures.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace exact_test {

using testing::principal;

constexpr double kEps = 2.220446049250313e-16;

BodyState makeState(const Eigen::Quaterniond& R, const Eigen::Vector3d& x,
                    const Eigen::Vector3d& w_B, const Eigen::Vector3d& v_B, double lambda) {
  BodyState s;
  s.M_WB = cga::Motor::fromPose(R.normalized(), x, lambda);
  s.omega_B = cga::Bivelocity::fromVelocities(w_B, v_B, lambda);
  return s;
}

Eigen::Quaterniond randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  q.normalize();
  return q;
}

// Distance between two attitudes up to the double cover.
double rotorDistance(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return std::min((a.coeffs() - b.coeffs()).norm(), (a.coeffs() + b.coeffs()).norm());
}

// |‖r‖² − 1| of the motor's rotor: a few ε for a motor built in closed form. (Motor::normDrift
// also reports r·q, which scales with |x|/λ and is not a relative measure.)
double rotorNormError(const BodyState& s) {
  return std::abs(s.M_WB.rotation().coeffs().squaredNorm() - 1.0);
}

// The state after n steps of h, with one cache.
BodyState flowSteps(const Inertia& I, double lambda, BodyState s, double h, int n) {
  FreeFlowCache cache;
  for (int i = 0; i < n; ++i) exactFreeFlow(I, lambda, h, s, cache);
  return s;
}

// ---- Independent reference: classical RK4 on (q, w) -----------------------------------------
// q̇ = ½ q ⊗ (0, w), J ẇ = (J w) × w + τ_B. The state update uses compensated (Kahan) summation,
// which leaves the method unchanged but keeps increments far below ulp(w) (near-symmetric bodies:
// ẇ ∝ J2 − J1) from being rounded away.
struct Rk4State {
  Eigen::Vector4d q;  // (w, x, y, z)
  Eigen::Vector3d w;
};

Rk4State rk4Derivative(const Rk4State& s, const Eigen::Vector3d& J, const Eigen::Vector3d& tau) {
  const Eigen::Vector4d& q = s.q;
  const Eigen::Vector3d& w = s.w;
  Rk4State d;
  d.q = 0.5 * Eigen::Vector4d(
                  -q[1] * w[0] - q[2] * w[1] - q[3] * w[2], q[0] * w[0] + q[2] * w[2] - q[3] * w[1],
                  q[0] * w[1] + q[3] * w[0] - q[1] * w[2], q[0] * w[2] + q[1] * w[1] - q[2] * w[0]);
  d.w = (J.cwiseProduct(w).cross(w) + tau).cwiseQuotient(J);
  return d;
}

Rk4State rk4(Rk4State s, const Eigen::Vector3d& J, const Eigen::Vector3d& tau, double h,
             int steps) {
  Eigen::Vector4d cq = Eigen::Vector4d::Zero();
  Eigen::Vector3d cw = Eigen::Vector3d::Zero();
  auto axpy = [](const Rk4State& s, double a, const Rk4State& d) {
    return Rk4State{s.q + a * d.q, s.w + a * d.w};
  };
  for (int i = 0; i < steps; ++i) {
    const Rk4State k1 = rk4Derivative(s, J, tau);
    const Rk4State k2 = rk4Derivative(axpy(s, 0.5 * h, k1), J, tau);
    const Rk4State k3 = rk4Derivative(axpy(s, 0.5 * h, k2), J, tau);
    const Rk4State k4 = rk4Derivative(axpy(s, h, k3), J, tau);
    const Eigen::Vector4d dq = (h / 6.0) * (k1.q + 2.0 * k2.q + 2.0 * k3.q + k4.q) - cq;
    const Eigen::Vector3d dw = (h / 6.0) * (k1.w + 2.0 * k2.w + 2.0 * k3.w + k4.w) - cw;
    const Eigen::Vector4d q = s.q + dq;
    const Eigen::Vector3d w = s.w + dw;
    cq = (q - s.q) - dq;
    cw = (w - s.w) - dw;
    s.q = q;
    s.w = w;
  }
  return s;
}

Rk4State toRk4(const BodyState& s) {
  const Eigen::Quaterniond& q = s.M_WB.rotation();
  return {Eigen::Vector4d(q.w(), q.x(), q.y(), q.z()), s.omega_B.rot};
}
Eigen::Quaterniond rk4Rotor(const Rk4State& s) {
  return Eigen::Quaterniond(s.q[0], s.q[1], s.q[2], s.q[3]);
}

// Attitude and w after 1 s from the flow (in `steps` steps) and from RK4 at h = 1e-5.
struct Rk4Diff {
  double rotor, w;  // |Δq| (up to sign), |Δw|/|w0|
};
Rk4Diff compareWithRk4(const Eigen::Vector3d& J_principal, const Eigen::Vector3d& w0, int steps,
                       unsigned seed) {
  std::mt19937 rng(seed);
  const Inertia I = principal(J_principal);
  const BodyState s0 = makeState(randomRotation(rng), Eigen::Vector3d(0.1, -0.2, 0.3), w0,
                                 Eigen::Vector3d(0.5, 0.1, -0.4), 1.0);
  const BodyState s = flowSteps(I, 1.0, s0, 1.0 / steps, steps);
  const Rk4State r = rk4(toRk4(s0), I.principalMoments(), Eigen::Vector3d::Zero(), 1e-5, 100000);
  return {rotorDistance(s.M_WB.rotation(), rk4Rotor(r)), (s.omega_B.rot - r.w).norm() / w0.norm()};
}

// ---- Tennis racket ------------------------------------------------------------------------
// Truth: the analytic period 4K(k)/ω_p of the elliptic solution (Landau–Lifshitz §37), with K
// from Boost's Carlson R_F (independent of the flow's own AGM). Measured: the times at which w2
// crosses zero, located by bisection on the exact flow evaluated from the initial state at any
// t (one fresh exactFreeFlow call per evaluation). Tolerance: near a crossing w2 changes at
// |ẇ2| ≈ 2 rad/s², so bisection locates it to the round-off of w2 over the 40 s run
// (~100 ε |w| / |ẇ2| ≈ 1e-14 s), and K(k) at k'² = 5e-5 is accurate to ~1e-15 (Boost promotes
// to long double); the period (≈ 22 s) is then good to ~1e-14 relative. 1e-9 is the required
// accuracy, far above both.
TEST(ExactFreeFlow, TennisRacketFlipPeriodMatchesEllipticPeriod) {
  const Eigen::Vector3d J(1.0, 2.0, 3.0);
  const Eigen::Vector3d w0(0.01, 2.0, 0.01);
  const Inertia I = principal(J);
  const BodyState s0 = makeState(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), w0,
                                 Eigen::Vector3d::Zero(), 1.0);

  // Analytic period, D = |L|² > 2T J2 (the polhode circles e3). k'² = 1 − k² is formed from
  // D − E J2 (Landau's k² rearranged) and K(k) = R_F(0, k'², 1), because k² = 1 − 5e-5 here:
  // taking 1 − k² or passing k would cost ~1e-12 of relative accuracy to cancellation.
  const Eigen::Vector3d L = J.cwiseProduct(w0);
  const double D = L.squaredNorm(), E = w0.dot(L);
  ASSERT_GT(D, E * J[1]);
  const double d_minus_ej2 =
      L[2] * L[2] * (J[2] - J[1]) / J[2] - L[0] * L[0] * (J[1] - J[0]) / J[0];
  const double d_minus_ej1 =
      L[1] * L[1] * (J[1] - J[0]) / J[1] + L[2] * L[2] * (J[2] - J[0]) / J[2];
  const double kp2 = (J[2] - J[0]) * d_minus_ej2 / ((J[2] - J[1]) * d_minus_ej1);
  const double omega_p = std::sqrt((J[2] - J[1]) * d_minus_ej1 / (J[0] * J[1] * J[2]));
  const double period = 4.0 * boost::math::ellint_rf(0.0, kp2, 1.0) / omega_p;

  auto w2At = [&](double t) {
    BodyState s = s0;
    FreeFlowCache cache;
    exactFreeFlow(I, 1.0, t, s, cache);
    return s.omega_B.rot[1];
  };
  // Bracket the zero crossings of w2 on a 0.05 s grid, then bisect each to round-off.
  std::vector<double> crossings;
  double t_prev = 0.0, w_prev = w2At(0.0);
  for (int i = 1; i <= 900 && crossings.size() < 4; ++i) {
    const double t = 0.05 * i, w = w2At(t);
    if ((w < 0) != (w_prev < 0)) {
      double lo = t_prev, hi = t;
      const bool lo_negative = w_prev < 0;
      for (int it = 0; it < 80 && hi - lo > 0; ++it) {
        const double mid = 0.5 * (lo + hi);
        if (mid == lo || mid == hi) break;
        ((w2At(mid) < 0) == lo_negative ? lo : hi) = mid;
      }
      crossings.push_back(0.5 * (lo + hi));
    }
    t_prev = t;
    w_prev = w;
  }
  ASSERT_EQ(crossings.size(), 4u);
  // Crossings alternate direction: j and j + 2 are one full period apart; j and j + 1 one flip.
  const double measured_a = crossings[2] - crossings[0];
  const double measured_b = crossings[3] - crossings[1];
  const double flip = crossings[1] - crossings[0];
  EXPECT_NEAR(measured_a / period - 1.0, 0.0, 1e-9);
  EXPECT_NEAR(measured_b / period - 1.0, 0.0, 1e-9);
  EXPECT_NEAR(flip / (0.5 * period) - 1.0, 0.0, 1e-9);
  RecordProperty("period_rel_error", std::to_string(measured_a / period - 1.0));
  std::printf("[ info ] racket: period %.15f s, analytic %.15f s, rel. error %.2e / %.2e\n",
              measured_a, period, measured_a / period - 1.0, measured_b / period - 1.0);
}

// ---- Exactness at any step ------------------------------------------------------------------
// Truth: the flow is a one-parameter group, so N steps of h must equal one step of N h.
// Tolerance: both are evaluated from the same closed form; they differ by the round-off of the
// accumulated phase and angles, ≤ a few ε per radian turned (≤ 10⁴ rad here: 2.3 rad/s × 100 s
// at h = 10), i.e. ≲ 1e-12 relative; 1e-12 is the required accuracy.
TEST(ExactFreeFlow, NStepsEqualOneLongStep) {
  struct Case {
    const char* name;
    Eigen::Vector3d J;
  };
  const Case cases[] = {{"spherical", {2.0, 2.0, 2.0}},
                        {"symmetric", {2.0, 2.0, 3.0}},
                        {"asymmetric", {1.0, 2.0, 3.0}}};
  std::mt19937 rng(11);
  for (const Case& c : cases) {
    const Inertia I = principal(c.J);
    double worst = 0;
    for (double h : {1e-3, 0.1, 1.0, 10.0}) {
      const int n = 10;
      const BodyState s0 =
          makeState(randomRotation(rng), Eigen::Vector3d(1.0, -2.0, 0.5),
                    Eigen::Vector3d(0.3, 1.0, -2.0), Eigen::Vector3d(0.2, -0.7, 1.1), 1.0);
      const BodyState a = flowSteps(I, 1.0, s0, h, n);
      const BodyState b = flowSteps(I, 1.0, s0, n * h, 1);
      const double x_scale = comPosition_W(a, 1.0).norm();
      const double d[4] = {rotorDistance(a.M_WB.rotation(), b.M_WB.rotation()),
                           (a.omega_B.rot - b.omega_B.rot).norm() / s0.omega_B.rot.norm(),
                           (comPosition_W(a, 1.0) - comPosition_W(b, 1.0)).norm() / x_scale,
                           (a.omega_B.trans - b.omega_B.trans).norm() / s0.omega_B.trans.norm()};
      for (double di : d) {
        EXPECT_LE(di, 1e-12) << c.name << " h=" << h;
        worst = std::max(worst, di);
      }
      EXPECT_LE(rotorNormError(a), 8 * kEps) << c.name;
    }
    std::printf("[ info ] %-10s 10 steps of h vs one of 10 h, h = 1e-3 … 10 s: max diff %.1e\n",
                c.name, worst);
  }
}

// Truth: the semigroup property for the steps that take Π's part of ψ from its addition theorem
// and, for small phase steps, sn, cn, dn from theirs (doc/conventions.md (E32), free_flow_phase.h):
// j steps of h against one step of j h, for j = 1 … 100 (three runs and a part), which the cache
// evaluates from its anchor with R_J and Bulirsch's sn, cn, dn — an independent evaluation of the
// same closed form. Phase steps δ = ω_p h of 1e-3, 0.03 and 0.2 take the small-step path; 0.05
// … 3.6 half periods 2K the other (0.8 and 1.3 round to one half period: sn δ changes sign); both
// paths and both forms (n and N) are checked to occur. Bodies: both polhode axes, near the
// separatrix (k' ≪ 1: the state spends its time at cn, dn ≈ k', where an absolute error ε in
// them would be a phase error ε/k'), near symmetry, the thin rod. Tolerance: a run adds up at
// most 31 steps' round-off, a few ε each, on top of the anchored phase's few ulps:
// 64 ε (1 + phase), phase = |w| j h the angle turned.
TEST(ExactFreeFlow, AdditionTheoremStepsEqualTheAnchoredEvaluation) {
  struct Case {
    const char* name;
    Eigen::Vector3d J, w;
  };
  const Case cases[] = {{"e3 polhode", {1.0, 2.0, 3.0}, {0.3, 1.0, -2.0}},
                        {"e1 polhode", {1.0, 2.0, 3.0}, {2.0, 1.0, 0.3}},
                        {"racket", {1.0, 2.0, 3.0}, {0.01, 2.0, 0.01}},
                        {"near separatrix", {1.0, 2.0, 3.0}, {1e-7, 2.0, 1e-7}},
                        {"near symmetric", {1.0, 1.0 + 1e-6, 2.0}, {0.5, 0.2, 1.0}},
                        {"box", {1.0, 1.2, 1.9}, {0.9, -0.4, 0.7}},
                        {"thin rod", {1.0, 1.0005, 1e-3}, {0.3, 0.2, 100.0}}};
  // Phase steps δ: 1e-3, 0.03, 0.2 (small: sn, cn, dn by their addition theorems), and 0.05 …
  // 3.6 half periods (from the anchor when δ > 0.25).
  const double small_deltas[] = {1e-3, 0.03, 0.2};
  const double fractions[] = {0.05, 0.45, 0.8, 1.3, 1.7, 3.6};
  std::mt19937 rng(21);
  bool saw_n = false, saw_N = false, saw_small = false, saw_large = false;
  for (const Case& c : cases) {
    const Inertia I = principal(c.J);
    const BodyState s0 = makeState(randomRotation(rng), Eigen::Vector3d(0.3, -1.0, 2.0), c.w,
                                   Eigen::Vector3d(0.5, 0.1, -0.2), 1.0);
    // The half period 2K/ω_p of this state, from a cache built by one short step.
    FreeFlowCache probe;
    BodyState p = s0;
    exactFreeFlow(I, 1.0, 1e-9, p, probe);
    ASSERT_EQ(probe.path, FreeFlowCache::Path::kElliptic) << c.name;
    (probe.dual ? saw_N : saw_n) = true;
    const double half_period = 2.0 * probe.K / probe.omega_p;
    double worst = 0.0;
    std::vector<double> hs;
    for (double d : small_deltas) hs.push_back(d / probe.omega_p);
    for (double f : fractions) hs.push_back(f * half_period);
    for (double h : hs) {
      const double f = h / half_period;
      FreeFlowCache cache;
      BodyState a = s0;
      for (int j = 1; j <= 100; ++j) {
        exactFreeFlow(I, 1.0, h, a, cache);
        (cache.step_small ? saw_small : saw_large) = true;
        BodyState b = s0;
        FreeFlowCache once;
        exactFreeFlow(I, 1.0, j * h, b, once);
        const double tol = 64 * kEps * (1.0 + c.w.norm() * j * h);
        // The rotor itself, sign included: the angle about L must not jump by 2π.
        const double d_rot = (a.M_WB.rotation().coeffs() - b.M_WB.rotation().coeffs()).norm();
        const double d_w = (a.omega_B.rot - b.omega_B.rot).norm() / c.w.norm();
        ASSERT_LE(d_rot, tol) << c.name << " h = " << f << " half periods, step " << j;
        ASSERT_LE(d_w, tol) << c.name << " h = " << f << " half periods, step " << j;
        worst = std::max(worst, std::max(d_rot, d_w) / (kEps * (1.0 + c.w.norm() * j * h)));
      }
    }
    std::printf(
        "[ info ] %-16s (%s) 100 steps of δ = 1e-3 … 3.6 half periods: worst %.1f ε (1 + phase)\n",
        c.name, probe.dual ? "N" : "n", worst);
  }
  EXPECT_TRUE(saw_n);
  EXPECT_TRUE(saw_N);
  EXPECT_TRUE(saw_small);
  EXPECT_TRUE(saw_large);
}

// Coasting (freeFlowAt): the state k steps after `from`, as one evaluation from the anchor.
// Truth: a second method, k calls of exactFreeFlow(h) from the same state (which take their
// phases by the addition theorems within runs of 32). Bodies of every path: both polhode axes,
// near the separatrix, the thin rod, a symmetric top, a sphere, and a body falling under
// gravity; k from 1 to 20 000 (phases up to 2000 rad). Tolerance as for the runs above:
// 64 ε (1 + phase) on the rotor (sign included) and w; 64 ε relative on the centre of mass
// (both evaluate x_a + v_a t + ½ g t² from the same anchor, t = k h), and on v_B = R⁻¹ v_W
// the two added (the rotor's error turns it).
TEST(FreeFlowAt, EqualsTheSteppedFlowToRoundOff) {
  struct Case {
    const char* name;
    Eigen::Vector3d J, w, g;
  };
  const Case cases[] = {{"e3 polhode", {1.0, 2.0, 3.0}, {0.3, 1.0, -2.0}, {0, 0, 0}},
                        {"e1 polhode", {1.0, 2.0, 3.0}, {2.0, 1.0, 0.3}, {0, 0, -9.81}},
                        {"near separatrix", {1.0, 2.0, 3.0}, {1e-7, 2.0, 1e-7}, {0, 0, 0}},
                        {"thin rod", {1.0, 1.0005, 1e-3}, {0.3, 0.2, 100.0}, {0, 0, 0}},
                        {"symmetric top", {1.0, 1.0, 0.4}, {0.5, -0.3, 20.0}, {0, 0, -9.81}},
                        {"sphere", {0.4, 0.4, 0.4}, {1.0, 2.0, 3.0}, {0, 0, 0}},
                        {"still, falling", {1.0, 2.0, 3.0}, {0, 0, 0}, {0.1, 0, -9.81}}};
  const int checkpoints[] = {1, 2, 31, 32, 33, 100, 1000, 4321, 20000};
  const double h = 1e-3;
  std::mt19937 rng(7);
  for (const Case& c : cases) {
    const Inertia I = principal(c.J);
    const BodyState s0 = makeState(randomRotation(rng), Eigen::Vector3d(0.3, -1.0, 2.0), c.w,
                                   Eigen::Vector3d(0.5, 0.1, -0.2), 1.0);
    FreeFlowCache stepped, coast;
    BodyState a = s0;
    int k = 0;
    for (int target : checkpoints) {
      for (; k < target; ++k) exactFreeFlow(I, 1.0, h, a, stepped, c.g);
      BodyState b;
      freeFlowAt(I, 1.0, h, target, s0, coast, c.g, b);
      const double phase = c.w.norm() * target * h;
      const double tol = 64 * kEps * (1.0 + phase);
      EXPECT_LE((a.M_WB.rotation().coeffs() - b.M_WB.rotation().coeffs()).norm(), tol)
          << c.name << ", step " << target;
      if (!c.w.isZero()) {
        EXPECT_LE((a.omega_B.rot - b.omega_B.rot).norm() / c.w.norm(), tol)
            << c.name << ", step " << target;
      }
      const Eigen::Vector3d xa = a.M_WB.translation(1.0), xb = b.M_WB.translation(1.0);
      EXPECT_LE((xa - xb).norm(), 64 * kEps * xa.norm()) << c.name << ", step " << target;
      // v_B = R⁻¹ v_W: the rotor's error turns it, on top of v_W's own rounding.
      EXPECT_LE((a.omega_B.trans - b.omega_B.trans).norm(),
                (tol + 64 * kEps) * a.omega_B.trans.norm())
          << c.name << ", step " << target;
    }
  }
}

// Coasting's premise: the state at step k is a function of k alone — the cache carries nothing
// from one evaluation to the next that changes the result. Truth: the same evaluation on a fresh
// cache. One cache evaluates the step counts in a scrambled order (back and forth across half
// periods and across the first call), and each result must equal, bit for bit, that of a cache
// that evaluates only that count. Fails if an evaluation continued from the previous one (e.g.
// by the addition theorems) or left a phase behind that the next one reads.
TEST(FreeFlowAt, DependsOnTheStepCountAlone) {
  const Eigen::Vector3d Js[] = {{1.0, 2.0, 3.0}, {1.0, 2.0, 3.0}, {1.0, 1.0, 0.4}};
  const Eigen::Vector3d ws[] = {{0.3, 1.0, -2.0}, {2.0, 1.0, 0.3}, {0.5, -0.3, 20.0}};
  const double ks[] = {5000, 3, 3, 4, 777, 2, 100000, 1, 778, 64, 33};
  std::mt19937 rng(8);
  for (int c = 0; c < 3; ++c) {
    const Inertia I = principal(Js[c]);
    const BodyState s0 = makeState(randomRotation(rng), Eigen::Vector3d(1, 2, 3), ws[c],
                                   Eigen::Vector3d(0.5, 0.1, -0.2), 1.0);
    const Eigen::Vector3d g(0, 0, -9.81);
    FreeFlowCache shared;
    for (double k : ks) {
      BodyState a, b;
      freeFlowAt(I, 1.0, 1e-3, k, s0, shared, g, a);
      FreeFlowCache fresh;
      freeFlowAt(I, 1.0, 1e-3, k, s0, fresh, g, b);
      EXPECT_EQ(a.M_WB.coefficients(), b.M_WB.coefficients()) << "case " << c << ", k " << k;
      EXPECT_EQ(a.omega_B.coefficients(), b.omega_B.coefficients()) << "case " << c << ", k " << k;
    }
  }
}

// Regression (found by Contacts.EnergyNeverRisesInARandomPile): a box spinning almost exactly
// about its smallest axis, where the computed k'² rounds to 1 + 2⁻⁵² (k² ≈ 1e-19). The addition
// theorem's constants once took k² = 1 − k'² < 0 and the state became NaN on the second step;
// k² is now formed as G/B_c² ≥ 0. Truth: the free motion keeps |L| and T, and 100 steps of h
// equal one step of 100 h. Tolerance: 64 ε relative — a closed form rebuilt each step
// (ExactFreeFlow.ConservesWorldAngularMomentumAndEnergy), over a phase of 0.4 rad.
TEST(ExactFreeFlow, SpinWhereKPrimeSquaredRoundsAboveOneStaysFinite) {
  const Inertia I =
      principal({0.0023900012230343303, 0.0036769249585143549, 0.0045961561981429427});
  const Eigen::Vector3d w0(-3.9930218490359617, -1.7996087661795938e-09, -5.0349232295196098e-10);
  const BodyState s0 = makeState(Eigen::Quaterniond::Identity(), Eigen::Vector3d::Zero(), w0,
                                 Eigen::Vector3d::Zero(), 1.0);
  FreeFlowCache cache;
  BodyState a = s0;
  exactFreeFlow(I, 1.0, 1e-3, a, cache);
  EXPECT_GT(cache.kp2, 1.0);  // the edge this test is about
  for (int i = 1; i < 100; ++i) exactFreeFlow(I, 1.0, 1e-3, a, cache);
  ASSERT_TRUE(a.allFinite());
  const BodyState b = flowSteps(I, 1.0, s0, 0.1, 1);
  const Eigen::Vector3d J = I.principalMoments();
  const double L0 = J.cwiseProduct(w0).norm(), L1 = J.cwiseProduct(a.omega_B.rot).norm();
  const double T0 = w0.dot(J.cwiseProduct(w0)),
               T1 = a.omega_B.rot.dot(J.cwiseProduct(a.omega_B.rot));
  EXPECT_NEAR(L1 / L0, 1.0, 64 * kEps);
  EXPECT_NEAR(T1 / T0, 1.0, 64 * kEps);
  EXPECT_LE(rotorDistance(a.M_WB.rotation(), b.M_WB.rotation()), 64 * kEps);
  EXPECT_LE((a.omega_B.rot - b.omega_B.rot).norm() / w0.norm(), 64 * kEps);
}

// Truth: the semigroup property once more, over 10⁶ steps: 10⁶ steps of h = 1 ms against one
// step of 1000 s. The phases are evaluated from the elapsed time (free_flow.h), so both sides
// carry only the rounding of rate·t, ω_p t and the attitude built from them: a few ulps of the
// largest phase Φ = |w|max · T (the conditioning floor; ≈ 3000 rad here, whose ulp is 4.5e-13).
// Tolerance: 16 ε (1 + Φ) ≈ 1.1e-11, about 24 ulps of Φ. Phases accumulated step by step, as
// before, drifted by ≈ 6e-17 rad per step (one rounding of the reduced phase each step; measured
// on the tennis racket by bench_work_precision): ≈ 6e-11 after 10⁶ steps, which fails it.
TEST(ExactFreeFlow, MillionStepsEqualOneLongStepToRoundOff) {
  struct Case {
    const char* name;
    Eigen::Vector3d J;
  };
  const Case cases[] = {{"spherical", {2.0, 2.0, 2.0}},
                        {"symmetric", {2.0, 2.0, 3.0}},
                        {"tennis racket", {1.0, 2.0, 3.0}}};
  std::mt19937 rng(12);
  const double h = 1e-3;
  const int n = 1000000;
  for (const Case& c : cases) {
    const Inertia I = principal(c.J);
    // Near the intermediate axis for the racket: it flips (≈ 100 flips in 1000 s).
    const Eigen::Vector3d w0(0.05, 3.0, 0.05);
    const BodyState s0 = makeState(randomRotation(rng), Eigen::Vector3d(1.0, -2.0, 0.5), w0,
                                   Eigen::Vector3d(0.2, -0.7, 1.1), 1.0);
    const BodyState a = flowSteps(I, 1.0, s0, h, n);
    const BodyState b = flowSteps(I, 1.0, s0, n * h, 1);
    const double phase = w0.norm() * n * h;
    const double tol = 16 * kEps * (1.0 + phase);
    const double d_rot = rotorDistance(a.M_WB.rotation(), b.M_WB.rotation());
    const double d_w = (a.omega_B.rot - b.omega_B.rot).norm() / w0.norm();
    const double d_x =
        (comPosition_W(a, 1.0) - comPosition_W(b, 1.0)).norm() / comPosition_W(b, 1.0).norm();
    EXPECT_LE(d_rot, tol) << c.name;
    EXPECT_LE(d_w, tol) << c.name;
    EXPECT_LE(d_x, 64 * kEps) << c.name;  // x_W + k h v_W, summed with compensation
    std::printf(
        "[ info ] %-13s 1e6 steps of 1 ms vs one of 1000 s: attitude %.1e, w %.1e, "
        "x %.1e (tolerance %.1e)\n",
        c.name, d_rot, d_w, d_x, tol);
  }
}

// ---- Conservation ---------------------------------------------------------------------------
// Truth: world L and T are constants of the free motion (and |L| exactly). Tolerance: the flow
// never compounds rotations (L_B from the elliptic phase, R = Q Rot(u, ψ) P⁻¹ with Q u = L̂_W),
// so each step's error is a few ε and does not accumulate: 1e-13 relative over 10⁴ steps leaves
// a factor ~100 on the expected ~1e-15.
TEST(ExactFreeFlow, ConservesWorldAngularMomentumAndEnergy) {
  struct Case {
    const char* name;
    Eigen::Vector3d J, w;
  };
  const Case cases[] = {{"spherical", {2.0, 2.0, 2.0}, {0.3, 1.0, -2.0}},
                        {"symmetric", {2.0, 2.0, 3.0}, {0.3, 1.0, -2.0}},
                        {"asymmetric", {1.0, 2.0, 3.0}, {0.3, 1.0, -2.0}},
                        {"asymmetric e1 polhode", {1.0, 2.0, 3.0}, {2.0, 1.0, 0.3}},
                        {"racket", {1.0, 2.0, 3.0}, {0.01, 2.0, 0.01}}};
  std::mt19937 rng(5);
  for (const Case& c : cases) {
    const Inertia I = principal(c.J);
    BodyState s = makeState(randomRotation(rng), Eigen::Vector3d::Zero(), c.w,
                            Eigen::Vector3d(1.0, 0.0, 0.0), 1.0);
    const Eigen::Vector3d L0 = angularMomentumCom_W(I, s);
    const Eigen::Vector3d p0 = linearMomentum_W(I, s, 1.0);
    const double T0 = kineticEnergy(I, s, 1.0);
    double dL = 0, dT = 0, dp = 0, dnorm = 0;
    FreeFlowCache cache;
    for (int i = 0; i < 10000; ++i) {
      exactFreeFlow(I, 1.0, 0.01, s, cache);
      dL = std::max(dL, (angularMomentumCom_W(I, s) - L0).norm() / L0.norm());
      dT = std::max(dT, std::abs(kineticEnergy(I, s, 1.0) / T0 - 1.0));
      dp = std::max(dp, (linearMomentum_W(I, s, 1.0) - p0).norm() / p0.norm());
      dnorm = std::max(dnorm, rotorNormError(s));
    }
    EXPECT_LE(dL, 1e-13) << c.name;
    EXPECT_LE(dT, 1e-13) << c.name;
    EXPECT_LE(dp, 1e-13) << c.name;
    EXPECT_LE(dnorm, 8 * kEps) << c.name;
    std::printf("[ info ] %-22s 1e4 steps: |ΔL_W|/|L| %.1e, |ΔT|/T %.1e, |Δp|/|p| %.1e\n", c.name,
                dL, dT, dp);
  }
}

// Truth: a spin too slow for |L|² to be represented (it underflows to 0) turns the body by less
// than 1e-135 rad in the age of the universe: the flow leaves the state as it is, finite. Before,
// the asymmetric amplitudes were 0/0 and the state NaN (found by fuzz/fuzz_world_inputs.cc: a
// world couple of 1e-230 N m kicked an asymmetric box to such a spin). The same when |L|² is
// not 0 but subnormal (3.4e-323 for w = (3, −2, 1)e-162 and J = (1, 2, 3)), or normal but so small
// that the squared components times the J-ratios underflow (found again by the fuzz target: a
// force of 2.3e-159 N off the centre of mass for one step): the state is left as it is too.
TEST(ExactFreeFlow, SpinTooSlowForItsSquareIsLeftAsItIs) {
  std::mt19937 rng(13);
  for (const Eigen::Vector3d& J : {Eigen::Vector3d(1.0, 2.0, 3.0), Eigen::Vector3d(2.0, 2.0, 3.0),
                                   Eigen::Vector3d(2.0, 2.0, 2.0)}) {
    const Inertia I = principal(J);
    for (const Eigen::Vector3d& w :
         {Eigen::Vector3d(0.0, 0.0, -1e-233), Eigen::Vector3d(3e-200, -1e-190, 2e-180),
          Eigen::Vector3d(3e-162, -2e-162, 1e-162), Eigen::Vector3d(-5e-161, 2e-162, 0.0),
          Eigen::Vector3d(1e-154, 1e-156, -3e-155)}) {
      const BodyState s0 = makeState(randomRotation(rng), Eigen::Vector3d::Zero(), w,
                                     Eigen::Vector3d(1.0, 0.0, 0.0), 1.0);
      BodyState s = s0;
      FreeFlowCache cache;
      exactFreeFlow(I, 1.0, 0.01, s, cache);
      ASSERT_TRUE(s.allFinite()) << J.transpose() << " / " << w.transpose();
      EXPECT_EQ(s.omega_B.rot, s0.omega_B.rot);  // torque-free: w_B constant when it is still
    }
  }
}

// ---- RK4 cross-checks -----------------------------------------------------------------------
// Truth: the classical RK4 above at h = 1e-5 over 1 s. Its truncation error is ~(|w| h)⁴ |w| t
// ≈ 1e-18 and its round-off (compensated) ~1e-15, so 1e-9 is the required margin, not a fit.
TEST(ExactFreeFlow, SymmetricTopMatchesRk4) {
  for (const Eigen::Vector3d& J :
       {Eigen::Vector3d(2.0, 2.0, 3.0), Eigen::Vector3d(3.0, 3.0, 1.0)}) {
    const Rk4Diff d = compareWithRk4(J, Eigen::Vector3d(0.3, 1.0, 2.0), 7, 1);
    EXPECT_LE(d.rotor, 1e-9);
    EXPECT_LE(d.w, 1e-9);
    std::printf("[ info ] symmetric J=(%g,%g,%g) vs RK4: |Δq| %.1e, |Δw|/|w| %.1e\n", J[0], J[1],
                J[2], d.rotor, d.w);
  }
}

TEST(ExactFreeFlow, AsymmetricMatchesRk4) {
  struct Case {
    const char* name;
    Eigen::Vector3d J, w;
  };
  // Both polhode orientations, both signs of the circled component, and the racket.
  const Case cases[] = {{"e3 polhode", {1.0, 2.0, 3.0}, {0.3, 1.0, 2.0}},
                        {"e3 polhode, L3 < 0", {1.0, 2.0, 3.0}, {-0.3, 1.0, -2.0}},
                        {"e1 polhode", {1.0, 2.0, 3.0}, {2.0, 1.0, 0.3}},
                        {"e1 polhode, L1 < 0", {1.0, 2.0, 3.0}, {-2.0, 0.5, -0.3}},
                        {"racket", {1.0, 2.0, 3.0}, {0.01, 2.0, 0.01}},
                        {"box-like", {0.05 / 3, 0.10 / 3, 0.13 / 3}, {1.0, -3.0, 2.0}}};
  unsigned seed = 2;
  for (const Case& c : cases) {
    const Rk4Diff d = compareWithRk4(c.J, c.w, 3, seed++);
    EXPECT_LE(d.rotor, 1e-9) << c.name;
    EXPECT_LE(d.w, 1e-9) << c.name;
    std::printf("[ info ] asymmetric %-20s vs RK4: |Δq| %.1e, |Δw|/|w| %.1e\n", c.name, d.rotor,
                d.w);
  }
}

// ---- Hard states ------------------------------------------------------------------------------
// Truth: conservation (as above) and, where RK4 can follow the motion over 1 s, RK4 (as above).
// The states: the exact separatrix (J = (3, 4, 6), w = (2, w2, 1) gives D = 2T J2 exactly in
// floating point), states 1e-12 off it on both sides, the unstable e2 spin exactly, w = 0, and
// near-symmetric bodies just above Inertia's equal-moments threshold (1e-12) up to 1e-6, with
// the polhode around either axis. Tolerances as in the tests above.
TEST(ExactFreeFlow, SeparatrixAndNearSymmetricStatesStayExact) {
  struct Case {
    const char* name;
    Eigen::Vector3d J, w;
  };
  const double d11 = 1e-11, d8 = 1e-8, d6 = 1e-6;
  const Case cases[] = {
      {"separatrix", {3.0, 4.0, 6.0}, {2.0, 0.5, 1.0}},
      {"separatrix, L1 L3 < 0", {3.0, 4.0, 6.0}, {-2.0, 0.5, -1.0}},
      {"separatrix + 1e-12", {3.0, 4.0, 6.0}, {2.0, 0.5, 1.0 + 1e-12}},
      {"separatrix - 1e-12", {3.0, 4.0, 6.0}, {2.0, 0.5, 1.0 - 1e-12}},
      {"e2 spin", {1.0, 2.0, 3.0}, {0.0, 2.0, 0.0}},
      {"e3 spin", {1.0, 2.0, 3.0}, {0.0, 0.0, -2.0}},
      {"at rest", {1.0, 2.0, 3.0}, {0.0, 0.0, 0.0}},
      {"oblate 1e-11, e3 polhode", {2.0, 2.0 * (1 + d11), 3.0}, {0.3, 1.0, 2.0}},
      {"oblate 1e-8, e1 polhode", {2.0, 2.0 * (1 + d8), 3.0}, {2.0, 1.0, 1e-5}},
      {"oblate 1e-6, e3 polhode", {2.0, 2.0 * (1 + d6), 3.0}, {0.3, 1.0, 2.0}},
      {"prolate 1e-11, e1 polhode", {1.0, 3.0, 3.0 * (1 + d11)}, {2.0, 1.0, 0.5}},
      {"prolate 1e-8, e3 polhode", {1.0, 3.0, 3.0 * (1 + d8)}, {1e-5, 1.0, 0.5}},
  };
  std::mt19937 rng(3);
  for (const Case& c : cases) {
    const Inertia I = principal(c.J);
    ASSERT_TRUE(I.inertiaClass() == InertiaClass::kAsymmetric) << c.name;
    const BodyState s0 = makeState(randomRotation(rng), Eigen::Vector3d::Zero(), c.w,
                                   Eigen::Vector3d(0.0, 1.0, 0.0), 1.0);
    // Conservation over 10⁴ steps of 0.01 s (100 s: many polhode periods, or far along the
    // separatrix).
    BodyState s = s0;
    const Eigen::Vector3d L0 = angularMomentumCom_W(I, s);
    const double T0 = kineticEnergy(I, s, 1.0);
    double dL = 0, dT = 0;
    FreeFlowCache cache;
    for (int i = 0; i < 10000; ++i) {
      exactFreeFlow(I, 1.0, 0.01, s, cache);
      ASSERT_TRUE(s.allFinite()) << c.name << " step " << i;
      dL = std::max(dL, (angularMomentumCom_W(I, s) - L0).norm() / std::max(L0.norm(), 1e-300));
      dT = std::max(dT, std::abs(kineticEnergy(I, s, 1.0) - T0) / T0);
    }
    EXPECT_LE(dL, 1e-13) << c.name;
    EXPECT_LE(dT, 1e-13) << c.name;
    // Accuracy over 1 s against RK4 (for w = 0 too: RK4 keeps it still).
    BodyState e = flowSteps(I, 1.0, s0, 0.25, 4);
    const Rk4State r = rk4(toRk4(s0), I.principalMoments(), Eigen::Vector3d::Zero(), 1e-5, 100000);
    const double dq = rotorDistance(e.M_WB.rotation(), rk4Rotor(r));
    const double dw = (e.omega_B.rot - r.w).norm() / std::max(c.w.norm(), 1.0);
    EXPECT_LE(dq, 1e-9) << c.name;
    EXPECT_LE(dw, 1e-9) << c.name;
    std::printf("[ info ] %-26s |ΔL_W|/|L| %.1e |ΔT|/T %.1e; vs RK4 |Δq| %.1e |Δw| %.1e\n", c.name,
                dL, dT, dq, dw);
  }
}

// ---- The CGA conventions -----------------------------------------------------------------------
// Truth: the kinematics (E5) of doc/conventions.md, Ω_B = −2 M̃ Ṁ, i.e.
// M(t + δ) = M(t) exp(−½ δ Ω_B) to first order.
// The flow's motor over a short step, read back through the algebra's own logarithm,
// −(2/δ) log(M̃(t) M(t + δ)), must equal Ω_B at the midpoint t + δ/2 (a symmetric difference:
// error ≈ δ² |Ω̈|/24 ≈ 3e-10 relative at δ = 3e-5 and |w| ≈ 2 rad/s, plus the round-off of the
// difference quotient, ≈ ε |x|/(δ |v|) ≈ 2e-11). 1e-8 relative checks the sense of rotation and
// of translation, which a sign error would change at O(1).
TEST(ExactFreeFlow, KinematicsFollowTheMotorConvention) {
  const double delta = 3e-5;
  std::mt19937 rng(12);
  for (const Eigen::Vector3d& J : {Eigen::Vector3d(2.0, 2.0, 2.0), Eigen::Vector3d(2.0, 2.0, 3.0),
                                   Eigen::Vector3d(1.0, 2.0, 3.0)}) {
    const Inertia I = principal(J);
    const BodyState s0 =
        makeState(randomRotation(rng), Eigen::Vector3d(0.5, -1.0, 2.0),
                  Eigen::Vector3d(0.3, 1.0, -2.0), Eigen::Vector3d(0.7, -0.2, 0.4), 1.0);
    const BodyState s1 = flowSteps(I, 1.0, s0, delta, 1);
    const BodyState mid = flowSteps(I, 1.0, s0, 0.5 * delta, 1);
    const cga::Bivelocity omega = (-2.0 / delta) * cga::log(s0.M_WB.reverse() * s1.M_WB);
    const double dw = (omega.rot - mid.omega_B.rot).norm() / mid.omega_B.rot.norm();
    const double dv = (omega.trans - mid.omega_B.trans).norm() / mid.omega_B.trans.norm();
    EXPECT_LE(dw, 1e-8) << J.transpose();
    EXPECT_LE(dv, 1e-8) << J.transpose();
    std::printf("[ info ] J=(%g,%g,%g): −(2/δ) log(M̃ M(δ)) vs Ω_B(δ/2): %.1e (w), %.1e (v/λ)\n",
                J[0], J[1], J[2], dw, dv);
  }
}

// ---- The cache ----------------------------------------------------------------------------
// Truth: a stale cache must never be used. After an impulse changes w between steps, stepping
// with the old cache must give exactly what a fresh cache gives (the rebuild is deterministic).
TEST(ExactFreeFlow, CacheIsRebuiltWhenTheStateChanges) {
  const Inertia I = principal({1.0, 2.0, 3.0});
  std::mt19937 rng(9);
  BodyState s = makeState(randomRotation(rng), Eigen::Vector3d::Zero(), {0.3, 1.0, 2.0},
                          {0.1, 0.0, 0.0}, 1.0);
  FreeFlowCache cache;
  for (int i = 0; i < 5; ++i) exactFreeFlow(I, 1.0, 0.1, s, cache);
  s.omega_B.rot += Eigen::Vector3d(0.2, -0.1, 0.05);  // an impulse
  BodyState a = s, b = s;
  FreeFlowCache fresh;
  exactFreeFlow(I, 1.0, 0.1, a, cache);
  exactFreeFlow(I, 1.0, 0.1, b, fresh);
  EXPECT_EQ(a.M_WB.coefficients(), b.M_WB.coefficients());
  EXPECT_EQ(a.omega_B.coefficients(), b.omega_B.coefficients());
}

// Truth (doc/conventions.md#length-scale-lambda): results do not depend on λ beyond round-off,
// 1e-12 relative; the λ-dependent parts are one scaling of v and of the motor's dual part per step.
TEST(ExactFreeFlow, IndependentOfLambda) {
  const Inertia I = principal({1.0, 2.0, 3.0});
  std::mt19937 rng(4);
  const Eigen::Quaterniond R = randomRotation(rng);
  const Eigen::Vector3d x(1.0, -2.0, 0.5), w(0.3, 1.0, 2.0), v(0.2, -0.7, 1.1);
  const BodyState a = flowSteps(I, 1.0, makeState(R, x, w, v, 1.0), 0.05, 100);
  const BodyState b = flowSteps(I, 7.3, makeState(R, x, w, v, 7.3), 0.05, 100);
  EXPECT_LE(rotorDistance(a.M_WB.rotation(), b.M_WB.rotation()), 1e-12);
  EXPECT_LE((comPosition_W(a, 1.0) - comPosition_W(b, 7.3)).norm() / comPosition_W(a, 1.0).norm(),
            1e-12);
  EXPECT_LE((comVelocity_W(a, 1.0) - comVelocity_W(b, 7.3)).norm() / v.norm(), 1e-12);
  EXPECT_LE((a.omega_B.rot - b.omega_B.rot).norm() / w.norm(), 1e-12);
}

// ---- The integrator -----------------------------------------------------------------------------
// MuJoCo's free-body gyroscopic test (a uniform box of half-sizes 0.1/0.2/0.3 m, h = 5 ms,
// 20 000 steps; MuJoCo bounds the energy growth at 1%), made stricter. Truth: kinetic energy is
// conserved. Tolerance: T is computed from L_B on the elliptic phase, so its error is a few ε per
// evaluation and does not grow with the step count: 1e-12 relative.
TEST(ExactIntegrator, MujocoBoxKeepsKineticEnergy) {
  const double a = 0.1, b = 0.2, c = 0.3, m = 1.0;
  const Eigen::Vector3d J_F =
      m / 3.0 * Eigen::Vector3d(b * b + c * c, a * a + c * c, a * a + b * b);
  const Inertia I = principal(J_F, m);
  const Eigen::Quaterniond R_FB = I.rotationFromPrincipal();
  for (const Eigen::Vector3d& w_F :
       {Eigen::Vector3d(0.05, 5.0, 0.05), Eigen::Vector3d(20.0, 0.05, 0.05)}) {
    // The box starts aligned with the world; its body axes are the principal axes B.
    BodyState s = makeState(R_FB, Eigen::Vector3d::Zero(), R_FB.conjugate() * w_F,
                            Eigen::Vector3d::Zero(), 1.0);
    ExactIntegrator integrator;
    const Loads no_loads;
    const double T0 = kineticEnergy(I, s, 1.0);
    double dT = 0;
    for (int i = 0; i < 20000; ++i) {
      integrator.step(I, no_loads, 1.0, 0.005, s);
      dT = std::max(dT, std::abs(kineticEnergy(I, s, 1.0) / T0 - 1.0));
    }
    EXPECT_LE(dT, 1e-12) << "w_F = " << w_F.transpose();
    std::printf("[ info ] MuJoCo box w_F=(%g,%g,%g): max |ΔT|/T over 20000 steps %.1e\n", w_F[0],
                w_F[1], w_F[2], dT);
  }
}

// Truth: under uniform gravity alone the centre of mass follows x0 + v0 t + ½ g t² whatever the
// spin (kick–drift–kick is exact for a constant acceleration). Tolerance: each step rounds x and
// v once (a few ε relative), 1000 steps: ~1e-13; 1e-12 relative is required.
TEST(ExactIntegrator, GravityAloneGivesTheExactParabolaWhileSpinning) {
  const Inertia I = principal({0.05, 0.1, 0.13}, 2.0);
  std::mt19937 rng(8);
  const Eigen::Quaterniond R0 = randomRotation(rng);
  const Eigen::Vector3d x0(1.0, -2.0, 3.0), v0_W(2.0, 1.0, 8.0), g(0.0, 0.0, -9.81);
  const double lambda = 1.0, h = 0.01;
  BodyState s =
      makeState(R0, x0, Eigen::Vector3d(30.0, -40.0, 25.0), R0.conjugate() * v0_W, lambda);
  Loads loads;
  loads.setGravity(g);
  ExactIntegrator integrator;
  const BodyState free0 = s;
  double dx = 0, dv = 0;
  for (int i = 1; i <= 1000; ++i) {
    integrator.step(I, loads, lambda, h, s);
    const double t = i * h;
    const Eigen::Vector3d x = x0 + v0_W * t + 0.5 * g * t * t, v = v0_W + g * t;
    dx = std::max(dx, (comPosition_W(s, lambda) - x).norm() / x.norm());
    dv = std::max(dv, (comVelocity_W(s, lambda) - v).norm() / v.norm());
  }
  EXPECT_LE(dx, 1e-12);
  EXPECT_LE(dv, 1e-12);
  // Gravity exerts no torque: the attitude is the free one.
  const BodyState f = flowSteps(I, lambda, free0, 10.0, 1);
  EXPECT_LE(rotorDistance(s.M_WB.rotation(), f.M_WB.rotation()), 1e-11);
  std::printf("[ info ] gravity parabola over 10 s: |Δx|/|x| %.1e, |Δv|/|v| %.1e\n", dx, dv);
}

// Truth: v(t) = v0 + g t for a body that does not spin (the rotation's "still" path). A
// regression: the state's v_B was left at v0 while x followed the parabola, so momentum and the
// contacts saw a body that did not fall. Tolerance as in the test above (1e-12 relative).
TEST(ExactIntegrator, GravityAloneWithoutSpinUpdatesTheVelocity) {
  const Inertia I = principal({0.05, 0.1, 0.13}, 2.0);
  const Eigen::Vector3d x0(1.0, -2.0, 3.0), v0_W(2.0, 1.0, 8.0), g(0.0, 0.0, -9.81);
  const double lambda = 1.0, h = 0.01;
  BodyState s =
      makeState(Eigen::Quaterniond::Identity(), x0, Eigen::Vector3d::Zero(), v0_W, lambda);
  Loads loads;
  loads.setGravity(g);
  ExactIntegrator integrator;
  for (int i = 0; i < 100; ++i) integrator.step(I, loads, lambda, h, s);
  const Eigen::Vector3d v = v0_W + g * 1.0;
  EXPECT_LE((comVelocity_W(s, lambda) - v).norm() / v.norm(), 1e-12);
}

// Truth: the exact parabola x0 + v0 t + ½ g t² over 10⁷ steps (h = 0.1 ms, t = 1000 s) while
// the body spins. Each step rounds v (the kicks, the rotation of v_B to the world) by a few ε
// in no fixed direction, so x wanders like a random walk: ≈ ε √N · |x| ≈ 1e-13 relative; the
// compensated sum keeps the additions themselves from adding N roundings of the same sign
// (≈ N ε ≈ 2e-9, what accumulating x_W += h v_W gave). Tolerance 1e-11 relative: 100× the
// random walk, 200× below the linear drift.
TEST(ExactIntegrator, TenMillionStepsUnderGravityStayOnTheParabola) {
  const Inertia I = principal({0.05, 0.1, 0.13}, 2.0);
  std::mt19937 rng(9);
  const Eigen::Quaterniond R0 = randomRotation(rng);
  const Eigen::Vector3d x0(1.0, -2.0, 3.0), v0_W(2.0, 1.0, 8.0), g(0.0, 0.0, -9.81);
  const double lambda = 1.0, h = 1e-4;
  const int n = 10000000;
  BodyState s = makeState(R0, x0, Eigen::Vector3d(3.0, -4.0, 2.5), R0.conjugate() * v0_W, lambda);
  Loads loads;
  loads.setGravity(g);
  ExactIntegrator integrator;
  for (int i = 0; i < n; ++i) integrator.step(I, loads, lambda, h, s);
  const double t = n * h;
  const Eigen::Vector3d x = x0 + v0_W * t + 0.5 * g * t * t, v = v0_W + g * t;
  const double dx = (comPosition_W(s, lambda) - x).norm() / x.norm();
  const double dv = (comVelocity_W(s, lambda) - v).norm() / v.norm();
  EXPECT_LE(dx, 1e-11);
  EXPECT_LE(dv, 1e-11);
  std::printf("[ info ] gravity parabola over 1e7 steps (1000 s): |Δx|/|x| %.1e, |Δv|/|v| %.1e\n",
              dx, dv);
}

// Truth: with a torque the splitting is second order: against RK4 at h = 1e-5 (error ~1e-18),
// halving h divides the error at t = 1 s by 4. Tolerance: ratio in [3.5, 4.5] (the O(h⁴) term
// of a symmetric method shifts it by ≲ (ωh)² ≈ 1%).
TEST(ExactIntegrator, SecondOrderWithTorque) {
  const Inertia I = principal({1.0, 2.0, 3.0});
  std::mt19937 rng(6);
  const BodyState s0 = makeState(randomRotation(rng), Eigen::Vector3d::Zero(), {0.3, 1.0, 2.0},
                                 Eigen::Vector3d::Zero(), 1.0);
  const Eigen::Vector3d tau_B(0.4, -0.3, 0.2);
  Loads loads;
  AppliedLoad couple;
  couple.axes = Axes::kBody;
  couple.couple = tau_B;
  loads.add(couple);
  const Rk4State r = rk4(toRk4(s0), I.principalMoments(), tau_B, 1e-5, 100000);
  double err[2];
  for (int k = 0; k < 2; ++k) {
    const int n = 50 << k;
    BodyState s = s0;
    ExactIntegrator integrator;
    for (int i = 0; i < n; ++i) integrator.step(I, loads, 1.0, 1.0 / n, s);
    err[k] = rotorDistance(s.M_WB.rotation(), rk4Rotor(r)) + (s.omega_B.rot - r.w).norm();
  }
  EXPECT_GT(err[0] / err[1], 3.5);
  EXPECT_LT(err[0] / err[1], 4.5);
  std::printf("[ info ] torque: error %.2e (h = 0.02) %.2e (h = 0.01), ratio %.2f\n", err[0],
              err[1], err[0] / err[1]);
}

// Truth: the registry finds it as "exact", and without loads its step is exactFreeFlow itself
// (same code, same cache), so the two agree bit for bit.
TEST(ExactIntegrator, NameAndFreeStepIsTheExactFlow) {
  ExactIntegrator integrator;
  EXPECT_STREQ(integrator.name(), "exact");
  const Inertia I = principal({1.0, 2.0, 3.0});
  const BodyState s0 = makeState(Eigen::Quaterniond::Identity(), Eigen::Vector3d(1, 2, 3),
                                 {0.3, 1.0, 2.0}, {0.1, 0.2, 0.3}, 1.0);
  BodyState a = s0;
  for (int i = 0; i < 3; ++i) integrator.step(I, Loads(), 1.0, 0.1, a);
  const BodyState b = flowSteps(I, 1.0, s0, 0.1, 3);
  EXPECT_EQ(a.M_WB.coefficients(), b.M_WB.coefficients());
  EXPECT_EQ(a.omega_B.coefficients(), b.omega_B.coefficients());
}

}  // namespace exact_test
}  // namespace dynamics
}  // namespace cga_rigid_sim
