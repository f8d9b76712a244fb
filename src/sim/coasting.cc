#include "sim/coasting.h"

#include "sim/body_ranges.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

void syncRange(void* context, std::size_t begin, std::size_t end) {
  const Model& model = *static_cast<BodyRange*>(context)->model;
  Data& data = *static_cast<BodyRange*>(context)->data;
  for (std::size_t i = begin; i < end; ++i) syncBody(model, data, static_cast<int>(i));
}

}  // namespace

bool mayCoast(const Model& model, const MovingBodyData& b, int i) {
  // Contacts read the pose of every body with a shape at every step (contact_detection.cc);
  // trees and curved space have steps of their own.
  return !model.curved_space && model.tree_of_moving[i] < 0 &&
         b.contact_step == MovingBodyData::ContactStep::kNone && b.integrator->coasts(b.loads) &&
         model.bodyOf(i).shapes.empty();
}

void startCoast(Data& data, int i) {
  MovingBodyData& b = data.bodies[i];
  b.integrator->reset();  // the coast's cache is built from `from`
  b.coast.from = b.state;
  b.coast.start = data.step_count;  // the state is that of the step's start
  b.coast.synced = data.step_count;
  data.coasting[i] = 1;
}

void syncBody(const Model& model, Data& data, int i) {
  MovingBodyData& b = data.bodies[i];
  const std::uint64_t now = data.step_count;
  if (!data.coasting[i] || b.coast.synced == now) return;
  b.integrator->coast(model.moving[i].inertia, b.loads, model.lambda, model.config.dt,
                      static_cast<double>(now - b.coast.start), b.coast.from, b.state);
  b.coast.synced = now;
}

void syncBodies(const Model& model, Data& data, WorkerPool* pool) {
  std::size_t stale = 0;
  for (std::size_t i = 0; i < data.bodies.size(); ++i)
    stale += data.coasting[i] && data.bodies[i].coast.synced != data.step_count;
  if (stale > 0) forBodyRanges(model, data, pool, stale, syncRange);
}

void endCoast(const Model& model, Data& data, int i) {
  if (!data.coasting[i]) return;
  syncBody(model, data, i);
  data.coasting[i] = 0;
  data.bodies[i].integrator->reset();
}

}  // namespace sim
}  // namespace cga_rigid_sim
