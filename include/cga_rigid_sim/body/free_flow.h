// The exact torque-free motion of one rigid body (Euler–Poinsot), written as motor updates.
//
// The centre of mass moves on a straight line, x_W(t) = x_W(0) + v_W t, or on the parabola
// x_W(0) + v_W(0) t + ½ g t² under a uniform acceleration g (gravity: no torque, so the attitude
// is still the free one). The attitude follows
// the closed-form solution of the free rigid body, by inertia class:
//   spherical:  w is constant in the body; R(t) = R(0) Rot_B(ŵ, |w| t).
//   symmetric:  the symmetric-top rotor solution (doc/conventions.md (E21); J1 = J2, distinct
//               axis e3),
//               R(t) = exp(−½ (L/J1) t) R(0) exp(−½ w3 (1 − J3/J1) e12 t), i.e. in body form
//               R(t) = R(0) Rot_B(L̂_B(0), |L| t/J1) Rot_B(e3, β t), β = w3 (1 − J3/J1), and
//               w_B(t) = Rot(e3, −β t) w_B(0).
//   asymmetric: L_B(t) from Jacobi's elliptic functions, and the angle ψ(t) of the body about
//               the fixed world L from the incomplete elliptic integral of the third kind:
//               R(t) = Q Rot_B(u, ψ(t)) P(t)⁻¹, with P(t) the shortest rotation taking a fixed
//               principal axis u to L̂_B(t) and Q the constant rotation taking u to L̂_W.
//               (Derived in doc/conventions.md, (E26)–(E32). The same
//               solution as Celledoni, Fassò, Säfström & Zanna, "The exact computation of the
//               free rigid body motion and its use in splitting methods", SIAM J. Sci. Comput.
//               30 (2008) 2084–2112, and Landau & Lifshitz, Mechanics, §37.)
//
// The phases are evaluated from the elapsed time, not accumulated: the cache keeps the angles
// of an anchor (the state it was built from, or the last change of step size) and the number k
// of steps of h taken since, and each call sets ψ = ψ_a + rate·t (uniform, symmetric),
// ψ3 = ψ3_a + β t (symmetric), τ = τ_a + ω_p t with ψ = ψ_a + rate·t + m Δψ_half + g(τ_r) −
// g(τ_a) (elliptic; m whole half periods, τ_r reduced to [−K, K]), t = k h, each reduced once
// to [−π, π]. So the round-off of a phase is a few ulps of the phase itself — the conditioning
// floor, set by the rounding of the rates — however many steps it took. (Elliptic: the third-kind
// integral inside g is evaluated so only on the first step of every run of 32; the others add its
// change by the integral's addition theorem, and sn, cn, dn advance by theirs when that is well
// conditioned — doc/conventions.md (E32) — so a run's round-off adds up over ≤ 31 steps only.) The
// centre of mass likewise: x_W = x_a + v_a t + ½ g t² from its own anchor (renewed when a kick
// changes v). The rotor is rebuilt in closed form from those angles, never by compounding step
// rotations, so world L, |L| and T are kept to round-off at every step, and N steps of h equal one
// step of N h to round-off (doc/conventions.md#how-the-code-evaluates-the-closed-forms).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cstdint>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/inertia.h"

namespace cga_rigid_sim {
namespace dynamics {

/// Per-body data of the free flow that depends only on (J, L_B, T), plus the running phase.
/// Built on the first call, then reused as long as the incoming state is exactly the state the
/// previous call left (its rotor and angular velocity, bit for bit) and the moments are the same;
/// anything else (an impulse, a torque kick, a state override) rebuilds it. Gravity and forces
/// through the centre of mass only change v_B, which the cache does not depend on, so they keep
/// it valid. A default-constructed cache is empty.
///
/// Every body of the `exact` and `auto` integrators holds one, so it keeps only what a step reads
/// (832 bytes): members in order of alignment (no padding), the centre of mass as its anchor and
/// step count (x_W and v_W are re-evaluated from them when needed), the AGM table as its b_j
/// alone (a_j and 1/a_j are re-formed in the forward pass of each evaluation, elliptic.h), and
/// the small fields in bytes at the end (a static_assert in free_flow.cc keeps it so).
struct FreeFlowCache {
  /// Which closed form the cache holds.
  enum class Path : std::uint8_t {
    kNone,        ///< empty: rebuild on the next call
    kStill,       ///< w = 0: the attitude does not change
    kUniform,     ///< w constant in the body (spherical body, or spin about a principal axis)
    kSymmetric,   ///< J1 = J2: the symmetric-top rotor solution (doc/conventions.md (E21))
    kElliptic,    ///< J1 < J2 < J3 off the separatrix: Jacobi elliptic functions
    kSeparatrix,  ///< J1 < J2 < J3 on the separatrix (k = 1): hyperbolic functions
  };

