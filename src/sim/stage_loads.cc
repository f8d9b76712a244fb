// Stage 2 of the step: each body's loads are gravity (set once, when its data is made) plus its
// active wrenches, summed in the order they started. Only bodies whose set of wrenches changed
// are rebuilt.
#include "cga_rigid_sim/sim/stages.h"
#include "sim/coasting.h"

namespace cga_rigid_sim {
namespace sim {

void updateLoads(const Model& model, Data& data) {
  if (data.dirty_list.empty()) return;
  for (int i : data.dirty_list) {
    MovingBodyData& b = data.bodies[i];
    endCoast(model, data, i);  // its loads change: stepped from here (coasting.h)
    b.loads.clearApplied();
    for (const ActiveWrench& a : b.wrenches) b.loads.add(a.load);  // room reserved when queued
    b.loads_dirty = false;
  }
  data.dirty_list.clear();
}

}  // namespace sim
}  // namespace cga_rigid_sim
