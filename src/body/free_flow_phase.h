// The elliptic phase of the exact free flow from step to step (doc/conventions.md (E29), (E32)):
// evaluated from the anchor, or advanced within a run of steps by the addition theorems, with
// the constants of a run's step. Internal: included by free_flow.cc alone, whose step inlines
// these (in an anonymous namespace, as they were in that file).
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "body/free_flow_psi.h"
#include "cga_rigid_sim/body/free_flow.h"
#include "cga_rigid_sim/math/atan_series.h"
#include "cga_rigid_sim/math/elliptic.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

using elliptic::jacobiSnCnDn;

// Elliptic path: steps per run of the addition theorems, the first of them evaluated from the
// anchor (doc/conventions.md (E32)).
constexpr int kRunLength = 32;
// Phase steps δ = ω_p h up to this size advance sn, cn, dn by their addition theorems, and any
// step when k'² is at least kWellConditionedKp2; other steps evaluate them from the anchor
// (doc/conventions.md (E32)).
constexpr double kSmallPhaseStep = 0.25;
constexpr double kWellConditionedKp2 = 0.1;

// ψ gained per half period 2K of τ beyond rate·t: Π(ν; φ + π) − F(φ + π) gains
// 2(Π(ν) − K) = 2 (ν/3) R_J(0, k'², 1, 1 − ν); Θ gains π, the dual angle Φ nothing. Computed on
// first use: a step under torque rebuilds the cache and rarely crosses a half period.
double halfPeriodThirdKindGain(const FreeFlowCache& c) {
  return 2.0 * (c.nchar / 3.0) * carlsonRJ(0.0, c.kp2, 1.0, 1.0 - c.nchar);
}

void computeHalfPeriodGain(FreeFlowCache& c) {
  c.dpsi_half = c.coef_pi * halfPeriodThirdKindGain(c);
  if (!c.dual) c.dpsi_half += c.coef_atan * kPi;
  c.dpsi_half_ready = true;
}

// The constants of a step of h for the Π addition theorem (E32): sn δ for δ = ω_p h, and
// P(δ) = Π(ν; am δ) − δ, from δ = 2K m + r, r ∈ [−K, K] (sn changes sign m times, P gains m
// half-period gains).
void buildStepConstants(double h, FreeFlowCache& c) {
  const double delta = c.omega_p * h;
  const double m = std::nearbyint(delta / (2.0 * c.K));
  const double r = std::fma(-2.0 * c.K, m, delta);
  double sn, cn, dn;
  jacobiSnCnDn(r, c, sn, cn, dn);
  c.step_small = std::abs(delta) <= kSmallPhaseStep || c.kp2 >= kWellConditionedKp2;
  c.step_cn = isOdd(m) ? -cn : cn;
  c.step_dn = dn;
  c.step_sn = isOdd(m) ? -sn : sn;
  c.step_P = (m != 0.0 ? m * halfPeriodThirdKindGain(c) : 0.0) + thirdKindGain(c, sn, cn, dn);
  // P(u + δ) = P(u) + P(δ) − A atan(B sn u sn δ sn(u + δ)/(1 − ν sn²(u + δ) + ν sn u sn δ
  // cn(u + δ) dn(u + δ))), μ = −ν ≥ 0.
  // k² = G/B_c² ≥ 0 as formed (1 − k'² can round below 0 as k → 0, where k'² rounds above 1).
  const double mu = -c.nchar;
  const double k2 = c.G / (c.Bc * c.Bc);
  if (mu > 0.0) {
    c.add_A = std::sqrt(mu / ((k2 + mu) * (1.0 + mu)));
    c.add_B = std::sqrt(mu * (k2 + mu) * (1.0 + mu));
  } else {
    c.add_A = 0.0;
    c.add_B = 0.0;
  }
  c.step_h = h;
  c.step_ready = true;
}

// The phase at the elapsed time t from the anchor (E29): τ = τ_a + ω_p t reduced by m half
// periods to τ_r ∈ [−K, K], sn, cn, dn there (cn ≥ 0), and ρ; returns m.
double phaseAt(FreeFlowCache& c, double t, double& sn, double& cn, double& dn) {
  double tau = c.tau_a + c.omega_p * t;
  double m = 0.0;
  if (std::abs(tau) > c.K) {
    m = std::nearbyint(tau / (2.0 * c.K));
    tau = std::fma(-2.0 * c.K, m, tau);
    if (!c.dpsi_half_ready) computeHalfPeriodGain(c);
  }
  c.rho = isOdd(m) ? -c.rho_a : c.rho_a;
  c.tau = tau;
  jacobiSnCnDn(tau, c, sn, cn, dn);
  return m;
}

