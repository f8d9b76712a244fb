#include "state_edit.h"

#include "cga_rigid_sim/scene/placement.h"
#include "input_admission.h"
#include "input_rules.h"
#include "wrench_schedule.h"

namespace cga_rigid_sim {
namespace sim {

Result<bool> setBodyState(const Model& model, Data& data, const std::string& body,
                          const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                          const Eigen::Vector3d& w_W) {
  const std::string what = "set_body_state";
  if (auto e = checkPose(what, pose_root)) return *e;
  if (auto e = checkFinite(what, "linear_velocity", v_W)) return *e;
  if (auto e = checkFinite(what, "angular_velocity", w_W)) return *e;
  auto target = movingTarget(model, what, body);
  if (!target) return target.failure();
  const int i = *target;
  MovingBodyData& b = data.bodies[i];
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
    if (auto b = makeBodyData(model, model.moving[i].initial))
      data.bodies[i] = std::move(b.value());
}

}  // namespace sim
}  // namespace cga_rigid_sim
