// Stage 4 of the step: wrenches whose last step was the one just done end; their loads drop
// out at the next updateLoads.
#include "cga_rigid_sim/sim/stages.h"
#include "sim/input/wrench_schedule.h"

namespace cga_rigid_sim {
namespace sim {

void expireInputs(const Model& /*model*/, Data& data) {
  expireWrenches(data, data.step_count);  // a look at the heap's top when nothing ends
  if (!data.trees.empty()) expireEfforts(data);
}

}  // namespace sim
}  // namespace cga_rigid_sim