  // Validity key: the moments and the state this cache ends at (the rotor, w_B, v_B/λ, the
  // motor's dual part and λ), to tell whether the next call continues from it (then x and v come
  // from the anchor below, not from the motor: no random walk).
  Eigen::Vector4d key_r = Eigen::Vector4d::Zero();  ///< rotor quaternion coefficients (x, y, z, w)
  Eigen::Vector4d key_q = Eigen::Vector4d::Zero();  ///< motor dual part coefficients
  Eigen::Vector3d key_J = Eigen::Vector3d::Zero();
  Eigen::Vector3d key_w = Eigen::Vector3d::Zero();
  Eigen::Vector3d key_trans = Eigen::Vector3d::Zero();
  double key_lambda = 0;
  // The centre of mass: its anchor (x_a, v_a, world), the step size and acceleration it was
  // taken with and the steps since: x_W = x_a + v_a t + ½ g t², v_W = v_a + g t, t = steps·h.
  Eigen::Vector3d x_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d v_a = Eigen::Vector3d::Zero();
  Eigen::Vector3d com_g = Eigen::Vector3d::Zero();
  double com_h = 0;
  double com_steps = 0;

  // Every path: R(t) = Q Rot(axis, psi) [...], psi = angle turned since the cache was built
  // (kept reduced to [−π, π]).
  Eigen::Quaterniond Q = Eigen::Quaterniond::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();  ///< uniform: ŵ; symmetric: L̂_B(0)
  double rate = 0;  ///< dψ/dt (uniform, symmetric), its linear part (elliptic, separatrix)
  double psi = 0;

  // The anchor the phases are evaluated from: their values when the cache was built or the
  // step size last changed, the step size, and the number of steps taken since (a double:
  // exact up to 2^53 steps).
  double anchor_h = 0;
  double anchor_steps = 0;
  double psi_a = 0, psi3_a = 0, tau_a = 0, g_a = 0, rho_a = 1;

  // Symmetric: the body spin about e3, angle psi3 at rate beta; w_B(0).
  Eigen::Vector3d w0 = Eigen::Vector3d::Zero();
  double beta = 0;
  double psi3 = 0;

