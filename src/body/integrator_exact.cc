#include "cga_rigid_sim/body/integrator_exact.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace {

// K(τ): Ω_B += τ (I∧n)⁻¹ T, T the applied and gravity moments at the current pose.
void kick(const Inertia& inertia, const Loads& loads, double lambda, double tau, BodyState& state) {
  const cga::Moment T = loads.moment_B(inertia.mass(), state.M_WB, lambda);
  state.omega_B += inertia.solve(T, lambda) * tau;
}

}  // namespace

void ExactIntegrator::step(const Inertia& inertia, const Loads& loads, double lambda, double h,
                           BodyState& state) {
  if (!loads.hasApplied()) {
    // Free, or under gravity alone (no torque): the closed form, parabola included.
    exactFreeFlow(inertia, lambda, h, state, cache_, loads.gravity());
    return;
  }
  // Strang splitting: K(h/2) F(h) K(h/2).
  kick(inertia, loads, lambda, 0.5 * h, state);
  exactFreeFlow(inertia, lambda, h, state, cache_);
  kick(inertia, loads, lambda, 0.5 * h, state);
}

void ExactIntegrator::coast(const Inertia& inertia, const Loads& loads, double lambda, double h,
                            double steps, const BodyState& from, BodyState& out) {
  freeFlowAt(inertia, lambda, h, steps, from, cache_, loads.gravity(), out);
}

}  // namespace dynamics
}  // namespace cga_rigid_sim
