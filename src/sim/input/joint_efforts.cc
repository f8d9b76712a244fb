// Joint-effort inputs and joint states (joint_efforts.h).
#include "sim/input/joint_efforts.h"

#include <cmath>
#include <map>
#include <set>

#include "cga_rigid_sim/format.h"
#include "sim/input/input_admission.h"
#include "sim/input/input_rules.h"

namespace cga_rigid_sim {
namespace sim {

namespace {

Result<std::pair<int, int>> findJoint(const Model& model, const std::string& input,
                                      const std::string& field, const std::string& name) {
  const auto it = model.joint_by_name.find(name);
  if (it == model.joint_by_name.end()) {
    std::string known;
    for (const auto& kv : model.joint_by_name) {
      if (known.size() > 200) {
        known += ", …";
        break;
      }
      known += (known.empty() ? "'" : ", '") + kv.first + "'";
    }
    return Error(input, field,
                 "unknown joint '" + name + "'" +
                     (known.empty() ? std::string(" (the scene has no joints)")
                                    : " (joints: " + known + ")"));
  }
  return it->second;
}

}  // namespace

Result<bool> queueJointEfforts(const Model& model, Data& data, const JointEffortInput& in) {
  const std::string what = "joint_efforts";
  if (in.names.size() != in.efforts.size())
    return Error(what, "effort",
                 "has " + std::to_string(in.efforts.size()) + " entries for " +
                     std::to_string(in.names.size()) + " names (one effort per name)");
  if (!std::isfinite(in.stamp)) return Error(what, "stamp", "not finite (" + num(in.stamp) + ")");
  auto k = stepOf(model, data, what, in.stamp);
  if (!k) return Error(what, "stamp", k.failure().rule);
  std::vector<QueuedInput> out;
  std::set<std::string> seen;
  for (std::size_t n = 0; n < in.names.size(); ++n) {
    const std::string field = "name[" + std::to_string(n) + "]";
    auto joint = findJoint(model, what, field, in.names[n]);
    if (!joint) return joint.failure();
    if (!seen.insert(in.names[n]).second)
      return Error(what, field, "joint '" + in.names[n] + "' given twice");
    const std::string effort = "effort[" + std::to_string(n) + "]";
    if (!std::isfinite(in.efforts[n]))
      return Error(what, effort, "not finite (" + num(in.efforts[n]) + ")");
    if (auto e = checkMagnitude(what, effort, Eigen::Vector3d(in.efforts[n], 0, 0),
                                model.config.max_force, "max_force", "N m (or N)"))
      return *e;
    QueuedInput q;
    q.kind = QueuedInput::Kind::kHeldEffort;
    q.step = *k;
    q.tree = joint->first;
    q.joint = joint->second;
    q.effort = in.efforts[n];
    out.push_back(q);
  }
  // The bounds on waiting inputs, for the message as a whole (refused whole or queued whole).
  std::map<int, std::pair<std::size_t, const QueuedInput*>> per_tree;  // count, first entry
  for (const QueuedInput& q : out) {
    auto& [n, first] = per_tree[q.tree];
    if (n++ == 0) first = &q;
  }
  for (const auto& [tree, entry] : per_tree)
    if (auto e = checkQueueRoom(model, data, what, "name", *entry.second, entry.first)) return *e;
  if (auto e = checkQueueTotal(model, data, what, out.size())) return *e;
  for (const QueuedInput& q : out) data.queue.push(q);
  return true;
}

Result<bool> queueTimedJointEffort(const Model& model, Data& data,
                                   const TimedJointEffortInput& in) {
  const std::string what = "apply_joint_effort";
  auto joint = findJoint(model, what, "joint", in.joint);
  if (!joint) return joint.failure();
  if (auto e = checkFinite(what, "effort", in.effort)) return *e;
  if (auto e = checkMagnitude(what, "effort", Eigen::Vector3d(in.effort, 0, 0),
                              model.config.max_force, "max_force", "N m (or N)"))
    return *e;
  if (auto e = checkFinite(what, "duration", in.duration)) return *e;
  if (auto e = checkFinite(what, "start_time", in.start_time)) return *e;
  auto k = stepOf(model, data, what, in.start_time);
  if (!k) return k.failure();
  std::uint64_t steps = 1;  // the duration rules of wrenches (world.h)
  if (in.duration < 0) {
    steps = 0;
  } else if (in.duration > 0) {
    const double n = std::floor(in.duration / model.config.dt + 0.5 + kStepTolerance);
    if (n > kMaxSteps)
      return Error(what, "duration",
                   num(in.duration) + " s is more than " + num(kMaxSteps) +
                       " steps (use a negative duration: until cleared)");
    steps = std::max<std::uint64_t>(1, static_cast<std::uint64_t>(n));
  }
  QueuedInput q;
  q.kind = QueuedInput::Kind::kTimedEffort;
  q.step = *k;
  q.tree = joint->first;
  q.joint = joint->second;
  q.effort = in.effort;
  q.steps = steps;
  if (auto e = checkQueueRoom(model, data, what, "joint", q)) return *e;
  // Room for it when it starts, so the step does not allocate: at most every timed effort of
  // the tree active or waiting, and never more than the bound lets start.
  TreeData& td = data.trees[q.tree];
  td.timed.reserve(roomFor(td.timed.size() + data.queue.timedEffortCount(q.tree) + 1,
                           model.config.max_active_wrenches_per_body));
  data.queue.push(q);
  return true;
}

std::vector<JointStateReport> jointStateReports(const Model& model, const Data& data) {
  std::vector<JointStateReport> out;
  for (std::size_t t = 0; t < model.trees.size(); ++t) {
    const TreeModel& tm = model.trees[t];
    const TreeData& td = data.trees[t];
    for (int k = 0; k < tm.body.jointCount(); ++k) {
      JointStateReport r;
      r.name = model.scene.joints[tm.scene_joint[k]].name;
      r.position = td.state.q[k];
      r.velocity = td.state.v[k];
      r.effort = td.loads.effort[k];
      r.clamped_steps = td.clamped_steps[k];
      out.push_back(std::move(r));
    }
  }
  return out;
}

}  // namespace sim
}  // namespace cga_rigid_sim