// The angle term continued over m half periods from the anchor: Φ (periodic), or Θ + mπ.
inline double continuedAngle(const FreeFlowCache& c, double m, double sn, double cn, double dn) {
  return c.dual ? angleTerm(c, sn, cn, dn) : m * kPi + angleTerm(c, sn, cn, dn);
}

// An evaluation from the anchor (E29), which also starts a run of steps (E32):
// ψ = ψ_a + rate·t + m Δψ_half + g(τ_r) − g_a, with R_J for Π.
void evaluateFromAnchor(FreeFlowCache& c, double t, double& sn, double& cn, double& dn) {
  const double m = phaseAt(c, t, sn, cn, dn);
  const double g = periodicPsi(c, sn, cn, dn);
  c.psi = reduceAngle(c.psi_a + (c.rate * t + m * c.dpsi_half + (g - c.g_a)));
  c.g_tau = g;
  c.run_sn = c.rho * c.rho_a * sn;
  c.run_cn = c.rho * c.rho_a * cn;
  c.run_dn = dn;
  c.run_atan = 0.0;
  c.run_angle0 = continuedAngle(c, m, sn, cn, dn);
  c.run_angle = c.run_angle0;
  c.run_psi0 = c.psi;
  c.run_steps = 0;
}

// sn, cn, dn of τ + δ from those of τ by the addition theorems, for a small phase step δ, and the
// angle term continued (Φ as it is; Θ by the turn of (B_a cn, B_b sn), which is small). Then
// back onto sn² + cn² = 1 and dn = √(cn² + k'² sn²): the recurrence alone is unstable across
// those curves (an error of ε grew 1.35× per step at δ ≈ 0.7). Along the curve the error only
// adds up, and for a small step the theorems keep the relative precision of small cn and dn
// (no cancellation), which is what fixes the phase near the separatrix, where the state spends
// its time at cn, dn ≈ k' — there an absolute error ε would be a phase error ε/k'.
inline void advanceSmall(FreeFlowCache& c) {
  const double s = c.run_sn, co = c.run_cn, d = c.run_dn;
  const double sd = c.step_sn, cd = c.step_cn, dd = c.step_dn;
  double sn = s * cd * dd + sd * co * d;  // the common denominator cancels below
  double cn = co * cd - s * sd * d * dd;
  const double inv_r = 1.0 / std::sqrt(sn * sn + cn * cn);
  sn *= inv_r;
  cn *= inv_r;
  const double dn = std::sqrt(cn * cn + c.kp2 * sn * sn);
  if (c.dual) {
    c.run_angle = angleTerm(c, sn, cn, dn);
  } else {
    // Θ continued by the principal turn from the old to the new (B_a cn, B_b sn). A step over
    // a whole half period turns it by π or more, which this reads 2π short; that changes ψ by
    // 2π γ, and γ = 1 identically (1 to 7e-16 on 10⁵ random bodies), so ψ mod 2π — all the
    // rotor takes — is unchanged.
    c.run_angle += atan2NearZero(c.Ba * c.Bb * (co * sn - s * cn),
                                 c.Ba * c.Ba * co * cn + c.Bb * c.Bb * s * sn);
  }
  c.run_sn = sn;
  c.run_cn = cn;
  c.run_dn = dn;
}

// A step within a run (E32). Π's part of ψ comes from the addition theorem instead of R_J:
// P(τ) − P(τ_run) = j P(δ) − A Σ atan(…), summed over the run's steps, with sn, cn, dn signed as
// continued from the anchor. For a small phase step δ, sn, cn, dn come from their own addition
// theorems too (advanceSmall); otherwise from the anchor (phaseAt).
void stepInRun(FreeFlowCache& c, double t, double h, double& sn, double& cn, double& dn) {
  const double s_old = c.run_sn;
  double angle;
  if (c.step_small) {
    advanceSmall(c);
    c.rho = c.rho_a;  // sn, cn below are continued from the anchor, signs included
    sn = c.run_sn;
    cn = c.run_cn;
    dn = c.run_dn;
    angle = c.run_angle;
  } else {
    const double m = phaseAt(c, t, sn, cn, dn);
    const double sign = c.rho * c.rho_a;
    c.run_sn = sign * sn;
    c.run_cn = sign * cn;
    c.run_dn = dn;
    angle = continuedAngle(c, m, sn, cn, dn);
  }
  const double ss = s_old * c.step_sn;
  const double den = 1.0 - c.nchar * (c.run_sn * c.run_sn) + c.nchar * ss * c.run_cn * c.run_dn;
  c.run_atan += atanNearZero(c.add_B * ss * c.run_sn / den);
  const double j = ++c.run_steps;
  c.psi = reduceAngle(c.run_psi0 +
                      (c.rate * (j * h) + c.coef_pi * (j * c.step_P - c.add_A * c.run_atan) +
                       c.coef_atan * (angle - c.run_angle0)));
}

}  // namespace
}  // namespace dynamics
}  // namespace cga_rigid_sim
