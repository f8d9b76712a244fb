#include "state_edit.h"

#include "input_admission.h"
#include "input_rules.h"
#include "wrench_schedule.h"

namespace cga_rigid_sim {
namespace sim {

dynamics::BodyState placedState(const cga::Motor& M_BL0, const Eigen::Isometry3d& pose_root,
                                const Eigen::Vector3d& v_W, const Eigen::Vector3d& w_W,
                                double lambda) {
  const Eigen::Quaterniond R_WL(Eigen::Quaterniond(pose_root.linear()).normalized());
  const cga::Motor M_WL0 = cga::Motor::fromPose(R_WL, pose_root.translation(), lambda);
  dynamics::BodyState s;
  s.M_WB = (M_WL0 * M_BL0.reverse()).normalized();  // a unit motor to round-off
  const Eigen::Quaterniond R_BW = s.M_WB.rotation().conjugate();
  s.omega_B = cga::Bivelocity::fromVelocities(R_BW * w_W, R_BW * v_W, lambda);
  return s;
}

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
  b.state = placedState(model.bodyOf(i).links.front().M_BL, pose_root, v_W, w_W, model.lambda);
  b.integrator->reset();
  return true;
}

void resetBodies(const Model& model, Data& data) {
  dropActiveWrenches(data);
  data.queue.clear();
  data.dirty_list.clear();
  // Remade, not patched: a per-body datum added to MovingBodyData is reset with it.
  // (makeBodyData fails only for an unknown integrator, which compileModel refused.)
  for (std::size_t i = 0; i < data.bodies.size(); ++i)
    if (auto b = makeBodyData(model, model.moving[i].initial))
      data.bodies[i] = std::move(b.value());
}

}  // namespace sim
}  // namespace cga_rigid_sim
