// rk4: the classical fourth-order Runge–Kutta method on (quaternion, w) and (x, v) — a baseline,
// for comparison only.
//
// Order 4, neither symplectic nor symmetric: the energy and |L| drift (slowly, O(h⁴) per unit
// time), and the quaternion leaves the unit sphere within a step (normalised at the end of each
// step; loads are evaluated at the normalised stage pose). The ODE, with loads at the stage pose:
//   q̇ = ½ q ⊗ (0, w),  ẇ = J⁻¹(τ_B + Jw × w),  ẋ = v_W,  v̇_W = f_W/m.
// Exact for the centre of mass under constant forces (a cubic is integrated exactly).
#pragma once

#include "cga_rigid_sim/body/integrator.h"

namespace cga_rigid_sim {
namespace dynamics {

class Rk4Integrator : public Integrator {
 public:
  const char* name() const override { return "rk4"; }
  void step(const Inertia& inertia, const Loads& loads, double lambda, double h,
            BodyState& state) override;
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
