#include "cga_rigid_sim/body/free_flow.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "cga_rigid_sim/body/loads.h"
#include "cga_rigid_sim/math/atan_series.h"
#include "cga_rigid_sim/math/elliptic.h"
#include "cga_rigid_sim/math/sin_cos.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

using Path = FreeFlowCache::Path;
using elliptic::buildAgm;
using elliptic::carlsonRF;
using elliptic::carlsonRJ;
using elliptic::jacobiSnCnDn;

// The cache is per body (free_flow.h): keep it from growing back unnoticed. 832 bytes on LP64
// (8-byte double, 16-byte aligned Eigen 4-vectors).
static_assert(sizeof(void*) != 8 || sizeof(FreeFlowCache) <= 832,
              "FreeFlowCache grew: it is held per body by the exact and auto integrators");

using math::kPi;
using math::sinCosReduced;
// Elliptic path: steps per run of the addition theorems, the first of them evaluated from the
// anchor (doc/conventions.md (E32)).
constexpr int kRunLength = 32;
// Phase steps δ = ω_p h up to this size advance sn, cn, dn by their addition theorems, and any
// step when k'² is at least kWellConditionedKp2; other steps evaluate them from the anchor
// (doc/conventions.md (E32)).
constexpr double kSmallPhaseStep = 0.25;
constexpr double kWellConditionedKp2 = 0.1;

// |L|² (kg² m⁴/s²) below which a spin counts as still. The asymmetric amplitudes square the
// components of L and multiply them by ratios of J-differences (down to about 1e-12 × J_a/J_b,
// kEqualMomentsRelTol), so |L|² has to stay far above the smallest normal double (2.2e-308)
// for none of them to underflow to 0 and turn the amplitudes into 0/0: with 1e-250 they stay
// above 1e-280 for moments within 1e18 of each other. Such a spin (|L| < 1e-125 kg m²/s, i.e.
// |w| < 1e-113 rad/s even for J = 1e-12 kg m²) turns the body by less than 1e-95 rad in the
// age of the universe.
constexpr double kStillMomentumSquared = 1e-250;

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

// The rotation by ψ about the unit axis u, (cos ψ/2, sin ψ/2 u), for ψ ∈ [−π, π] (reduced: the
// half angle is within sinCosReduced's range).
inline Eigen::Quaterniond axisAngle(const Eigen::Vector3d& u, double psi) {
  double s, c;
  sinCosReduced(0.5 * psi, s, c);
  return Eigen::Quaterniond(c, s * u.x(), s * u.y(), s * u.z());
}

// The shortest rotation taking the unit vector u to the unit vector a: (1 + u·a, u × a),
// normalised. Well conditioned while u·a stays away from −1; the callers keep u·a ≥ 0.
inline Eigen::Quaterniond swing(const Eigen::Vector3d& u, const Eigen::Vector3d& a) {
  const Eigen::Vector3d x = u.cross(a);
  Eigen::Quaterniond p(1.0 + u.dot(a), x.x(), x.y(), x.z());
  p.normalize();
  return p;
}

// The angle term of g (see the derivation above exactFreeFlow): Θ = atan2(B_b sn, B_a cn) for
// the characteristic n (continued across its branch cuts by the caller), and for N the periodic
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

inline Eigen::Vector3d referenceAxis(const FreeFlowCache& c) {
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  u[c.ic] = c.sigma;
  return u;
}

