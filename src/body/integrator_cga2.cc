#include "cga_rigid_sim/body/integrator_cga2.h"

#include <cmath>
#include <cstring>

#include "cga_rigid_sim/math/sin_cos.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace splitting {
namespace {

#define CGA_ALWAYS_INLINE __attribute__((always_inline)) inline
// compose() below, once for x86-64 as such, once for CPUs with FMA and, with GCC 12 or later
// (which dispatches on the x86-64 ISA levels), once for x86-64-v4 (AVX-512). Off elsewhere, under
// clang (which does not clone function templates; the fuzz targets build with it), and with
// -DCGA_RIGID_SIM_NO_FMA_CLONES (to run the tests on the plain clone on a machine with FMA).
#if defined(__x86_64__) && defined(__ELF__) && defined(__GNUC__) && !defined(__clang__) && \
    !defined(CGA_RIGID_SIM_NO_FMA_CLONES)
#if __GNUC__ >= 12
#define CGA_FMA_CLONES __attribute__((target_clones("arch=x86-64-v4", "fma", "default")))
#else
#define CGA_FMA_CLONES __attribute__((target_clones("fma", "default")))
#endif
#else
#define CGA_FMA_CLONES
#endif

constexpr double kOne = 1.0;

// The reference axis r of the split T_rot = |L|²/(2 J_r) + Σ_{i≠r} κ_i L_i²/(2 J_i), κ_i = 1 −
// J_i/J_r (integrator_cga2.h), and the order of the two axis pieces in R_a(h/2) R_b(h) R_a(h/2).
// B's axes are sorted J1 ≤ J2 ≤ J3 (inertia.h). r = 2 (the middle moment) leaves the two smallest
// coefficients, |κ_1|/J_1 = 1/J_1 − 1/J_2 and |κ_3|/J_3 = 1/J_2 − 1/J_3, and makes the step exact
// for every symmetric body (J1 = J2 or J2 = J3: one piece is the identity, the other commutes with
// the rest). The outer axis a = 1 is the more accurate on the thin rod and the tennis racket,
// a = 3 on the projectile; neither wins everywhere (doc/decisions.md, "the outer axis").
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
// x, and the turn then grows |L| by φ²/2 every step, a bias (the thin rod under cga4 at h = 1e-4
// gained 2e-11 of energy in 10⁶ steps); each shear has determinant 1 exactly, so its roundings
// do not add up to a bias. Below 2⁻⁴⁰ the series t = (φ/2)(1 + φ²/12), sin φ = φ(1 − φ²/6),
// sin(φ/2) = (φ/2)(1 − φ²/24) and versin(φ/2) = φ²/8 are exact to the last bit (next terms
// ≤ 1e-25 relative; versin(φ/2) is below 2⁻⁴³ and only enters the rotor against 1).
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

// The turning of a step with no torque: one flow of the Casimir part for h (it commutes with
// every piece) and the axis pieces of all S stages composed into one rotor; the closing R_a of a
// stage and the opening R_a of the next merge.
template <int S>
CGA_ALWAYS_INLINE FreeFlow mergedFreeTurning(double h, const double* gamma, const Cache& cache,
                                             const double* w) {
  FreeFlow f = beginFreeFlow(h, cache, w);
  rotatePiece<kA>(0.5 * gamma[0] * h * cache.kappa[kA], cache.ratio, f);
#pragma GCC unroll 8
  for (int i = 0; i < S; ++i) {
    const double tau = gamma[i] * h;
    rotatePiece<kB>(tau * cache.kappa[kB], cache.ratio, f);
    rotatePiece<kA>(0.5 * (tau + (i + 1 < S ? gamma[i + 1] * h : 0.0)) * cache.kappa[kA],
                    cache.ratio, f);
  }
  return f;
}

// The applied loads' world sums when they are all world-axes loads at the centre of mass
// (gravity, pushes through it, couples: Loads::worldSums), formed once per step for
// composeWorldLoads, which then makes no pass over the loads.
struct StepLoads {
  bool world_sums;
  bool has_force, has_couple;
  Eigen::Vector3d f_W, couple_W;

