// euler: explicit Euler on (quaternion, w) and (x, v) — a baseline, for comparison only.
//
// Order 1, not symplectic, conserves nothing: what most game engines do. From the state at t:
//   q ← normalise(q + h ½ q ⊗ (0, w)),   w ← w + h J⁻¹(τ_B + Jw × w),
//   v_W ← v_W + h f_W/m,                 x ← x + h v_W,
// every right-hand side evaluated at the start of the step (loads at the old pose). The energy
// of a torque-free body grows every step (by h² |J⁻¹(Jw × w)|²-type terms), the centre of mass
// lags a parabola by h g t/2, and a fast spin blows up. The state stays a BodyState; it is
// converted to (q, x, v_W) and back once per step.
#pragma once

#include "cga_rigid_sim/body/integrator.h"

namespace cga_rigid_sim {
namespace dynamics {

class EulerIntegrator : public Integrator {
 public:
  const char* name() const override { return "euler"; }
  void step(const Inertia& inertia, const Loads& loads, double lambda, double h,
            BodyState& state) override;
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