// R = Q Rot(u, ψ) P⁻¹, P the shortest rotation taking u = σ e_c to â = L̂_B. With
// Rot(u, ψ) = (cos ψ/2, sin ψ/2 u) and P = (1 + σ a_c, σ e_c × â)/|…|, the product
// Rot(u, ψ) P⁻¹ = (cos ψ/2 · P_0, −cos ψ/2 · P_v + sin ψ/2 (P_0 u + â_⊥/|…|)), â_⊥ the part of â
// across e_c, is formed by components (u is a principal axis) and then carried by Q.
inline Eigen::Quaterniond attitude(const FreeFlowCache& c, const Eigen::Vector3d& L_B) {
  const int i0 = c.ic, i1 = i0 == 2 ? 0 : i0 + 1, i2 = i0 == 0 ? 2 : i0 - 1;  // cyclic
  const double inv_ell = c.inv_ell;
  const double a0 = L_B[i0] * inv_ell, a1 = L_B[i1] * inv_ell, a2 = L_B[i2] * inv_ell;
  const double p0 = 1.0 + c.sigma * a0, p1 = -c.sigma * a2, p2 = c.sigma * a1;  // P unnormalised
  const double inv_norm = 1.0 / std::sqrt(p0 * p0 + p1 * p1 + p2 * p2);
  double sz, cz;
  sinCosReduced(0.5 * c.psi, sz, cz);  // ψ ∈ [−π, π]
  cz *= inv_norm;
  sz *= inv_norm;
  Eigen::Quaterniond zp;
  zp.w() = cz * p0;
  zp.vec()[i0] = sz * c.sigma * p0;
  zp.vec()[i1] = sz * a1 - cz * p1;
  zp.vec()[i2] = sz * a2 - cz * p2;
  return c.Q * zp;
}

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

