// Stage 2 of the step: each body's loads are gravity (set once, when its data is made) plus its
// active wrenches, summed in the order they started. Only bodies whose set of wrenches changed
// are rebuilt.
#include "cga_rigid_sim/sim/stages.h"

namespace cga_rigid_sim {
namespace sim {

void updateLoads(const Model& /*model*/, Data& data) {
  if (data.dirty_list.empty()) return;
  for (int i : data.dirty_list) data.bodies[i].loads.clearApplied();
  for (const auto& a : data.active) {
    MovingBodyData& b = data.bodies[a.body];
    if (b.loads_dirty) b.loads.add(a.load);  // room reserved when the wrench was queued
  }
  for (int i : data.dirty_list) data.bodies[i].loads_dirty = false;
  data.dirty_list.clear();
}

}  // namespace sim
}  // namespace cga_rigid_sim
