// Joint states set from outside (inputs.h JointStateInput): checked completely and queued as one
// QueuedInput per joint, or refused with nothing queued; applied at their step
// (stage_inputs.cc).
#include <cmath>
#include <map>
#include <set>

#include "cga_rigid_sim/format.h"
#include "sim/input/input_admission.h"
#include "sim/input/input_rules.h"
#include "sim/input/joint_efforts.h"

namespace cga_rigid_sim {
namespace sim {

Result<bool> queueJointState(const Model& model, Data& data, const JointStateInput& in) {
  const std::string what = "set_joint_state";
  const std::size_t n = in.names.size();
  if (in.positions.size() != n)
    return Error(what, "position",
                 "has " + std::to_string(in.positions.size()) + " entries for " +
                     std::to_string(n) + " names (one position per name)");
  if (!in.velocities.empty() && in.velocities.size() != n)
    return Error(what, "velocity",
                 "has " + std::to_string(in.velocities.size()) + " entries for " +
                     std::to_string(n) + " names (one velocity per name, or none: 0)");
  if (!std::isfinite(in.stamp)) return Error(what, "stamp", "not finite (" + num(in.stamp) + ")");
  auto k = stepOf(model, data, what, in.stamp);
  if (!k) return Error(what, "stamp", k.failure().rule);
  std::vector<QueuedInput> out;
  std::set<std::string> seen;
  for (std::size_t i = 0; i < n; ++i) {
    const std::string index = "[" + std::to_string(i) + "]";
    const auto it = model.joint_by_name.find(in.names[i]);
    if (it == model.joint_by_name.end())
      return Error(what, "name" + index, "unknown joint '" + in.names[i] + "'");
    if (!seen.insert(in.names[i]).second)
      return Error(what, "name" + index, "joint '" + in.names[i] + "' given twice");
    const auto [tree, joint] = it->second;
    const TreeModel& tm = model.trees[tree];
    const dynamics::TreeJoint& tj = tm.body.joints()[joint];
    if (tj.mimic >= 0)
      return Error(what, "name" + index,
                   "joint '" + in.names[i] + "' mimics joint '" +
                       model.scene.joints[tm.scene_joint[tj.mimic]].name + "': set that one");
    const double q = in.positions[i], v = in.velocities.empty() ? 0.0 : in.velocities[i];
    if (!std::isfinite(q)) return Error(what, "position" + index, "not finite (" + num(q) + ")");
    if (!std::isfinite(v)) return Error(what, "velocity" + index, "not finite (" + num(v) + ")");
    if (q < tj.lower || q > tj.upper)
      return Error(what, "position" + index,
                   num(q) + " is outside the limits [" + num(tj.lower) + ", " + num(tj.upper) +
                       "] of joint '" + in.names[i] + "'");
    const double v_max = model.scene.joints[tm.scene_joint[joint]].limits.velocity;
    if (std::abs(v) > v_max)
      return Error(what, "velocity" + index,
                   num(v) + " is beyond the velocity limit " + num(v_max) + " of joint '" +
                       in.names[i] + "'");
    QueuedInput e;
    e.kind = QueuedInput::Kind::kJointState;
    e.step = *k;
    e.tree = tree;
    e.joint = joint;
    e.position = q;
    e.velocity = v;
    out.push_back(e);
  }
  std::map<int, std::pair<std::size_t, const QueuedInput*>> per_tree;  // count, first entry
  for (const QueuedInput& e : out) {
    auto& [count, first] = per_tree[e.tree];
    if (count++ == 0) first = &e;
  }
  for (const auto& [tree, entry] : per_tree)
    if (auto e = checkQueueRoom(model, data, what, "name", *entry.second, entry.first)) return *e;
  if (auto e = checkQueueTotal(model, data, what, out.size())) return *e;
  for (const QueuedInput& e : out) data.queue.push(e);
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
