// cga2 and cga4 (integrator_cga2.h): the Strang step and its symmetric compositions, composed from
// the exact flows of the split's parts (splitting_flows.h) and the kicks of the loads.
#include "cga_rigid_sim/body/integrator_cga2.h"

#include <cmath>
#include <cstring>

#include "body/splitting_flows.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace splitting {
namespace {

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
    // The couple and w as local arrays, their loops written out, so that no kick or turn stores
    // them and loads them again on the path from one kick to the next (doc/decisions.md, "local
    // copies under a world couple").
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
