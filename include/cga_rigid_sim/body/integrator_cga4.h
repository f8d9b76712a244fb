// cga4: fourth-order symmetric composition of cga2.
//
// Order 4, symmetric and symplectic: one step is S(γ_1 h) ∘ … ∘ S(γ_s h) with S the Strang step
// of cga2 (integrator_cga2.h) and the coefficients of a symmetric composition whose order
// conditions make the h³ error terms cancel (Yoshida 1990, Phys. Lett. A 150, 262; Suzuki 1990,
// Phys. Lett. A 146, 319; Hairer, Lubich & Wanner, Geometric Numerical Integration, §II.4 and
// §V.3). Adjacent kicks are merged, and with no loads the stages share one drift, one rotation
// about L_B and one rotor (2s + 1 axis rotations per step).
//
// The composition is Yoshida's triple jump, γ = (a, 1 − 2a, a), a = 1/(2 − 2^(1/3)) ≈ 1.35 (the
// middle stage steps back by 1.70 h): 3 stages, 7 axis rotations per free step. It meets the
// accuracy target with orders of magnitude to spare at the fewest rotations per step; why not a
// five-stage composition with a smaller error constant: doc/decisions.md.
//
// Conserves what cga2 conserves: |L| and (without loads) world L, p to round-off, no energy
// drift, the ballistic centre of mass to round-off (Σγ = 1 and each stage is exact for it).
#pragma once

#include "cga_rigid_sim/body/integrator_cga2.h"

namespace cga_rigid_sim {
namespace dynamics {

/// cga4: cga2's Strang step composed as Yoshida's triple jump.
class Cga4Integrator : public StrangCompositionIntegrator {
 public:
  Cga4Integrator();
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
