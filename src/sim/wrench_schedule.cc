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

bool mayStart(const Model& model, Data& data, const QueuedInput& in, std::uint64_t k) {
  const bool wrench = in.kind == QueuedInput::Kind::kWrench;
  std::size_t total = data.active.size();
  for (const TreeData& t : data.trees) total += t.timed.size();
  const std::size_t own =
      wrench ? data.bodies[in.body].active_wrenches : data.trees[in.tree].timed.size();
  const bool per_body = own >= static_cast<std::size_t>(model.config.max_active_wrenches_per_body);
  if (!per_body && total < static_cast<std::size_t>(model.config.max_active_wrenches)) return true;
  StartRefusals& r = data.start_refusals;
  ++r.count;
  r.input = in;  // a copy of fixed size: no allocation
  r.step = k;
  r.per_body = per_body;
  r.active = per_body ? own : total;
  return false;
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
  ++data.bodies[in.body].active_wrenches;
  data.next_expiry = std::min(data.next_expiry, a.end_step);
  markLoadsDirty(data, in.body);
}

void expireWrenches(Data& data, std::uint64_t k) {
  std::size_t out = 0;
  data.next_expiry = kUntilCleared;
  for (std::size_t a = 0; a < data.active.size(); ++a) {
    if (data.active[a].end_step <= k) {
      markLoadsDirty(data, data.active[a].body);
      --data.bodies[data.active[a].body].active_wrenches;
      continue;
    }
    data.next_expiry = std::min(data.next_expiry, data.active[a].end_step);
    if (out != a) data.active[out] = data.active[a];
    ++out;
  }
  data.active.resize(out);  // shrinking never allocates
}

void dropActiveWrenches(Data& data) {
  for (const auto& a : data.active) {
    data.bodies[a.body].loads.clearApplied();
    data.bodies[a.body].active_wrenches = 0;
  }
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