// Builds the cache of an asymmetric body (J1 < J2 < J3) from its rotor r and body w ≠ 0.
void buildAsymmetric(const Eigen::Vector3d& J, const Eigen::Quaterniond& r,
                     const Eigen::Vector3d& w, FreeFlowCache& c) {
  const Eigen::Vector3d L = J.cwiseProduct(w);
  // A spin about a principal axis is a steady rotation (for e2 an unstable one; it stays exact).
  const int zeros = (L[0] == 0.0) + (L[1] == 0.0) + (L[2] == 0.0);
  if (zeros >= 2) {
    c.path = Path::kUniform;
    c.Q = r;
    c.axis = w.normalized();
    c.rate = w.norm();
    return;
  }
  // D − E J2 (D = |L|², E = 2T), from the components: its sign says which axis the polhode
  // circles (> 0: e3, < 0: e1; 0: the separatrix).
  const double d_minus_ej2 =
      L[2] * L[2] * ((J[2] - J[1]) / J[2]) - L[0] * L[0] * ((J[1] - J[0]) / J[0]);
  c.ic = d_minus_ej2 >= 0.0 ? 2 : 0;
  c.ia = 2 - c.ic;
  c.ib = 1;
  const double Ja = J[c.ia], Jb = J[c.ib], Jc = J[c.ic];
  const double La = L[c.ia], Lb = L[c.ib], Lc = L[c.ic];
  // The ratios of J-differences below are positive for either choice of c (for c = e1 all three
  // differences change sign), and each amplitude is a sum of non-negative terms.
  const double d_minus_eja = Lb * Lb * ((Jb - Ja) / Jb) + Lc * Lc * ((Jc - Ja) / Jc);
  const double La2 = La * La, Lb2 = Lb * Lb, Lc2 = Lc * Lc;
  const double Ba2 = La2 + Lb2 * (Ja * (Jc - Jb)) / (Jb * (Jc - Ja));
  const double Bb2 = Lb2 + La2 * (Jb * (Jc - Ja)) / (Ja * (Jc - Jb));
  const double Bc2 = Lc2 + Lb2 * (Jc * (Jb - Ja)) / (Jb * (Jc - Ja));
  // B_b² − B_a² = k² B_c², formed without cancellation.
  const double G = Jc * (Jb - Ja) * (La2 / (Ja * (Jc - Jb)) + Lb2 / (Jb * (Jc - Ja)));
  c.Ba = std::sqrt(Ba2);
  c.Bb = std::sqrt(Bb2);
  c.Bc = std::sqrt(Bc2);
  c.sigma = Lc < 0.0 ? -1.0 : 1.0;
  c.kp2 = ((Jc - Ja) * d_minus_ej2) / ((Jc - Jb) * d_minus_eja);
  if (c.kp2 < 0.0) c.kp2 = 0.0;  // round-off at the separatrix only
  c.omega_p = std::sqrt(((Jc - Jb) * d_minus_eja) / (Ja * Jb * Jc));
  c.G = G;
  c.ell = L.norm();
  c.inv_ell = 1.0 / c.ell;
  c.inv_J = J.cwiseInverse();
  const double beta = c.ell * (Jc - Ja) / (Ja * Jc * c.omega_p);
  const double gamma = c.Ba * c.Bc * (Jc - Ja) / (Ja * Jc * c.omega_p * c.Bb);
  // The two characteristics n = −G/B_a² and N = k²/n = −B_a²/B_c² (nN = k² ≤ 1): use the
  // smaller in magnitude, so |ν| ≤ k and no coefficient below grows like 1/ω_p times an O(1)
  // function (doc/conventions.md (E28)).
  c.dual = G * Bc2 > Ba2 * Ba2;

  // The phase of the current state: (sn, cn) ∝ (σ L_b/B_b, L_a/B_a); the sign ρ puts cn ≥ 0,
  // i.e. the phase in [−K, K].
  double sn = c.sigma * Lb / c.Bb, cn = La / c.Ba;
  c.rho = cn < 0.0 ? -1.0 : 1.0;
  sn *= c.rho;
  cn *= c.rho;
  const double norm = std::hypot(sn, cn);
  sn /= norm;
  cn /= norm;

  // Q: R(t) = Q Rot(u, ψ) P(t)⁻¹ with ψ = 0 now, so Q = R(0) P(0).
  const Eigen::Vector3d u = referenceAxis(c);
  c.Q = r * swing(u, L / c.ell);
  c.psi = 0.0;

  if (c.kp2 == 0.0) {
    // The separatrix: sn = tanh τ, cn = dn = sech τ; always the dual form.
    c.path = Path::kSeparatrix;
    c.dual = true;
    c.rate = c.ell / Jc + beta * c.omega_p * Ba2 / (c.ell * c.ell);
    c.coef_pi = -beta * c.Ba * c.Bc / (c.ell * c.ell);
    c.coef_atan = gamma;
    c.tau = cn > 0.0 ? std::asinh(sn / cn) : std::copysign(std::numeric_limits<double>::max(), sn);
    c.g_tau = separatrixPsi(c, sn, cn);
    return;
  }
  c.path = Path::kElliptic;
  c.step_ready = false;
  c.run_steps = 0;
  buildAgm(c.kp2, c);
  c.K = kPi / (2.0 * c.agm_limit);
  if (c.dual) {
    c.nchar = -Ba2 / Bc2;
    c.rate = c.ell / Jc;
    c.coef_pi = -beta;
    c.coef_atan = gamma;
  } else {
    c.nchar = -G / Ba2;
    c.rate = c.ell / Ja;
    c.coef_pi = beta;
    c.coef_atan = -gamma;
  }
  c.dpsi_half_ready = false;  // computed by the first step that crosses a half period
  const double dn2 = cn * cn + c.kp2 * sn * sn;
  // τ0 = F(φ0, k) = sn R_F(cn², dn², 1) (Carlson's form of F, valid for |φ0| ≤ π/2).
  c.tau = sn * carlsonRF(cn * cn, dn2, 1.0);
  c.g_tau = periodicPsi(c, sn, cn, std::sqrt(dn2));
}

