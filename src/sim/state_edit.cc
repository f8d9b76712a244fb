#include "sim/state_edit.h"

#include "cga_rigid_sim/scene/placement.h"
#include "sim/input/input_admission.h"
#include "sim/input/input_rules.h"
#include "sim/input/wrench_schedule.h"

namespace cga_rigid_sim {
namespace sim {

std::optional<Error> checkStateInput(const std::string& input, const Eigen::Isometry3d& pose_root,
                                     const Eigen::Vector3d& v_W, const Eigen::Vector3d& w_W) {
  if (auto e = checkPose(input, pose_root)) return e;
  if (auto e = checkFinite(input, "linear_velocity", v_W)) return e;
  if (auto e = checkFinite(input, "angular_velocity", w_W)) return e;
  if (auto e = checkMagnitude(input, "pose.translation", pose_root.translation(), kMaxPointDistance,
                              "the largest distance", "m"))
    return e;
  if (auto e = checkMagnitude(input, "linear_velocity", v_W, kMaxSpeed, "the largest speed", "m/s"))
    return e;
  return checkMagnitude(input, "angular_velocity", w_W, kMaxAngularSpeed,
                        "the largest angular speed", "rad/s");
}

Result<bool> setBodyState(const Model& model, Data& data, const std::string& body,
                          const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                          const Eigen::Vector3d& w_W) {
  const std::string what = "set_body_state";
  if (auto e = checkStateInput(what, pose_root, v_W, w_W)) return *e;
  auto target = movingTarget(model, what, body);
  if (!target) return target.failure();
  const int i = *target;
  MovingBodyData& b = data.bodies[i];
  if (const int t = model.tree_of_moving[i]; t >= 0) {
    if (model.tree_body_of_moving[i] != 0) {
      const int k = model.tree_body_of_moving[i] - 1;
      return Error(what, "body",
                   "body '" + body + "' is moved by joint '" +
                       model.scene.joints[model.trees[t].scene_joint[k]].name +
                       "' of a tree: set the tree's root, or the joint positions in "
                       "~initial_state");
    }
    // The floating root of a tree: the whole tree moves with it, joints unchanged.
    const dynamics::BodyState s =
        scene::placedState(model.bodyOf(i).links.front().M_BL, pose_root, v_W, w_W, model.lambda);
    data.trees[t].state.M_W0 = s.M_WB;
    data.trees[t].state.omega_0 = s.omega_B;
    data.trees[t].integrator->reset();
    writeTreeBodies(model, data, t);
    return true;
  }
  data.coasting[i] = 0;  // the new state replaces the coast's
  b.state =
      scene::placedState(model.bodyOf(i).links.front().M_BL, pose_root, v_W, w_W, model.lambda);
  b.integrator->reset();
  return true;
}

void resetBodies(const Model& model, Data& data) {
  dropActiveWrenches(data);
  data.queue.clear();
  data.dirty_list.clear();
  data.contacts.clear();
  data.dissipated_energy = 0.0;
  // Remade, not patched: a per-body datum added to MovingBodyData is reset with it.
  // (makeBodyData fails only for an unknown integrator, which compileModel refused.)
  for (std::size_t i = 0; i < data.bodies.size(); ++i)
    if (auto b = makeBodyData(model, model.moving[i].initial, static_cast<int>(i)))
      data.bodies[i] = std::move(b.value());
  data.coasting.assign(data.bodies.size(), 0);
  for (int t = 0; t < static_cast<int>(model.trees.size()); ++t)
    if (auto td = makeTreeData(model, t)) {
      data.trees[t] = std::move(td.value());
      writeTreeBodies(model, data, t);
    }
}

}  // namespace sim
}  // namespace cga_rigid_sim
