// The exact flows of the parts of the cga2/cga4 splitting (integrator_cga2.h): C(τ) about L_B,
// the axis pieces R_i(τ), the drift D(τ) and the motor update that ends a flow, on plain doubles.
// Internal: included by integrator_cga2.cc alone, whose composition (compose) is compiled once per
// instruction set (target_clones); GCC inlines into such a clone only what is forced inline, so
// everything here is CGA_ALWAYS_INLINE (the .cc undefines the macro after use), and in an
// anonymous namespace, local to that file as before the split into files (GCC's code for the
// clones depends on it).
#pragma once

#include <Eigen/Geometry>
#include <cmath>

#include "cga_rigid_sim/body/integrator_cga2.h"
#include "cga_rigid_sim/math/sin_cos.h"

#define CGA_ALWAYS_INLINE __attribute__((always_inline)) inline

namespace cga_rigid_sim {
namespace dynamics {
namespace splitting {
namespace {

// The reference axis r of the split T_rot = |L|²/(2 J_r) + Σ_{i≠r} κ_i L_i²/(2 J_i), κ_i = 1 −
// J_i/J_r (integrator_cga2.h), and the order of the two axis pieces in R_a(h/2) R_b(h) R_a(h/2).
// B's axes are sorted J1 ≤ J2 ≤ J3 (inertia.h). r = 2 (the middle moment) leaves the two smallest
// coefficients, |κ_1|/J_1 = 1/J_1 − 1/J_2 and |κ_3|/J_3 = 1/J_2 − 1/J_3, and makes the step exact
// for every symmetric body (J1 = J2 or J2 = J3: one piece is the identity, the other commutes with
// the rest). The outer axis a = 1 was measured against a = 3 (doc/decisions.md, "the outer axis").
constexpr int kRef = 1, kA = 0, kB = 2;

// sin φ and versin φ of an axis rotation: math/sin_cos.h (fine, small and medium series, the
// library beyond).
using math::kSinVersinFineZ;
using math::kSinVersinMediumZ;
using math::kSinVersinSmallZ;
using math::sinVersinFine;
using math::sinVersinFineWithHalf;
using math::sinVersinLibrary;
using math::sinVersinMedium;
using math::sinVersinSmall;
// Below φ² = 2⁻⁴⁰ a piece turns by shears (rotatePiece).
constexpr double kTinyZ = 0x1p-40;

// A quaternion as four plain doubles (Hamilton, i = −e23, j = −e31, k = −e12).
struct Quat {
  double w, x, y, z;
};

CGA_ALWAYS_INLINE Quat mul(const Quat& a, const Quat& b) {
  return {
      a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z, a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
      a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x, a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w};
}
inline Quat toQuat(const Eigen::Quaterniond& q) { return {q.w(), q.x(), q.y(), q.z()}; }
inline Eigen::Quaterniond toEigen(const Quat& q) { return Eigen::Quaterniond(q.w, q.x, q.y, q.z); }

// The rotation part of a free flow while its pieces run: w, and the rotor ρ of the pieces so
// far, kept as d = ρ − 1 so that its small parts are not rounded against the 1.
struct FreeFlow {
  double w[3];
  Quat d;
};

// ρ̃ x ρ for ρ = 1 + d: a world-fixed vector x (u = v_B/λ, the loads' world-axes parts) in the
// body's axes after the flow. Written as Loads::toBody (t = 2 x × a, x + ρ_w t + t × a, a = ρ's
// vector part) with ρ_w t = t + d_w t, so that no small part is rounded against x before the sum.
// One turn by the composed rotor instead of one per piece: ρ's norm is 1 to a few ε (it is formed
// afresh every flow), and x keeps its length to that. x is doubled before the cross product (exact,
// so the same bits as doubling t): the doubling then waits for x, not for ρ, which a flow forms
// last. The sum is written out three times: GCC at -O2 keeps a loop over x in memory otherwise,
// and the next operation on x then waits for a store and a load (doc/decisions.md).
CGA_ALWAYS_INLINE void turnInto(const Quat& d, double* x) {
  const double x2[3] = {2.0 * x[0], 2.0 * x[1], 2.0 * x[2]};
  const double t[3] = {x2[1] * d.z - x2[2] * d.y, x2[2] * d.x - x2[0] * d.z,
                       x2[0] * d.y - x2[1] * d.x};
  const double c[3] = {t[1] * d.z - t[2] * d.y, t[2] * d.x - t[0] * d.z, t[0] * d.y - t[1] * d.x};
#pragma GCC unroll 3
  for (int i = 0; i < 3; ++i) x[i] += t[i] + (d.w * t[i] + c[i]);
}

// R_i(τ κ_i): the flow of κ_i L_i²/(2J_i): the body turns by φ = τ κ_i w_i about e_i; L_B turns
// by −φ about e_i; the rotor gains the factor (cos φ/2, sin φ/2 e_i) on the right
// (ṙ = ½ r ⊗ (0, ω)). `tau` here is τ κ_i.
// Rotation of L_B by −φ about e_i, (j, k) = the next axes cyclically:
//   L_j ← L_j cos φ + L_k sin φ,  L_k ← L_k cos φ − L_j sin φ,
// written on w = L/J: w_j ← w_j cos φ + (J_k/J_j) w_k sin φ (ratios from the cache): keeping w
// avoids the per-step round trip w → Jw → w, whose rounding (J·fl(1/J) ≠ 1) would bias |L|;
// a rounded ratio only perturbs the determinant of the turn by O(ε φ²).
// Rotor composition with d = ρ − 1 and ε = (−versin(φ/2), sin(φ/2) e_i):
//   ρ(1 + ε) − 1 = d + ε + d ε,  and d e_i has only four nonzero products (the sparse product).
// Only w → φ → (sin φ, versin φ) → w is on the critical path; the half angle's functions and
// the rotor run beside it. Both angles' functions are summed from their own series (at φ and at
// φ/2, each within the bounds above), which keeps the half angle off that path
// (doc/decisions.md, "each angle's functions").
//
// `carried`, when given, is a world-fixed vector in body axes (the couple of composeWorldLoads),
// turned with L_B (by −φ about e_i, with the same sin φ and versin φ or shears; its ratios are 1):
// so it is in the new axes as soon as w is, and not one rotation by the stage's rotor later.
//
// A piece turning by less than 2⁻²⁰ rad (φ² ≤ kTinyZ; e.g. the small κ of a nearly symmetric
// body) turns w by three shears instead, t = tan(φ/2): L_j += t L_k, L_k −= sin φ L_j,
// L_j += t L_k. Rounded, x + s y − versin·x loses the versin term once it is below half an ulp of
// x, and the turn then grows |L| by φ²/2 every step, a bias (doc/decisions.md, "tiny pieces turn
// by shears"); each shear has determinant 1 exactly, so its roundings do not add up to a bias.
// Below 2⁻⁴⁰ the series t = (φ/2)(1 + φ²/12), sin φ = φ(1 − φ²/6), sin(φ/2) = (φ/2)(1 − φ²/24) and
// versin(φ/2) = φ²/8 are exact to the last bit (next terms ≤ 1e-25 relative; versin(φ/2) is below
// 2⁻⁴³ and only enters the rotor against 1).
template <int I>
CGA_ALWAYS_INLINE void rotatePiece(double tau, const double* ratio, FreeFlow& f,
                                   double* carried = nullptr) {
  constexpr int J = (I + 1) % 3, K = (I + 2) % 3;
  const double phi = tau * f.w[I], z = phi * phi;
  double sh, vh;
  if (z <= kTinyZ) {
    const double s = phi - (math::kInv3 * phi) * z;
    const double t = 0.5 * phi + (0.5 / 12.0) * phi * z;
    sh = 0.5 * phi - (0.5 * math::kInv3 * 0.25) * phi * z;
    vh = 0.125 * z;
    const double wj = f.w[J] + t * (ratio[2 * I] * f.w[K]);
    f.w[K] -= s * (ratio[2 * I + 1] * wj);
    f.w[J] = wj + t * (ratio[2 * I] * f.w[K]);
    if (carried) {
      const double cj = carried[J] + t * carried[K];
      carried[K] -= s * cj;
      carried[J] = cj + t * carried[K];
    }
  } else {
    double s, k;
    if (z <= kSinVersinFineZ) {
      sinVersinFineWithHalf(phi, z, s, k, sh, vh);
    } else if (z <= kSinVersinSmallZ) {
      sinVersinSmall(phi, z, s, k);
      sinVersinSmall(0.5 * phi, 0.25 * z, sh, vh);
    } else if (z <= kSinVersinMediumZ) {
      sinVersinMedium(phi, z, s, k);
      sinVersinMedium(0.5 * phi, 0.25 * z, sh, vh);
    } else {
      sinVersinLibrary(phi, s, k);
      sinVersinLibrary(0.5 * phi, sh, vh);
    }
    const double wj = f.w[J], wk = f.w[K];
    f.w[J] = (wj + s * (ratio[2 * I] * wk)) - k * wj;
    f.w[K] = (wk - s * (ratio[2 * I + 1] * wj)) - k * wk;
    if (carried) {
      const double cj = carried[J], ck = carried[K];
      carried[J] = (cj + s * ck) - k * cj;
      carried[K] = (ck - s * cj) - k * ck;
    }
  }

  const Quat d = f.d;
  // d e_i: e_1 = i: (−x, w, z, −y); e_2 = j: (−y, −z, w, x); e_3 = k: (−z, y, −x, w).
  Quat de;
  if constexpr (I == 0) {
    de = {-d.x, d.w, d.z, -d.y};
  } else if constexpr (I == 1) {
    de = {-d.y, -d.z, d.w, d.x};
  } else {
    de = {-d.z, d.y, -d.x, d.w};
  }
  f.d = {d.w - vh * (1.0 + d.w) + sh * de.w, d.x - vh * d.x + sh * de.x, d.y - vh * d.y + sh * de.y,
         d.z - vh * d.z + sh * de.z};
  if constexpr (I == 0) f.d.x += sh;
  if constexpr (I == 1) f.d.y += sh;
  if constexpr (I == 2) f.d.z += sh;
}

CGA_ALWAYS_INLINE void refreshCache(const Inertia& inertia, Cache& cache) {
  const Eigen::Vector3d& J = inertia.principalMoments();
  if (J != cache.J) {
    cache.J = J;
    cache.couple.age = Cache::CarriedCouple::kMaxSteps;  // its |L|² is J's
    cache.inv_J = J.cwiseInverse();
    for (int i = 0; i < 3; ++i) {
      const int j = (i + 1) % 3, k = (i + 2) % 3;
      cache.ratio[2 * i] = J[k] / J[j];
      cache.ratio[2 * i + 1] = J[j] / J[k];
      cache.kappa[i] = 1.0 - J[i] / J[kRef];
      cache.g[i] = J[i] / J[kRef];
    }
  }
}

// C(τ): the flow of |L|²/(2 J_r), the first piece of a free flow. L_B stays; the body turns by
// θ = τ |L|/J_r about L_B: the rotor factor (cos|a|, sin|a| a/|a|) with a = ½ τ L_B/J_r =
// ½ τ (J/J_r) w. sin|a|/|a| and versin|a| come from the pieces' series with t = 1 (the series of
// sin t / t), so no square root is taken below |a| = 1/2. It starts the flow's rotor: d = factor
// − 1. `z_given`, when given, is |a|² known otherwise (composeWorldLoads).
CGA_ALWAYS_INLINE FreeFlow beginFreeFlow(double tau, const Cache& c, const double* w,
                                         const double* z_given = nullptr) {
  FreeFlow f;
  for (int i = 0; i < 3; ++i) f.w[i] = w[i];
  const double k = 0.5 * tau;
  const double a[3] = {k * (c.g[0] * w[0]), k * (c.g[1] * w[1]), k * (c.g[2] * w[2])};
  const double z = z_given ? *z_given : (a[0] * a[0] + a[1] * a[1]) + a[2] * a[2];
  double sigma, nu;
  if (z <= kSinVersinFineZ) {
    sinVersinFine(1.0, z, sigma, nu);
  } else if (z <= kSinVersinSmallZ) {
    sinVersinSmall(1.0, z, sigma, nu);
  } else if (z <= kSinVersinMediumZ) {
    sinVersinMedium(1.0, z, sigma, nu);
  } else {
    const double t = std::sqrt(z);
    double s;
    sinVersinLibrary(t, s, nu);
    sigma = s / t;
  }
  f.d = {-nu, sigma * a[0], sigma * a[1], sigma * a[2]};
  return f;
}

// The pieces of one Strang stage of duration τ after C(τ): R_a(τ/2) R_b(τ) R_a(τ/2).
CGA_ALWAYS_INLINE void stagePieces(double tau, const Cache& c, FreeFlow& f,
                                   double* carried = nullptr) {
  rotatePiece<kA>(0.5 * tau * c.kappa[kA], c.ratio, f, carried);
  rotatePiece<kB>(tau * c.kappa[kB], c.ratio, f, carried);
  rotatePiece<kA>(0.5 * tau * c.kappa[kA], c.ratio, f, carried);
}

// M ← M / |r| to first order, M + e M with e = (1 − n)/2 (n = |r|², n − 1 a few ε), once at the
// start of a step: the rotor factors of parts turning by a large angle have norm errors of a few
// ε, and without this the motor's norm walks by them, and v_W = r u r̃ and the centre of mass with
// it, beyond the round-off allowance. e is exact (Sterbenz) and small, so M + eM rounds without
// bias, where a scale such as (3 − n)/2 would round to 1 or 1 − ε/2 and shrink the motor a little
// every step. In the general path (kicks at the pose) it runs after the opening kick, which then
// reads the rotor as the last step left it (norm 1 + O(ε)) and does not wait for this; in
// composeWorldLoads just before the motor update, off the chain from kick to kick
// (doc/decisions.md, "renormalising the motor").
CGA_ALWAYS_INLINE void renormalise(BodyState& s) {
  const Quat r = toQuat(s.M_WB.rotorQuaternion()), q = toQuat(s.M_WB.dualQuaternion());
  const double n = (r.w * r.w + r.x * r.x) + (r.y * r.y + r.z * r.z);
  const double e = 0.5 * (1.0 - n);
  s.M_WB = cga::Motor::fromQuaternions(
      toEigen({r.w + e * r.w, r.x + e * r.x, r.y + e * r.y, r.z + e * r.z}),
      toEigen({q.w + e * q.w, q.x + e * q.x, q.y + e * q.y, q.z + e * q.z}));
}

// Ends a free flow of duration τ: the drift by τ v_B (with the u0 = v_B/λ it had at its start)
// and the composed rotor ρ = 1 + f.d:
//   M ← M T_B(τ λ u0) ρ,  i.e.  r ← r ρ,  q ← (q + r ⊗ (0, −½ τ u0)) ρ,
// and u0 turned into the new body axes (it is world-fixed during the flow).
// With loads whose force is fixed in the world, the drift's velocity (the mean over the flow, in
// the start's axes) and the one turned into the end's axes differ: `u_drift` and `u`.
CGA_ALWAYS_INLINE void endFreeFlow(const Quat& d, double tau, const double* u_drift, double* u,
                                   BodyState& s) {
  const Quat r = toQuat(s.M_WB.rotorQuaternion());
  Quat q = toQuat(s.M_WB.dualQuaternion());
  const double k = -0.5 * tau;
  const Quat rb = mul(r, Quat{0.0, k * u_drift[0], k * u_drift[1], k * u_drift[2]});
  q = {q.w + rb.w, q.x + rb.x, q.y + rb.y, q.z + rb.z};
  const Quat rd = mul(r, d), qd = mul(q, d);
  s.M_WB = cga::Motor::fromQuaternions(toEigen({r.w + rd.w, r.x + rd.x, r.y + rd.y, r.z + rd.z}),
                                       toEigen({q.w + qd.w, q.x + qd.x, q.y + qd.y, q.z + qd.z}));
  turnInto(d, u);
}
CGA_ALWAYS_INLINE void endFreeFlow(const FreeFlow& f, double tau, double* u, BodyState& s) {
  endFreeFlow(f.d, tau, u, u, s);
}

}  // namespace
}  // namespace splitting
}  // namespace dynamics
}  // namespace cga_rigid_sim
