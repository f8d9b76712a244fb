#include "sim/input/wrench_schedule.h"

#include <algorithm>

#include "sim/coasting.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// The heap's order: std::push_heap keeps the largest on top, so "larger" is "ends later".
bool endsLater(const Data::Expiry& a, const Data::Expiry& b) { return a.end_step > b.end_step; }

}  // namespace

void markLoadsDirty(Data& data, int i) {
  MovingBodyData& b = data.bodies[i];
  if (b.loads_dirty) return;
  b.loads_dirty = true;
  data.dirty_list.push_back(i);  // capacity reserved: one slot per body
}

bool mayStart(const Model& model, Data& data, const QueuedInput& in, std::uint64_t k) {
  const bool wrench = in.kind == QueuedInput::Kind::kWrench;
  std::size_t total = data.active_wrenches;
  for (const TreeData& t : data.trees) total += t.timed.size();
  const std::size_t own =
      wrench ? data.bodies[in.body].wrenches.size() : data.trees[in.tree].timed.size();
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
  a.end_step = in.steps == 0 ? kUntilCleared : k + in.steps;
  a.load.axes = in.axes;
  a.load.F = in.F;
  a.load.couple = in.couple;
  MovingBodyData& b = data.bodies[in.body];
  endCoast(model, data, in.body);  // a world point is taken into the body at the pose now
  if (in.axes == dynamics::Axes::kWorld) {
    const cga::Motor& M = b.state.M_WB;
    a.load.point_B = M.rotation().conjugate() * (in.point - M.translation(model.lambda));
  } else {
    a.load.point_B = in.point;
  }
  b.wrenches.push_back(a);  // capacity reserved when the input was queued
  ++data.active_wrenches;
  if (a.end_step != kUntilCleared) {
    data.expiries.push_back({a.end_step, in.body});  // capacity reserved likewise
    std::push_heap(data.expiries.begin(), data.expiries.end(), endsLater);
  }
  markLoadsDirty(data, in.body);
}

void expireWrenches(Data& data, std::uint64_t k) {
  while (!data.expiries.empty() && data.expiries.front().end_step <= k) {
    const int i = data.expiries.front().body;
    std::pop_heap(data.expiries.begin(), data.expiries.end(), endsLater);
    data.expiries.pop_back();
    // Every wrench of the body that ends now goes at once (their other heap entries, popped
    // next, find none); the others keep their order. Shrinking never allocates.
    std::vector<ActiveWrench>& w = data.bodies[i].wrenches;
    const std::size_t before = w.size();
    w.erase(
        std::remove_if(w.begin(), w.end(), [k](const ActiveWrench& a) { return a.end_step <= k; }),
        w.end());
    if (w.size() == before) continue;
    data.active_wrenches -= before - w.size();
    markLoadsDirty(data, i);
  }
}

void dropActiveWrenches(Data& data) {
  for (MovingBodyData& b : data.bodies) {
    if (b.wrenches.empty()) continue;
    b.loads.clearApplied();
    b.wrenches.clear();
  }
  data.active_wrenches = 0;
  data.expiries.clear();
}

void removeActiveWrenchesOf(Data& data, int i) {
  data.active_wrenches -= data.bodies[i].wrenches.size();
  std::size_t out = 0;
  for (Data::Expiry e : data.expiries) {
    if (e.body == i) continue;
    if (e.body > i) --e.body;
    data.expiries[out++] = e;
  }
  data.expiries.resize(out);
  std::make_heap(data.expiries.begin(), data.expiries.end(), endsLater);
}

}  // namespace sim
}  // namespace cga_rigid_sim