  CGA_ALWAYS_INLINE StepLoads(const Loads& l, double mass) {
    world_sums = l.hasApplied() && l.worldSums(mass, f_W, couple_W);
    has_force = world_sums && !f_W.isZero(0.0);
    has_couple = world_sums && !couple_W.isZero(0.0);
  }
};

// K(τ): Ω_B += τ (I∧n)⁻¹ T, T the loads' body moment at the current pose (Loads::moment_B: one
// rotation into the body for all world-axes parts): (I∧n)⁻¹ (τ_B, λ f_B) = (τ_B/J, f_B/(m λ)).
// The general kick, for loads at points of the body or in its axes (world-axes loads at the
// centre take composeWorldLoads). Out of line: kept out of the hot paths' register allocation.
__attribute__((noinline)) void kick(const Inertia& inertia, const Loads& loads, double lambda,
                                    double tau, const Cache& cache, BodyState& s) {
  const double m = inertia.mass();
  const cga::Moment T = loads.moment_B(m, s.M_WB, lambda);
  s.omega_B.rot += tau * T.rot.cwiseProduct(cache.inv_J);
  s.omega_B.trans += (tau / (m * lambda * lambda)) * T.trans;
}

// |L|² and L·c after a kick L += τ c (composeWorldLoads): |L|² + 2τ L·c + τ²|c|² and L·c + τ|c|².
CGA_ALWAYS_INLINE void kickSums(double tau, double cc, double& LL, double& Lc) {
  LL += tau * (2.0 * Lc + tau * cc);
  Lc += tau * cc;
}

// The composition when every load is a world-axes sum at the centre (gravity alone, or
// Loads::worldSums): force F_W and couple c_W fixed in the world for the step. The centre's
// motion then does not depend on the turning: in the axes the body had at the step's start,
// its velocity changes by the kicks' constant a = R̃ F_W/(m λ) (one rotation per step), the
// drifts of the stages add up to the exact parabola h u0 + ½ h² a whatever the γ (Σγ = 1, every
// stage's drift sits halfway between its kicks), and the velocity at the end is u0 + h a
// turned into the end's axes by the step's rotor. The turning alone sees the couple: without one
// it is the free path's (one C(h), the pieces merged into one rotor); with one, each stage's flow
// and its kick run in turn, the couple is carried in body axes from stage to stage and from step
// to step (turned by each stage's C(τ) and then piece by piece with L_B, off the chain from one
// kick to the next) and the stages' rotors are composed, so that the motor is updated once per
// step.
template <int S>
CGA_ALWAYS_INLINE void composeWorldLoads(const Eigen::Vector3d* accel_W, double accel_scale,
                                         const Eigen::Vector3d* couple_W, double h,
                                         const double* gamma, Cache& cache, BodyState& state) {
  // The centre's acceleration over λ in the start's axes, times h: accel_scale · R̃ accel_W.
  // Taken from the rotor before this step's renormalisation (which scales it by 1 + O(ε)).
  const Eigen::Quaterniond& r0 = state.M_WB.rotorQuaternion();
  double u[3] = {state.omega_B.trans[0], state.omega_B.trans[1], state.omega_B.trans[2]};
  double u_drift[3] = {u[0], u[1], u[2]};
  if (accel_W) {
    const Eigen::Vector3d a = Loads::toBody(r0, *accel_W) * accel_scale;
    for (int j = 0; j < 3; ++j) {
      u_drift[j] += 0.5 * a[j];
      u[j] += a[j];
    }
  }
  Quat d;
  double* w_state = state.omega_B.rot.data();
  if (!couple_W) {
    FreeFlow f = mergedFreeTurning<S>(h, gamma, cache, w_state);
    for (int j = 0; j < 3; ++j) w_state[j] = f.w[j];
    d = f.d;
  } else {
    // The couple and w as local arrays, their loops written out: kept in state memory or in an
    // Eigen vector whose address is taken, and looped over, every kick and turn stored them and
    // loaded them again on the path from one kick to the next.
    double w[3] = {w_state[0], w_state[1], w_state[2]};
    const Eigen::Vector3d& inv_J = cache.inv_J;
    double tau_kick = 0.5 * (gamma[0] * h);  // each kick is w += (τ/J)·c, one operation after c
    // The couple in body axes, c = R̃ c_W, carried from the last step (Cache::CarriedCouple): the
    // stages turn it with the body (by each C(τ), then piece by piece with L_B), so that at the
    // end of a step it is in the new axes without a turn by the new rotor. Turned from the world
    // afresh, the next step's first kick waits for the rotor, which waits for the whole turning
    // of this step: carried, the path from one step to the next is the turning alone, and the
    // rotor is off it. The carried c and R̃ c_W differ by the roundings of the turns (a few ε a
    // step, and a bias of the order of the rotor's norm error when the same turn repeats), so the
    // couple is turned from the world again every CarriedCouple::kMaxSteps steps, which keeps c
    // close to R̃ c_W (integrator_cga2_test.cc bounds the gap; doc/decisions.md).
    //
    // Each stage's C(τ) turns by |a|, |a|² = (½τ/J_r)² |L|², with |L|² carried as a number
    // instead of summed from the kicked w: the flows keep |L_B| and L_B·c (C turns c about L_B;
    // a piece turns L_B and c by the same rotation) and a kick L += τ c makes them |L|² + 2τ L·c
    // + τ²|c|² and L·c + τ|c|², so the angle is ready before the kick's w, and the couple's
    // turn by C, the longest path from one kick to the next, is three operations shorter. They
    // are carried across steps with c, and formed from w when c is turned afresh. The
    // carried |L|² agrees with Σ(J w)² to a few ε; the rotor norm error of that order is what
    // renormalise() takes off.
    Cache::CarriedCouple& carried = cache.couple;
    const double* c_W = couple_W->data();
    double c[3], LL, Lc, cc;
    if (carried.age < Cache::CarriedCouple::kMaxSteps &&
        std::memcmp(c_W, carried.c_W, sizeof(carried.c_W)) == 0 &&
        std::memcmp(r0.coeffs().data(), carried.rotor, sizeof(carried.rotor)) == 0 &&
        std::memcmp(w_state, carried.w, sizeof(carried.w)) == 0) {
      for (int j = 0; j < 3; ++j) c[j] = carried.c_B[j];
      LL = carried.LL;
      Lc = carried.Lc;
      cc = carried.cc;
      ++carried.age;
    } else {
      const Quat rq = toQuat(r0);
      for (int j = 0; j < 3; ++j) c[j] = c_W[j];
      turnInto({rq.w - 1.0, rq.x, rq.y, rq.z}, c);
      const Eigen::Vector3d& J = cache.J;
      LL = 0.0, Lc = 0.0, cc = 0.0;
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) {
        const double L = J[j] * w[j];
        LL += L * L;
        Lc += L * c[j];
        cc += c[j] * c[j];
      }
      carried.age = 0;
    }
#pragma GCC unroll 8
    for (int i = 0; i < S; ++i) {
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) w[j] += (tau_kick * inv_J[j]) * c[j];
      kickSums(tau_kick, cc, LL, Lc);
      const double tau = gamma[i] * h;
      const double kr = 0.5 * tau * inv_J[kRef], z = (kr * kr) * LL;
      FreeFlow f = beginFreeFlow(tau, cache, w, &z);
      turnInto(f.d, c);
      stagePieces(tau, cache, f, c);
#pragma GCC unroll 3
      for (int j = 0; j < 3; ++j) w[j] = f.w[j];
      if (i == 0) {
        d = f.d;
      } else {
        const Quat dd = mul(d, f.d);
        d = {d.w + f.d.w + dd.w, d.x + f.d.x + dd.x, d.y + f.d.y + dd.y, d.z + f.d.z + dd.z};
      }
      // The last kick as 0.5 * τ, the first one's expression when S = 1, so that GCC forms τ/J
      // once.
      tau_kick = i + 1 < S ? 0.5 * (tau + gamma[i + 1] * h) : 0.5 * tau;
    }
#pragma GCC unroll 3
    for (int j = 0; j < 3; ++j) {
      w_state[j] = w[j] + (tau_kick * inv_J[j]) * c[j];
      carried.w[j] = w_state[j];
      carried.c_B[j] = c[j];
      carried.c_W[j] = c_W[j];
    }
    kickSums(tau_kick, cc, LL, Lc);
    carried.LL = LL;
    carried.Lc = Lc;
    carried.cc = cc;
  }
  renormalise(state);
  endFreeFlow(d, h, u_drift, u, state);
  if (couple_W) {
    std::memcpy(cache.couple.rotor, state.M_WB.rotorQuaternion().coeffs().data(),
                sizeof(cache.couple.rotor));
  }
  for (int j = 0; j < 3; ++j) state.omega_B.trans[j] = u[j];
}

