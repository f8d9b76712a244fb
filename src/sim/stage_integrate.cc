// Stage 3 of the step: every moving body is advanced over [t_k, t_k + dt] by its integrator,
// then the clock advances.
#include "cga_rigid_sim/body/at_rest.h"
#include "cga_rigid_sim/sim/stages.h"
#include "contact/contact_drift.h"
#include "sim/body_ranges.h"
#include "sim/coasting.h"
#include "sim/curved_bodies.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// Bodies [begin, end) over one step; each reads its own data and the constant Model only.
void integrateRange(void* context, std::size_t begin, std::size_t end) {
  const Model& model = *static_cast<BodyRange*>(context)->model;
  Data& data = *static_cast<BodyRange*>(context)->data;
  const double h = model.config.dt, lambda = model.lambda;
  for (std::size_t i = begin; i < end; ++i) {
    // Coasting (coasting.h): nothing to do, and only a byte read. Whatever could end a coast —
    // an input, an edit, a change of its loads — ends it where it happens.
    if (data.coasting[i]) continue;
    MovingBodyData& b = data.bodies[i];
    if (model.tree_of_moving[i] >= 0) continue;  // moved by its tree (stage_trees.cc)
    if (model.curved_space) {                    // curved space: 1 up (curved_bodies.h)
      stepCurvedBody(model, static_cast<int>(i), b);
      continue;
    }
    if (b.contact_step != MovingBodyData::ContactStep::kNone) {  // kicked by its contacts
      finishBodyContactStep(model, static_cast<int>(i), b);
      continue;
    }
    // With no load and Ω_B = 0 a body is at rest under every integrator (the exact solution
    // is M(t) = M): it is skipped, its state left exactly as it is.
    const bool rest = dynamics::isAtRest(b.loads, b.state.omega_B);
    if (!rest && mayCoast(model, b, static_cast<int>(i))) {
      startCoast(data, static_cast<int>(i));
      b.last_path = StepPath::kStepped;
      continue;
    }
    b.last_path = rest ? StepPath::kAtRest : StepPath::kStepped;
    if (rest) continue;
    b.integrator->step(model.moving[i].inertia, b.loads, lambda, h, b.state);
  }
}

}  // namespace

void integrateBodies(const Model& model, Data& data, WorkerPool* pool) {
  forBodyRanges(model, data, pool, data.bodies.size(), integrateRange);
  ++data.step_count;
}

}  // namespace sim
}  // namespace cga_rigid_sim
