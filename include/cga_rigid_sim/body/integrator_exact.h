// exact: the exact torque-free flow, with loads added by Strang splitting.
//
// Without loads a step is exactFreeFlow(h) (free_flow.h): the Euler–Poinsot solution in closed
// form (Jacobi elliptic functions and the elliptic integral of the third kind for asymmetric
// bodies, the symmetric-top rotor solution (doc/conventions.md (E21)) for symmetric ones) and a
// straight line for the centre of mass. It is exact at any step size: N steps of h equal one
// step of N h to round-off, the phases being evaluated from the elapsed time
// (doc/conventions.md#how-the-code-evaluates-the-closed-forms).
//
// With loads, one step is the symmetric (Strang) splitting
//   S(h) = K(h/2) F(h) K(h/2),
// F the exact free flow and K(τ) the kick Ω_B += τ (I∧n)⁻¹(T_applied + T_gravity), the moments
// evaluated at the pose of the kick (doc/conventions.md (E15), (E23)). This is the
// splitting of Celledoni, Fassò, Säfström & Zanna ("The exact computation of the free rigid
// body motion and its use in splitting methods", SIAM J. Sci. Comput. 30 (2008) 2084–2112),
// i.e. of Touma & Wisdom (1994) and Dullweber, Leimkuhler & McLachlan (1997) with the free
// rotation solved exactly instead of split into axis rotations.
//
// Under gravity alone (no applied load) there is no torque and no splitting: the free flow takes
// the uniform acceleration and puts the centre of mass on its parabola in closed form, from the
// elapsed time (free_flow.h), so 10⁷ steps stay on it to round-off. Order: exact (to round-off)
// without loads and under gravity; exact also for a force through the centre of mass fixed in
// the world (the kicks then only change v, by a constant acceleration, for which kick–drift–kick
// is exact: the centre of mass follows the parabola whatever the spin, to a round-off that
// grows with the steps);
// 2 with torques (symmetric, time-reversible; symplectic/Lie–Poisson for conservative torques).
// Conserved: without loads, world L, T and |L| to round-off, and M M̃ = 1 (every motor is built
// in closed form, never compounded); with loads, M M̃ = 1, and the energy of a conservative
// system has no drift (it stays within O(h²) of its initial value).
// Cost: the free-flow cache (elliptic parameters) survives kicks that leave w unchanged (gravity,
// forces through the centre of mass); a torque kick changes w and rebuilds it each step.
#pragma once

#include "cga_rigid_sim/body/free_flow.h"
#include "cga_rigid_sim/body/integrator.h"

namespace cga_rigid_sim {
namespace dynamics {

class ExactIntegrator : public Integrator {
 public:
  const char* name() const override { return "exact"; }
  void step(const Inertia& inertia, const Loads& loads, double lambda, double h,
            BodyState& state) override;
  /// Every call of the flow builds a path (path ≠ kNone), so a cache still at kNone and not
  /// coasting is the fresh one of the last reset: it is not built again (a body in contact
  /// resets twice a step; the cache is ~1.5 kB).
  void reset() override {
    if (cache_.path != FreeFlowCache::Path::kNone || cache_.coast) cache_ = FreeFlowCache();
  }
  /// Torque-free (gravity allowed): the closed form of freeFlowAt.
  bool coasts(const Loads& loads) const override { return !loads.hasApplied(); }
  void coast(const Inertia& inertia, const Loads& loads, double lambda, double h, double steps,
             const BodyState& from, BodyState& out) override;

 private:
  FreeFlowCache cache_;
};

}  // namespace dynamics
}  // namespace cga_rigid_sim
