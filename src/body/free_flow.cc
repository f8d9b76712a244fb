// The exact torque-free flow (free_flow.h): the attitude from the phases of the cache, evaluated
// from the anchor and the elapsed time, and the centre of mass on its parabola. The cache's
// constants: free_flow_constants.cc; the elliptic phase from step to step: free_flow_phase.h.
#include "cga_rigid_sim/body/free_flow.h"

#include <cmath>

#include "body/free_flow_constants.h"
#include "body/free_flow_phase.h"
#include "cga_rigid_sim/body/loads.h"
#include "cga_rigid_sim/math/sin_cos.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

using free_flow::build;
using math::sinCosReduced;

// The cache is per body (free_flow.h): keep it from growing back unnoticed. 832 bytes on LP64
// (8-byte double, 16-byte aligned Eigen 4-vectors).
static_assert(sizeof(void*) != 8 || sizeof(FreeFlowCache) <= 832,
              "FreeFlowCache grew: it is held per body by the exact and auto integrators");

// The rotation by ψ about the unit axis u, (cos ψ/2, sin ψ/2 u), for ψ ∈ [−π, π] (reduced: the
// half angle is within sinCosReduced's range).
inline Eigen::Quaterniond axisAngle(const Eigen::Vector3d& u, double psi) {
  double s, c;
  sinCosReduced(0.5 * psi, s, c);
  return Eigen::Quaterniond(c, s * u.x(), s * u.y(), s * u.z());
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

// Keys the cache to the state `s` (rotor r, body w) for the moments J and λ: the state the
// last step left (exactFreeFlow) or the coast's anchor (freeFlowAt). Inlined into both: it is on
// the step's path.
__attribute__((always_inline)) inline void setKeys(FreeFlowCache& c, const Eigen::Vector3d& J,
                                                   const Eigen::Quaterniond& r,
                                                   const Eigen::Vector3d& w, const BodyState& s,
                                                   double lambda) {
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