// Rebuilds the cache from the current rotational state.
void build(const Inertia& inertia, const Eigen::Quaterniond& r, const Eigen::Vector3d& w,
           FreeFlowCache& c) {
  const Eigen::Vector3d& J = inertia.principalMoments();
  c.Q = r;
  c.psi = 0.0;
  // At rest; or not a state at all (non-finite w: left as it is for the caller's validation,
  // rather than fed to iterations that would never converge); or a spin so slow that the
  // squares below underflow (kStillMomentumSquared; e.g. after a couple of 1e-230 N m, or a
  // force of 2e-159 N at 1 m for one step): the amplitudes would be 0/0.
  if (w.isZero(0.0) || !w.allFinite() ||
      !(J.cwiseProduct(w).squaredNorm() >= kStillMomentumSquared)) {
    c.path = Path::kStill;
    return;
  }
  switch (inertia.inertiaClass()) {
    case InertiaClass::kSpherical:
      c.path = Path::kUniform;
      c.axis = w.normalized();
      c.rate = w.norm();
      return;
    case InertiaClass::kSymmetric: {
      const Eigen::Vector3d L = J.cwiseProduct(w);
      c.path = Path::kSymmetric;
      c.axis = L.normalized();
      c.rate = L.norm() / J[0];
      c.beta = w[2] * (1.0 - J[2] / J[0]);
      c.psi3 = 0.0;
      c.w0 = w;
      return;
    }
    case InertiaClass::kAsymmetric:
      buildAsymmetric(J, r, w, c);
      return;
  }
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

// Keys the cache to the state `s` (rotor r, body w) for the moments J and λ: the state the
// last step left (exactFreeFlow) or the coast's anchor (freeFlowAt).
inline void setKeys(FreeFlowCache& c, const Eigen::Vector3d& J, const Eigen::Quaterniond& r,
                    const Eigen::Vector3d& w, const BodyState& s, double lambda) {
  c.key_J = J;
  c.key_r = r.coeffs();
  c.key_w = w;
  c.key_trans = s.omega_B.trans;
  c.key_q = s.M_WB.dualQuaternion().coeffs();
  c.key_lambda = lambda;
}

// The centre of mass com_steps steps of com_h after its anchor: x_W = x_a + v_a t + ½ g t²,
// v_W = v_a + g t.
inline void centreOfMassAt(const FreeFlowCache& c, Eigen::Vector3d& x_W, Eigen::Vector3d& v_W) {
  const double t = c.com_steps * c.com_h;
  x_W = c.x_a + c.v_a * t + (0.5 * t * t) * c.com_g;
  v_W = c.v_a + c.com_g * t;
}

// The phases now become the anchor's, for steps of h counted from here.
inline void setAnchor(FreeFlowCache& c, double h) {
  c.run_steps = 0;
  c.anchor_h = h;
  c.anchor_steps = 0;
  c.psi_a = c.psi;
  c.psi3_a = c.psi3;
  c.tau_a = c.tau;
  c.g_a = c.g_tau;
  c.rho_a = c.rho;
}

// The attitude r and body angular velocity w_new at the elapsed time t = k h from the anchor;
// r and w_new come in as the anchor's (they stay so on the still path). With `runs`, the
// elliptic path takes the steps of a run by the addition theorems (E32); without, every
// call evaluates from the anchor (E29), so the result depends on t alone.
// Inlined into both callers: it is on the step's hot path (doc/decisions.md).
__attribute__((always_inline)) inline void attitudeAt(FreeFlowCache& c, double t, double h,
                                                      bool runs, Eigen::Quaterniond& r,
                                                      Eigen::Vector3d& w_new) {
  switch (c.path) {
    case Path::kNone:
    case Path::kStill:
      break;
    case Path::kUniform:
      c.psi = reduceAngle(c.psi_a + c.rate * t);
      r = c.Q * axisAngle(c.axis, c.psi);
      break;
    case Path::kSymmetric: {
      c.psi = reduceAngle(c.psi_a + c.rate * t);
      c.psi3 = reduceAngle(c.psi3_a + c.beta * t);
      double s3, c3;  // of ψ3/2
      sinCosReduced(0.5 * c.psi3, s3, c3);
      r = c.Q * axisAngle(c.axis, c.psi) * Eigen::Quaterniond(c3, 0.0, 0.0, s3);
      // w_B = Rot(e3, −ψ3) w_B(0), sin and cos of ψ3 from those of its half.
      const double s = 2.0 * s3 * c3, co = (c3 - s3) * (c3 + s3);
      w_new = Eigen::Vector3d(co * c.w0.x() + s * c.w0.y(), co * c.w0.y() - s * c.w0.x(), c.w0.z());
      break;
    }
    case Path::kElliptic: {
      double sn, cn, dn;
      if (!runs || c.anchor_steps == 1 || c.run_steps + 1 >= kRunLength || !c.step_ready) {
        evaluateFromAnchor(c, t, sn, cn, dn);
        if (runs && (!c.step_ready || c.step_h != h)) buildStepConstants(h, c);
      } else {
        stepInRun(c, t, h, sn, cn, dn);
      }
      const Eigen::Vector3d L = ellipticL(c, sn, cn, dn);
      r = attitude(c, L);
      w_new = L.cwiseProduct(c.inv_J);
      break;
    }
    case Path::kSeparatrix: {
      const double tau = c.tau_a + c.omega_p * t;
      const double sn = std::tanh(tau), cn = 1.0 / std::cosh(tau);
      const double g = separatrixPsi(c, sn, cn);
      c.psi = reduceAngle(c.psi_a + (c.rate * t + (g - c.g_a)));
      c.tau = tau;
      c.g_tau = g;
      const Eigen::Vector3d L = ellipticL(c, sn, cn, cn);
      r = attitude(c, L);
      w_new = L.cwiseProduct(c.inv_J);
      break;
    }
  }
}

}  // namespace