// The composition for a fixed number of stages S (unrolled).
//
// Compiled for x86-64 as such, for CPUs with fused multiply-add and for x86-64-v4 (GCC's
// target_clones: the loader picks the clone once, by CPUID, through an ifunc). A step is a chain
// of dependent products and sums, and FMA shortens it. The x86-64-v4 clone uses no 512-bit
// vectors (GCC prefers 256 bits, and no clock penalty comes with it); what it gains is AVX-512's
// 32 vector registers instead of 16: the FMA clone keeps w, the couple and the series' terms in
// stack memory for want of registers, and the step is bound by its work as much as by its chain
// (the measurements: doc/decisions.md, "compiled for FMA"). Everything it calls is inlined
// (CGA_ALWAYS_INLINE), since GCC does not inline ordinary functions into a clone whose target
// differs from theirs. The plain clone rounds differently from the others (a fused a·b + c is
// rounded once), so results are reproducible on one machine, and agree across machines only to
// rounding; every accuracy statement above holds for each clone, and the tests pass on each (the
// plain one with -DCGA_RIGID_SIM_NO_FMA_CLONES).
template <int S>
CGA_FMA_CLONES void compose(const Inertia& inertia, const Loads& loads, double lambda, double h,
                            const double* gamma, Cache& cache, BodyState& state) {
  refreshCache(inertia, cache);
  if (loads.empty()) {
    // No kicks: one drift by h v_B and the merged turning.
    FreeFlow f = mergedFreeTurning<S>(h, gamma, cache, state.omega_B.rot.data());
    double u[3] = {state.omega_B.trans[0], state.omega_B.trans[1], state.omega_B.trans[2]};
    renormalise(state);
    endFreeFlow(f, h, u, state);
    for (int j = 0; j < 3; ++j) {
      state.omega_B.rot[j] = f.w[j];
      state.omega_B.trans[j] = u[j];
    }
    return;
  }
  if (!loads.hasApplied()) {
    composeWorldLoads<S>(&loads.gravity(), h / lambda, nullptr, h, gamma, cache, state);
    return;
  }
  const StepLoads step_loads(loads, inertia.mass());
  if (step_loads.world_sums) {
    composeWorldLoads<S>(
        step_loads.has_force ? &step_loads.f_W : nullptr, h / (inertia.mass() * lambda),
        step_loads.has_couple ? &step_loads.couple_W : nullptr, h, gamma, cache, state);
    return;
  }
  kick(inertia, loads, lambda, 0.5 * gamma[0] * h, cache, state);
  renormalise(state);
#pragma GCC unroll 8
  for (int i = 0; i < S; ++i) {
    const double tau = gamma[i] * h;
    FreeFlow f = beginFreeFlow(tau, cache, state.omega_B.rot.data());
    stagePieces(tau, cache, f);
    double u[3] = {state.omega_B.trans[0], state.omega_B.trans[1], state.omega_B.trans[2]};
    endFreeFlow(f, tau, u, state);
    for (int j = 0; j < 3; ++j) {
      state.omega_B.rot[j] = f.w[j];
      state.omega_B.trans[j] = u[j];
    }
    kick(inertia, loads, lambda, 0.5 * (tau + (i + 1 < S ? gamma[i + 1] * h : 0.0)), cache, state);
  }
}

}  // namespace

