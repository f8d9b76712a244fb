// InputQueue: validated wrenches and impulses waiting for the step they belong to.
//
// Inputs are kept ordered by (step, arrival number), so the order in which they take effect
// depends only on their stamps and, within one step, on the order they arrived — never on
// wall time or addresses. Replaying the same inputs in the same order gives the same states
// bit for bit. Pushing may allocate (it runs when an input arrives); taking the due inputs
// (popDue) never does, so World::step() stays allocation-free.
#pragma once

#include <Eigen/Core>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "cga_rigid_sim/cga/force.h"
#include "cga_rigid_sim/dynamics/loads.h"

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
  /// kHeldEffort sets a joint's held effort; kTimedEffort starts an effort for `steps` steps.
  enum class Kind { kWrench, kImpulse, kHeldEffort, kTimedEffort };
  Kind kind = Kind::kWrench;
  std::uint64_t step = 0;     ///< the step it takes effect at (start of the step)
  std::uint64_t arrival = 0;  ///< arrival number (tie-break within a step)
  int body = -1;              ///< moving-body index in the World
  dynamics::Axes axes = dynamics::Axes::kWorld;
  cga::Force F;  ///< force (N) or linear impulse (N s), in `axes`
  Eigen::Vector3d point = Eigen::Vector3d::Zero();   ///< m: B (kBody) or world (kWorld)
  Eigen::Vector3d couple = Eigen::Vector3d::Zero();  ///< N m or N m s, in `axes`
  std::uint64_t steps = 1;  ///< wrench: how many steps it lasts; 0 = until cleared
  int tree = -1;            ///< efforts: the tree and the joint index in it
  int joint = -1;
  double effort = 0.0;  ///< N m or N
};

class InputQueue {
 public:
  /// Queues an input; its arrival number is assigned here (the next in sequence).
  void push(QueuedInput in);
  /// The next input due at or before `step`, in (step, arrival) order, or nullptr. The pointer
  /// stays valid until the next push/clear/remove. Never allocates.
  const QueuedInput* popDue(std::uint64_t step) {
    if (!hasDue(step)) return nullptr;
    return &items_[head_++];
  }
  /// Whether an input is due at or before `step`.
  bool hasDue(std::uint64_t step) const {
    return head_ != items_.size() && items_[head_].step <= step;
  }

  /// Inputs waiting (not yet popped).
  std::size_t size() const { return items_.size() - head_; }
  bool empty() const { return size() == 0; }
  /// Waiting wrenches for one body (to reserve room for them before they become active).
  std::size_t wrenchCount(int body) const;

  /// Drops everything waiting. The arrival counter keeps running.
  void clear();
  /// Drops every waiting wrench (impulses stay).
  void clearWrenches();
  /// Drops the inputs of moving body `body` and renumbers the bodies after it (body − 1), as
  /// when that body is deleted.
  void removeBody(int body);

 private:
  void compact();
  std::vector<QueuedInput> items_;  ///< sorted by (step, arrival); [0, head_) already popped
  std::size_t head_ = 0;
  std::uint64_t next_arrival_ = 0;
};

}  // namespace sim
}  // namespace cga_rigid_sim