// The exact torque-free flow. Derived in doc/conventions.md, "The asymmetric flow derived":
// the body momentum (E26), the attitude (E27) in its well-conditioned form (E28), evaluated
// from the anchor without drift (E29), the separatrix and principal-axis spins (E30),
// near-symmetric bodies (E31), and runs of steps by the addition theorems (E32). Notation:
// L = J w the body angular momentum, ℓ = |L|, D = ℓ², E = 2T.
//
// Symmetric and spherical bodies use the closed forms of free_flow.h, with their angles likewise
// evaluated from the elapsed time (ψ_a + rate·t, ψ3_a + β t) and reduced, and w_B rebuilt from
// w_B(0) each step. The centre of mass: x_W = x_a + v_a t + ½ g t², v_W = v_a + g t from its
// anchor, v_B = R(t + h)ᵀ v_W; the motor is rebuilt in closed form as M = T(x_W) R.
void exactFreeFlow(const Inertia& inertia, double lambda, double h, BodyState& state,
                   FreeFlowCache& cache, const Eigen::Vector3d& g_W) {
  const Eigen::Quaterniond r0 = state.M_WB.rotation();
  const Eigen::Vector3d& w = state.omega_B.rot;
  const Eigen::Vector3d& J = inertia.principalMoments();

  // The cache is valid when the state is the one it left (bit for bit) for the same moments.
  const bool valid = cache.path != Path::kNone && !cache.coast && cache.key_J == J &&
                     cache.key_r == r0.coeffs() && cache.key_w == w;
  if (!valid) {
    build(inertia, r0, w, cache);
    cache.coast = false;
  }

  // Centre of mass (world): x(t) = x_a + v_a t + ½ g t², v(t) = v_a + g t, evaluated from an
  // anchor and the elapsed time t = k h. The anchor is renewed when the state is not the one
  // the last call left (a kick changed v_B, an override moved x), or h, g or λ changed; x and v
  // are then taken from where the last call left them when that part of the state is unchanged
  // (so that converting v_B and x to and from the motor does not make them random-walk).
  const bool same_lambda = valid && cache.key_lambda == lambda;
  const bool same_v = same_lambda && cache.key_trans == state.omega_B.trans;
  const bool same_x = same_lambda && cache.key_q == state.M_WB.dualQuaternion().coeffs();
  Eigen::Vector3d x_W, v_W;
  if (!same_v || !same_x || cache.com_h != h || cache.com_g != g_W) {
    // Where the last call left x and v: re-evaluated from the anchor (the cache keeps no copy),
    // by the same expression, so bit for bit what that call produced.
    if (same_x || same_v) centreOfMassAt(cache, x_W, v_W);
    cache.x_a = same_x ? x_W : state.M_WB.translation(lambda);
    cache.v_a = same_v ? v_W : Eigen::Vector3d(r0 * (lambda * state.omega_B.trans));
    cache.com_steps = 0;
    cache.com_h = h;
    cache.com_g = g_W;
  }
  cache.com_steps += 1;
  centreOfMassAt(cache, x_W, v_W);

  Eigen::Quaterniond r = r0;
  Eigen::Vector3d w_new = w;
  FreeFlowCache& c = cache;
  // The elapsed time since the anchor, t = k h (free_flow.h): a new anchor when the cache was
  // rebuilt or the step size changed.
  if (!valid || c.anchor_h != h) {
    // A new step size in the middle of a run: the phase of the anchor to come is the phase now,
    // evaluated from the old anchor (the run does not keep τ and g up to date).
    if (valid && c.path == Path::kElliptic && c.run_steps > 0) {
      double sn, cn, dn;
      evaluateFromAnchor(c, c.anchor_steps * c.anchor_h, sn, cn, dn);
    }
    setAnchor(c, h);
  }
  c.anchor_steps += 1;
  attitudeAt(c, c.anchor_steps * h, h, /*runs=*/true, r, w_new);

  state.M_WB = cga::Motor::fromPose(r, x_W, lambda);
  state.omega_B.rot = w_new;
  // A body that neither spins nor falls keeps v_B bit for bit (no round trip through v_W).
  if (c.path != Path::kStill || !g_W.isZero(0.0))
    state.omega_B.trans = Loads::toBody(r, v_W) / lambda;  // R̃ v_W, inlined
  setKeys(c, J, r, w_new, state, lambda);
}

