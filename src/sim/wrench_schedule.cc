#include "wrench_schedule.h"

#include <algorithm>

namespace cga_rigid_sim {
namespace sim {

void markLoadsDirty(Data& data, int i) {
  MovingBodyData& b = data.bodies[i];
  if (b.loads_dirty) return;
  b.loads_dirty = true;
  data.dirty_list.push_back(i);  // capacity reserved: one slot per body
}

void startWrench(const Model& model, Data& data, const QueuedInput& in, std::uint64_t k) {
  ActiveWrench a;
  a.body = in.body;
  a.end_step = in.steps == 0 ? kUntilCleared : k + in.steps;
  a.load.axes = in.axes;
  a.load.F = in.F;
  a.load.couple = in.couple;
  if (in.axes == dynamics::Axes::kWorld) {
    const cga::Motor& M = data.bodies[in.body].state.M_WB;
    a.load.point_B = M.rotation().conjugate() * (in.point - M.translation(model.lambda));
  } else {
    a.load.point_B = in.point;
  }
  data.active.push_back(a);  // capacity reserved when the input was queued
  data.next_expiry = std::min(data.next_expiry, a.end_step);
  markLoadsDirty(data, in.body);
}

void expireWrenches(Data& data, std::uint64_t k) {
  std::size_t out = 0;
  data.next_expiry = kUntilCleared;
  for (std::size_t a = 0; a < data.active.size(); ++a) {
    if (data.active[a].end_step <= k) {
      markLoadsDirty(data, data.active[a].body);
      continue;
    }
    data.next_expiry = std::min(data.next_expiry, data.active[a].end_step);
    if (out != a) data.active[out] = data.active[a];
    ++out;
  }
  data.active.resize(out);  // shrinking never allocates
}

void dropActiveWrenches(Data& data) {
  for (const auto& a : data.active) data.bodies[a.body].loads.clearApplied();
  data.active.clear();
  data.next_expiry = kUntilCleared;
}

void removeActiveWrenchesOf(Data& data, int i) {
  std::size_t out = 0;
  data.next_expiry = kUntilCleared;
  for (std::size_t a = 0; a < data.active.size(); ++a) {
    if (data.active[a].body == i) continue;
    ActiveWrench aw = data.active[a];
    if (aw.body > i) --aw.body;
    data.next_expiry = std::min(data.next_expiry, aw.end_step);
    data.active[out++] = aw;
  }
  data.active.resize(out);
}

}  // namespace sim
}  // namespace cga_rigid_sim
