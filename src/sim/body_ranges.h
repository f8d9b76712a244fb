// Per-body work over all moving bodies, split between the WorkerPool's threads when there is
// enough of it (stages.h, kMinBodiesPerThread): the integration stage and the evaluation of
// coasting states (coasting.cc) share this, so both split the bodies the same way.
#pragma once

#include "cga_rigid_sim/sim/data.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/sim/stages.h"
#include "cga_rigid_sim/sim/worker_pool.h"

namespace cga_rigid_sim {
namespace sim {

/// What a range function over the bodies receives as its context.
struct BodyRange {
  const Model* model;
  Data* data;
};

/// Runs fn(context, begin, end) over the moving bodies [0, n): on the pool when it has several
/// threads and `work` (bodies that need something done) gives each at least
/// kMinBodiesPerThread, else on this thread.
inline void forBodyRanges(const Model& model, Data& data, WorkerPool* pool, std::size_t work,
                          WorkerPool::RangeFn fn) {
  BodyRange context{&model, &data};
  const std::size_t n = data.bodies.size();
  if (pool && pool->threads() > 1 &&
      work >= kMinBodiesPerThread * static_cast<std::size_t>(pool->threads())) {
    pool->parallelFor(n, fn, &context);
  } else {
    fn(&context, 0, n);
  }
}

}  // namespace sim
}  // namespace cga_rigid_sim