  // Elliptic and separatrix: L_a = ρ B_a cn τ, L_b = ρ σ B_b sn τ, L_c = σ B_c dn τ over the
  // principal axes (a, b, c), b = 2, c the axis the polhode circles; τ = ω_p t + τ0 is the
  // elliptic phase, kept reduced to [−K, K] (ρ = ±1 tracks the half periods dropped). The angle
  // about L is ψ(t) = rate t + (half periods) dpsi_half + g(τ) (see free_flow_phase.h).
  Eigen::Vector3d inv_J = Eigen::Vector3d::Zero();  ///< 1/J_i: w = L_B/J each step
  double sigma = 1, rho = 1;
  double Ba = 0, Bb = 0, Bc = 0;
  double ell = 0;      ///< |L|
  double inv_ell = 0;  ///< 1/|L|
  double G = 0;        ///< B_b² − B_a² = k² B_c²
  double kp2 = 0;      ///< complementary parameter k'² = 1 − k²
  double K = 0;        ///< complete integral of the first kind K(k) (quarter period in τ)
  double omega_p = 0;  ///< dτ/dt
  double nchar = 0;    ///< the characteristic used (n or N, |nchar| ≤ k ≤ 1, ≤ 0)
  double coef_pi = 0;  ///< g(τ) = coef_pi (nchar/3) sn³ R_J(…) + coef_atan atan2(…)
  double coef_atan = 0;
  double dpsi_half = 0;  ///< ψ gained per half period 2K of τ, beyond rate·t
  double tau = 0;        ///< reduced phase of the last evaluation from the anchor
  double g_tau = 0;      ///< g at tau
  // Steps between evaluations of Π from the anchor (runs of kRunLength steps) take Π's part of ψ
  // from its addition theorem (doc/conventions.md (E32)): sn δ and the gain P(δ) of Π(ν; am τ) − τ
  // over one step δ = ω_p h (for the step size `step_h`; step_ready false after a rebuild), the
  // theorem's constants A and B; the signed sn of the last step, the sum of the theorem's atan
  // terms, the angle term (Φ, or Θ continued) and ψ where the run started, and its steps.
  double step_h = 0;
  double step_sn = 0, step_cn = 1, step_dn = 1, step_P = 0;
  double add_A = 0, add_B = 0;
  double run_sn = 0, run_cn = 1, run_dn = 1, run_atan = 0, run_angle = 0, run_angle0 = 0,
         run_psi0 = 0;
  // The AGM sequence of (1, k') for Bulirsch's sn/cn/dn: b_j level by level (a_0 = 1 and
  // a_{j+1} = (a_j + b_j)/2 follow from them), and its limit. 16 levels cover every k'² down to
  // the smallest double (12 are needed there: the gap's logarithm halves per level until it is
  // O(1), then the gap squares).
  static constexpr int kMaxAgm = 16;
  double agm_b[kMaxAgm] = {};
  double agm_limit = 1;

  int run_steps = 0;
  std::int8_t agm_levels = 0;
  std::int8_t ia = 0, ib = 1, ic = 2;
  Path path = Path::kNone;
  /// Built by freeFlowAt (anchored at its `from`, the keys are that state) rather than by
  /// exactFreeFlow (keys are the state the last step left); each rebuilds the other's cache.
  bool coast = false;
  bool dual = false;             ///< ψ written with the characteristic N = k²/n instead of n
  bool dpsi_half_ready = false;  ///< dpsi_half is computed on first use
  bool step_ready = false;
  bool step_small = false;  ///< δ small: sn, cn, dn advance by their addition theorems too
};

/// Exact torque-free motion over h: the centre of mass moves on a straight line, or on the
/// parabola of a uniform acceleration g_W (gravity), the attitude follows the exact
/// Euler–Poinsot solution. Exact to round-off at any h (also h < 0), and N steps of h equal one
/// step of N h to round-off. `cache` belongs to this body; pass the same object on every call
/// (it is rebuilt whenever the incoming state is not the one the previous call left).
/// @param inertia principal moments (B is the principal frame; symmetric bodies have J1 = J2)
/// @param lambda  the CGA length scale λ (the result does not depend on it beyond round-off)
/// @param h       the time step, s
/// @param state   M_WB and Ω_B = (w, v/λ), advanced in place
/// @param g_W     uniform acceleration of the centre of mass, world axes, m/s² (no torque)
void exactFreeFlow(const Inertia& inertia, double lambda, double h, BodyState& state,
                   FreeFlowCache& cache, const Eigen::Vector3d& g_W = Eigen::Vector3d::Zero());

/// The torque-free motion (parabola under g_W included) `steps` steps of h after the state
/// `from`, in closed form from the elapsed time t = steps·h alone: a coasting body's state is
/// evaluated only when it is read (the World's coasting bodies, doc/conventions.md). The result
/// is a function of (from, steps) only — it does not depend on which other steps were evaluated
/// before — and equals `steps` calls of exactFreeFlow(h) from `from` to round-off (the elliptic
/// phase and Π are evaluated from the anchor every time: the accuracy of a single step of t).
/// `cache` belongs to this body; it is built from `from` on the first call and rebuilt whenever
/// `from`, h, g_W or λ differ from the call that built it.
void freeFlowAt(const Inertia& inertia, double lambda, double h, double steps,
                const BodyState& from, FreeFlowCache& cache, const Eigen::Vector3d& g_W,
                BodyState& out);

}  // namespace dynamics
}  // namespace cga_rigid_sim
