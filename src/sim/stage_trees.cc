// The tree stage of the step (sim/stages.h): every articulated tree advances over the step with
// its integrator under gravity, the loads on its links and its joints' efforts; then its bodies'
// states are written from the tree's (doc/articulated.md#in-the-step).
#include <algorithm>
#include <cmath>

#include "cga_rigid_sim/sim/stages.h"

namespace cga_rigid_sim {
namespace sim {

void integrateTrees(const Model& model, Data& data) {
  for (int t = 0; t < static_cast<int>(model.trees.size()); ++t) {
    const TreeModel& tm = model.trees[t];
    TreeData& td = data.trees[t];
    // The actuators: held effort plus the timed ones, clamped to <limit effort>.
    td.loads.effort = td.held_effort;
    for (const ActiveEffort& a : td.timed) td.loads.effort[a.joint] += a.effort;
    for (int k = 0; k < tm.body.jointCount(); ++k) {
      const double limit = tm.body.joints()[k].effort_limit;
      double& e = td.loads.effort[k];
      if (std::abs(e) > limit) {
        e = std::clamp(e, -limit, limit);
        ++td.clamped_steps[k];
      }
    }
    for (int b = 0; b < tm.body.bodyCount(); ++b) {
      const int i = tm.movingOf(b);
      td.loads.applied[b] =
          i >= 0 && data.bodies[i].loads.hasApplied() ? &data.bodies[i].loads : nullptr;
    }
    td.integrator->step(tm.body, td.loads, model.config.dt, td.state);
    writeTreeBodies(model, data, t);
  }
}

void expireEfforts(Data& data) {
  for (TreeData& td : data.trees)
    td.timed.erase(
        std::remove_if(td.timed.begin(), td.timed.end(),
                       [&](const ActiveEffort& a) { return a.end_step <= data.step_count; }),
        td.timed.end());
}

}  // namespace sim
}  // namespace cga_rigid_sim