void composeStrang(const Inertia& inertia, const Loads& loads, double lambda, double h,
                   const double* gamma, int stages, Cache& cache, BodyState& state) {
  switch (stages) {
    case 1:
      return compose<1>(inertia, loads, lambda, h, gamma, cache, state);
    case 3:
      return compose<3>(inertia, loads, lambda, h, gamma, cache, state);
    default:
      // Other stage counts: stage by stage, each a full Strang step (the same method, without the
      // merges of kicks, drifts and rotors).
      for (int i = 0; i < stages; ++i)
        compose<1>(inertia, loads, lambda, gamma[i] * h, &kOne, cache, state);
  }
}

}  // namespace splitting

#undef CGA_ALWAYS_INLINE
#undef CGA_FMA_CLONES

void StrangCompositionIntegrator::step(const Inertia& inertia, const Loads& loads, double lambda,
                                       double h, BodyState& state) {
  splitting::composeStrang(inertia, loads, lambda, h, gamma_, stages_, cache_, state);
}

namespace {
constexpr double kStrangGamma[1] = {1.0};
}  // namespace

Cga2Integrator::Cga2Integrator() : StrangCompositionIntegrator("cga2", kStrangGamma, 1) {}

}  // namespace dynamics
}  // namespace cga_rigid_sim
