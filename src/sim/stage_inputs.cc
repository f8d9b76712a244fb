// Stage 1 of the step: the inputs due at step k take effect, in (step, arrival) order.
#include "cga_rigid_sim/dynamics/impulse.h"
#include "cga_rigid_sim/sim/stages.h"
#include "wrench_schedule.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// ΔΩ_B = (I∧n)⁻¹ T_imp (doc/conventions.md (E17)); the pose does not jump. A
// world-frame impulse acts at the world point at this step's pose; a link-frame one is in B.
void applyImpulseNow(const Model& model, Data& data, const QueuedInput& in) {
  MovingBodyData& b = data.bodies[in.body];
  const double lambda = model.lambda;
  const cga::Moment T_imp_B =
      in.axes == dynamics::Axes::kWorld
          ? dynamics::impulseMoment_B(b.state, in.F, in.point, in.couple, lambda)
          : cga::Moment::ofForceAt(in.F.f, in.point, lambda) + cga::Moment::couple(in.couple);
  dynamics::applyImpulse(model.moving[in.body].inertia, T_imp_B, lambda, b.state);
  b.integrator->reset();  // its caches describe the motion before the jump
}

}  // namespace

void applyDueInputs(const Model& model, Data& data) {
  const std::uint64_t k = data.step_count;
  if (!data.queue.hasDue(k)) return;  // most steps: nothing to do, no frame to set up
  while (const QueuedInput* in = data.queue.popDue(k)) {
    if (in->kind == QueuedInput::Kind::kImpulse) {
      applyImpulseNow(model, data, *in);
    } else {
      startWrench(model, data, *in, k);
    }
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
