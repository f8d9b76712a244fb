#include "coasting.h"

#include "cga_rigid_sim/sim/stages.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

struct Bodies {
  const Model* model;
  Data* data;
};

void syncRange(void* context, std::size_t begin, std::size_t end) {
  const Model& model = *static_cast<Bodies*>(context)->model;
  Data& data = *static_cast<Bodies*>(context)->data;
  for (std::size_t i = begin; i < end; ++i)
    syncBody(model, data.bodies[i], static_cast<int>(i), data.step_count);
}

}  // namespace

bool mayCoast(const Model& model, const MovingBodyData& b, int i) {
  // Contacts read the pose of every body with a shape at every step (contact_detection.cc);
  // trees and curved space have steps of their own.
  return !model.curved_space && model.tree_of_moving[i] < 0 &&
         b.contact_step == MovingBodyData::ContactStep::kNone && b.integrator->coasts(b.loads) &&
         model.bodyOf(i).shapes.empty();
}

void syncBody(const Model& model, MovingBodyData& b, int i, std::uint64_t now) {
  if (!b.coast.active || b.coast.synced == now) return;
  b.integrator->coast(model.moving[i].inertia, b.loads, model.lambda, model.config.dt,
                      static_cast<double>(now - b.coast.start), b.coast.from, b.state);
  b.coast.synced = now;
}

void syncBodies(const Model& model, Data& data, WorkerPool* pool) {
  std::size_t stale = 0;
  for (const MovingBodyData& b : data.bodies)
    stale += b.coast.active && b.coast.synced != data.step_count;
  if (stale == 0) return;
  Bodies bodies{&model, &data};
  const std::size_t n = data.bodies.size();
  if (pool && pool->threads() > 1 &&
      stale >= kMinBodiesPerThread * static_cast<std::size_t>(pool->threads())) {
    pool->parallelFor(n, syncRange, &bodies);
  } else {
    syncRange(&bodies, 0, n);
  }
}

void endCoast(const Model& model, MovingBodyData& b, int i, std::uint64_t now) {
  if (!b.coast.active) return;
  syncBody(model, b, i, now);
  b.coast = MovingBodyData::Coast();
  b.integrator->reset();
}

}  // namespace sim
}  // namespace cga_rigid_sim
