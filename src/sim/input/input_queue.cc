#include "cga_rigid_sim/sim/input/input_queue.h"

#include <algorithm>

namespace cga_rigid_sim {
namespace sim {
namespace {

// The heap's order: std::push_heap keeps the largest on top, so "larger" is "later".
bool later(const QueuedInput& a, const QueuedInput& b) {
  return a.step != b.step ? a.step > b.step : a.arrival > b.arrival;
}

// Counts one more (sign > 0) or one less input at index i; the vector grows only when pushing.
void add(std::vector<std::size_t>& v, int i, int sign) {
  if (i < 0) return;
  if (static_cast<std::size_t>(i) >= v.size()) v.resize(i + 1, 0);
  if (sign > 0)
    ++v[i];
  else
    --v[i];
}

}  // namespace

void InputQueue::count(const QueuedInput& q, int sign) {
  const bool wrench = q.kind == QueuedInput::Kind::kWrench;
  if (q.kind == QueuedInput::Kind::kWrench || q.kind == QueuedInput::Kind::kImpulse) {
    add(body_inputs_, q.body, sign);
    if (wrench) add(body_wrenches_, q.body, sign);
  } else {
    add(tree_inputs_, q.tree, sign);
    if (q.kind == QueuedInput::Kind::kTimedEffort) add(tree_timed_, q.tree, sign);
  }
  if (wrench) {
    if (sign > 0)
      ++wrenches_;
    else
      --wrenches_;
  }
}

void InputQueue::push(QueuedInput in) {
  in.arrival = next_arrival_++;
  count(in, +1);
  heap_.push_back(in);
  std::push_heap(heap_.begin(), heap_.end(), later);
}

const QueuedInput* InputQueue::popDue(std::uint64_t step) {
  if (!hasDue(step)) return nullptr;
  std::pop_heap(heap_.begin(), heap_.end(), later);  // moves only; no allocation
  popped_ = heap_.back();
  heap_.pop_back();
  count(popped_, -1);  // the counters exist for every index pushed: no resize here
  return &popped_;
}

void InputQueue::clear() {
  heap_.clear();
  std::fill(body_inputs_.begin(), body_inputs_.end(), 0);
  std::fill(body_wrenches_.begin(), body_wrenches_.end(), 0);
  std::fill(tree_inputs_.begin(), tree_inputs_.end(), 0);
  std::fill(tree_timed_.begin(), tree_timed_.end(), 0);
  wrenches_ = 0;
}

template <class Drop>
void InputQueue::removeIf(Drop drop) {
  std::vector<QueuedInput> kept;
  kept.reserve(heap_.size());
  for (const QueuedInput& q : heap_) {
    if (drop(q))
      count(q, -1);
    else
      kept.push_back(q);
  }
  // The arrival numbers stay, so (step, arrival) order among what is kept is unchanged.
  std::make_heap(kept.begin(), kept.end(), later);
  heap_.swap(kept);
}

void InputQueue::clearWrenches() {
  removeIf([](const QueuedInput& q) {
    return q.kind == QueuedInput::Kind::kWrench || q.kind == QueuedInput::Kind::kTimedEffort;
  });
}

void InputQueue::removeBody(int body) {
  removeIf([body](const QueuedInput& q) {
    return q.body == body &&
           (q.kind == QueuedInput::Kind::kWrench || q.kind == QueuedInput::Kind::kImpulse);
  });
  for (auto& q : heap_)
    if (q.body > body) --q.body;
  for (auto* v : {&body_inputs_, &body_wrenches_})
    if (static_cast<std::size_t>(body) < v->size()) v->erase(v->begin() + body);
}

void InputQueue::removeTree(int tree) {
  removeIf([tree](const QueuedInput& q) {
    return q.tree == tree &&
           (q.kind != QueuedInput::Kind::kWrench && q.kind != QueuedInput::Kind::kImpulse);
  });
  for (auto& q : heap_)
    if (q.tree > tree) --q.tree;
  for (auto* v : {&tree_inputs_, &tree_timed_})
    if (static_cast<std::size_t>(tree) < v->size()) v->erase(v->begin() + tree);
}

}  // namespace sim
}  // namespace cga_rigid_sim
