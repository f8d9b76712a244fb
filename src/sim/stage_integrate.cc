// Stage 3 of the step: every moving body is advanced over [t_k, t_k + dt] by its integrator,
// then the clock advances.
#include "cga_rigid_sim/dynamics/at_rest.h"
#include "cga_rigid_sim/sim/stages.h"

namespace cga_rigid_sim {
namespace sim {
void integrateBodies(const Model& model, Data& data) {
  const double h = model.config.dt, lambda = model.lambda;
  const std::size_t n = data.bodies.size();
  for (std::size_t i = 0; i < n; ++i) {
    MovingBodyData& b = data.bodies[i];
    // With no load and Ω_B = 0 a body is at rest under every integrator (the exact solution
    // is M(t) = M): it is skipped, its state left exactly as it is.
    const bool rest = dynamics::isAtRest(b.loads, b.state.omega_B);
    b.last_path = rest ? StepPath::kAtRest : StepPath::kStepped;
    if (rest) continue;
    b.integrator->step(model.moving[i].inertia, b.loads, lambda, h, b.state);
  }
  ++data.step_count;
}

}  // namespace sim
}  // namespace cga_rigid_sim
