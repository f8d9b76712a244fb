// Mimic joints in the scene (joint.h, doc/urdf.md#mimic-joints): the range a leader may take,
// and the followers' initial state from their leaders'.
#include <algorithm>
#include <limits>

#include "cga_rigid_sim/scene/joint.h"
#include "cga_rigid_sim/tree/articulated_body.h"

namespace cga_rigid_sim {
namespace scene {

std::pair<double, double> mimicRange(const std::vector<JointModel>& joints, int joint) {
  const JointLimits& own = joints[joint].limits;
  double lower = own.has_position ? own.lower : -std::numeric_limits<double>::infinity();
  double upper = own.has_position ? own.upper : std::numeric_limits<double>::infinity();
  for (const JointModel& j : joints) {
    if (!j.mimic || j.mimic->leader != joint || !j.limits.has_position) continue;
    const auto [lo, hi] = dynamics::leaderLimits(j.limits.lower, j.limits.upper,
                                                 j.mimic->multiplier, j.mimic->offset);
    lower = std::max(lower, lo);
    upper = std::min(upper, hi);
  }
  return {lower, upper};
}

void followLeaders(std::vector<JointModel>& joints) {
  for (JointModel& j : joints) {
    if (!j.mimic) continue;
    const JointModel& l = joints[j.mimic->leader];
    double q = j.mimic->multiplier * l.initial_position + j.mimic->offset;
    if (j.limits.has_position) q = std::clamp(q, j.limits.lower, j.limits.upper);
    j.initial_position = q;
    j.initial_velocity = j.mimic->multiplier * l.initial_velocity;
  }
}

}  // namespace scene
}  // namespace cga_rigid_sim