// The same closed forms as a function of the elapsed steps alone (coasting, free_flow.h): the
// anchor is `from`, the cache is built from it once (keyed by it, so another `from` rebuilds), and
// every call evaluates from that anchor — the elliptic phase and Π by (E29), never by the runs of
// (E32) — and writes nothing the next call reads except what the build made. So the state at
// step k does not depend on which earlier steps were evaluated, or whether any were.
void freeFlowAt(const Inertia& inertia, double lambda, double h, double steps,
                const BodyState& from, FreeFlowCache& c, const Eigen::Vector3d& g_W,
                BodyState& out) {
  const Eigen::Quaterniond r0 = from.M_WB.rotation();
  const Eigen::Vector3d& w = from.omega_B.rot;
  const Eigen::Vector3d& J = inertia.principalMoments();
  const bool valid = c.coast && c.path != Path::kNone && c.key_J == J && c.key_r == r0.coeffs() &&
                     c.key_w == w && c.key_trans == from.omega_B.trans &&
                     c.key_q == from.M_WB.dualQuaternion().coeffs() && c.key_lambda == lambda &&
                     c.anchor_h == h && c.com_g == g_W;
  if (!valid) {
    build(inertia, r0, w, c);
    c.coast = true;
    setKeys(c, J, r0, w, from, lambda);
    setAnchor(c, h);
    c.x_a = from.M_WB.translation(lambda);
    c.v_a = r0 * (lambda * from.omega_B.trans);
    c.com_g = g_W;
    c.com_h = h;
  }
  const double t = steps * h;
  Eigen::Quaterniond r = r0;
  Eigen::Vector3d w_new = w;
  attitudeAt(c, t, h, /*runs=*/false, r, w_new);
  const Eigen::Vector3d x_W = c.x_a + c.v_a * t + (0.5 * t * t) * g_W;
  const Eigen::Vector3d v_W = c.v_a + g_W * t;
  out.M_WB = cga::Motor::fromPose(r, x_W, lambda);
  out.omega_B.rot = w_new;
  out.omega_B.trans = c.path != Path::kStill || !g_W.isZero(0.0)
                          ? Eigen::Vector3d(Loads::toBody(r, v_W) / lambda)
                          : Eigen::Vector3d(from.omega_B.trans);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
