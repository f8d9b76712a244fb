// InputQueue: validated wrenches, impulses and joint efforts waiting for the step they belong to.
//
// Inputs come out ordered by (step, arrival number), so the order in which they take effect
// depends only on their stamps and, within one step, on the order they arrived — never on
// wall time or addresses. Replaying the same inputs in the same order gives the same states
// bit for bit.
//
// The queue is a binary min-heap on (step, arrival): pushing and popping cost O(log n) moves,
// whatever the stamps (a sorted array paid a shift of the whole queue for every input stamped
// before the last one). Pushing may allocate (it runs when an input arrives); taking the due
// inputs (popDue) never does, so World::step() stays allocation-free. The queue also counts its
// inputs per body and per tree, so the bounds on waiting inputs (WorldConfig) cost O(1).
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "cga_rigid_sim/body/loads.h"
#include "cga_rigid_sim/cga/force.h"

namespace cga_rigid_sim {
namespace sim {

/// A wrench that lasts until cleared has this end step.
constexpr std::uint64_t kUntilCleared = std::numeric_limits<std::uint64_t>::max();

/// One input, resolved to a body and to the axes its directions are fixed in.
///
/// axes == kBody (given in a link frame): F, point and couple are already converted to the
/// body frame B (the link's placement M_BL is constant). axes == kWorld (given in the world
/// frame): F and couple are in world axes and `point` is the world point; it becomes a
/// material point of B only when the input takes effect, at the pose of that step.
struct QueuedInput {
  /// kHeldEffort sets a joint's held effort; kTimedEffort starts an effort for `steps` steps;
  /// kJointState sets a joint's position and rate.
  enum class Kind { kWrench, kImpulse, kHeldEffort, kTimedEffort, kJointState };
  Kind kind = Kind::kWrench;
  std::uint64_t step = 0;     ///< the step it takes effect at (start of the step)
  std::uint64_t arrival = 0;  ///< arrival number (tie-break within a step)
  int body = -1;              ///< moving-body index in the World (wrenches, impulses)
  dynamics::Axes axes = dynamics::Axes::kWorld;
  cga::Force F;  ///< force (N) or linear impulse (N s), in `axes`
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< m: B (kBody) or world (kWorld)
  Eigen::Vector3d couple = Eigen::Vector3d::Zero();  ///< N m or N m s, in `axes`
  std::uint64_t steps = 1;  ///< wrench: how many steps it lasts; 0 = until cleared
  int tree = -1;            ///< efforts: the tree and the joint index in it
  int joint = -1;
  double effort = 0.0;                    ///< N m or N
  double position = 0.0, velocity = 0.0;  ///< kJointState: rad (m) and rad/s (m/s)
};

class InputQueue {
 public:
  /// Queues an input; its arrival number is assigned here (the next in sequence). O(log n).
  void push(QueuedInput in);
  /// The next input due at or before `step`, in (step, arrival) order, or nullptr. The pointer
  /// stays valid until the next popDue/push/clear/remove. O(log n); never allocates.
  const QueuedInput* popDue(std::uint64_t step);
  /// Whether an input is due at or before `step`.
  bool hasDue(std::uint64_t step) const { return !heap_.empty() && heap_.front().step <= step; }

  /// Inputs waiting (not yet popped).
  std::size_t size() const { return heap_.size(); }
  bool empty() const { return heap_.empty(); }
  /// Waiting inputs of one moving body (wrenches and impulses), of one tree (joint efforts).
  std::size_t bodyCount(int body) const { return countAt(body_inputs_, body); }
  std::size_t treeCount(int tree) const { return countAt(tree_inputs_, tree); }
  /// Waiting wrenches of one body and in all, waiting timed efforts of one tree (to reserve
  /// room for them before they start).
  std::size_t wrenchCount(int body) const { return countAt(body_wrenches_, body); }
  std::size_t wrenchCount() const { return wrenches_; }
  std::size_t timedEffortCount(int tree) const { return countAt(tree_timed_, tree); }

  /// Drops everything waiting. The arrival counter keeps running.
  void clear();
  /// Drops every waiting wrench and timed joint effort (impulses and held efforts stay).
  void clearWrenches();
  /// Drops the inputs of moving body `body` and renumbers the bodies after it (body − 1), as
  /// when that body is deleted.
  void removeBody(int body);
  /// Drops the joint inputs of tree `tree` and renumbers the trees after it (tree − 1), as when
  /// a spawned robot with that tree is deleted.
  void removeTree(int tree);

 private:
  static std::size_t countAt(const std::vector<std::size_t>& v, int i) {
    return i >= 0 && static_cast<std::size_t>(i) < v.size() ? v[i] : 0;
  }
  void count(const QueuedInput& q, int sign);
  template <class Drop>
  void removeIf(Drop drop);

  std::vector<QueuedInput> heap_;  ///< min-heap on (step, arrival)
  QueuedInput popped_;             ///< the last input popDue handed out
  std::uint64_t next_arrival_ = 0;
  std::vector<std::size_t> body_inputs_, body_wrenches_;  ///< per moving body
  std::vector<std::size_t> tree_inputs_, tree_timed_;     ///< per tree
  std::size_t wrenches_ = 0;
};

}  // namespace sim
}  // namespace cga_rigid_sim
