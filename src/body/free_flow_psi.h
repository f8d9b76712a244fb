// The angle ψ of the exact free flow about L as a function of the elliptic phase, and L_B from
// the phase (doc/conventions.md, "The asymmetric flow derived", (E22), (E28)-(E30)). Internal:
// included by free_flow_constants.cc (a new cache's phase and ψ) and free_flow_phase.h (the
// steps); in an anonymous namespace, so that each of those files keeps them local, free to
// inline, as before the split into files.
#pragma once

#include <Eigen/Core>
#include <cmath>

#include "cga_rigid_sim/body/free_flow.h"
#include "cga_rigid_sim/math/constants.h"
#include "cga_rigid_sim/math/elliptic.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

using Path = FreeFlowCache::Path;
using elliptic::carlsonRJ;
using math::kPi;

// x reduced to [−π, π] by a whole number of turns. 2π is split into the double nearest to it
// and the remainder, so the reduction itself adds no systematic error per turn (a plain
// remainder by fl(2π) would lose 2.4e-16 rad per turn removed). The number of turns comes from
// a product with 1/(2π) (no division on the hot path); where that rounds to the other side of
// a half turn the result is ±π within an ulp, the same rotation.
inline double reduceAngle(double x) {
  constexpr double kInvTwoPi = 0.15915494309189535;
  if (std::abs(x) <= kPi) return x;
  const double m = std::nearbyint(x * kInvTwoPi);
  return std::fma(-m, math::kTwoPi, x) - m * math::kTwoPiLo;
}

// Whether the whole number m is odd (every double beyond 2⁵³ is even).
inline bool isOdd(double m) {
  return std::abs(m) < 9007199254740992.0 && (static_cast<long long>(m) & 1) != 0;
}

// The angle term of g ((E28), (E29)): Θ = atan2(B_b sn, B_a cn) for the characteristic n
// (continued across its branch cuts by the caller), and for N the periodic
// Φ = atan2(B_a B_b sn cn (ℓ − B_c dn), B_a² B_c dn cn² + B_b² ℓ sn²) with
// ℓ − B_c dn = (B_a² + k² B_c² sn²)/(ℓ + B_c dn) (no cancellation).
inline double angleTerm(const FreeFlowCache& c, double sn, double cn, double dn) {
  if (!c.dual) return std::atan2(c.Bb * sn, c.Ba * cn);
  // Φ's denominator is positive (dn > 0, and cn, sn never vanish together): atan of the ratio.
  // Φ = atan(B_a B_b sn cn (ℓ − B_c dn) / den), with ℓ − B_c dn = num/(ℓ + B_c dn): one division.
  const double num = c.Ba * c.Ba + c.G * sn * sn;
  const double den = c.Ba * c.Ba * c.Bc * dn * cn * cn + c.Bb * c.Bb * c.ell * sn * sn;
  return std::atan((c.Ba * c.Bb * sn * cn * num) / ((c.ell + c.Bc * dn) * den));
}

// Π(ν; am τ) − τ = (ν/3) sn³ R_J(cn², dn², 1, 1 − ν sn²) for a reduced phase (|am τ| ≤ π/2).
inline double thirdKindGain(const FreeFlowCache& c, double sn, double cn, double dn) {
  if (sn == 0.0) return 0.0;
  const double s2 = sn * sn;
  return (c.nchar / 3.0) * s2 * sn * carlsonRJ(cn * cn, dn * dn, 1.0, 1.0 - c.nchar * s2);
}

// The periodic part g of the angle about L for a reduced phase (sn, cn ≥ 0, dn):
//   g = coef_pi (Π(ν; am τ) − τ) + coef_atan (Θ or Φ).
inline double periodicPsi(const FreeFlowCache& c, double sn, double cn, double dn) {
  return c.coef_pi * thirdKindGain(c, sn, cn, dn) + c.coef_atan * angleTerm(c, sn, cn, dn);
}

// The same on the separatrix (k = 1: sn = tanh τ, cn = dn = sech τ, no reduction), where
// Π(N; am τ, 1) is elementary: g = −β (B_a B_c/ℓ²) atan((B_a/B_c) tanh τ) + γ Φ (dual form).
inline double separatrixPsi(const FreeFlowCache& c, double sn, double cn) {
  const double ell_minus = (c.Ba * c.Ba + c.G * sn * sn) / (c.ell + c.Bc * cn);
  return c.coef_pi * std::atan((c.Ba / c.Bc) * sn) +
         c.coef_atan *
             std::atan2(c.Ba * c.Bb * sn * cn * ell_minus,
                        c.Ba * c.Ba * c.Bc * cn * cn * cn + c.Bb * c.Bb * c.ell * sn * sn);
}

// L_B from the elliptic functions of the current phase.
inline Eigen::Vector3d ellipticL(const FreeFlowCache& c, double sn, double cn, double dn) {
  Eigen::Vector3d L;
  L[c.ia] = c.rho * c.Ba * cn;
  L[c.ib] = c.rho * c.sigma * c.Bb * sn;
  L[c.ic] = c.sigma * c.Bc * dn;
  return L;
}

}  // namespace
}  // namespace dynamics
}  // namespace cga_rigid_sim
