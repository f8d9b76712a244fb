#include "cga_rigid_sim/sim/input_queue.h"

#include <algorithm>

namespace cga_rigid_sim {
namespace sim {

void InputQueue::push(QueuedInput in) {
  compact();
  in.arrival = next_arrival_++;
  // Arrival numbers only grow, so the place in (step, arrival) order is after every input of
  // the same or an earlier step.
  const auto pos =
      std::upper_bound(items_.begin(), items_.end(), in.step,
                       [](std::uint64_t step, const QueuedInput& q) { return step < q.step; });
  items_.insert(pos, in);
}

std::size_t InputQueue::wrenchCount(int body) const {
  std::size_t n = 0;
  for (std::size_t i = head_; i < items_.size(); ++i)
    if (items_[i].body == body && items_[i].kind == QueuedInput::Kind::kWrench) ++n;
  return n;
}

void InputQueue::clear() {
  items_.clear();
  head_ = 0;
}

void InputQueue::clearWrenches() {
  compact();
  items_.erase(std::remove_if(items_.begin(), items_.end(),
                              [](const QueuedInput& q) {
                                return q.kind == QueuedInput::Kind::kWrench ||
                                       q.kind == QueuedInput::Kind::kTimedEffort;
                              }),
               items_.end());
}

void InputQueue::removeBody(int body) {
  compact();
  items_.erase(std::remove_if(items_.begin(), items_.end(),
                              [body](const QueuedInput& q) { return q.body == body; }),
               items_.end());
  for (auto& q : items_)
    if (q.body > body) --q.body;
}

// Drops the popped prefix (outside step(), where allocation and moves are allowed).
void InputQueue::compact() {
  items_.erase(items_.begin(), items_.begin() + static_cast<std::ptrdiff_t>(head_));
  head_ = 0;
}

}  // namespace sim
}  // namespace cga_rigid_sim
