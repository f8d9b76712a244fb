// makeData: the changing part of a World at its initial state.
#include "cga_rigid_sim/sim/data.h"

#include "sim/curved_bodies.h"

namespace cga_rigid_sim {
namespace sim {

Result<MovingBodyData> makeBodyData(const Model& model, const dynamics::BodyState& initial,
                                    int moving_index) {
  // In curved space the Euclidean integrator is never stepped (sim/curved_bodies.h): a cga2
  // stands in for it so that nothing holds a null integrator.
  auto integrator = dynamics::makeIntegrator(model.curved_space ? "cga2" : model.config.integrator);
  if (!integrator) return Error("config", "integrator", integrator.error());
  MovingBodyData b;
  b.state = initial;
  b.integrator = std::move(integrator.value());
  b.loads.setGravity(model.scene.gravity_W);
  if (model.curved_space) {
    if (moving_index < 0) return Error("config", "curvature", "a body without its moving index");
    if (auto e = makeCurvedBodyData(model, moving_index, initial, b)) return *e;
  }
  return b;
}

Result<TreeData> makeTreeData(const Model& model, int t) {
  const TreeModel& tm = model.trees[t];
  auto integrator = dynamics::makeTreeIntegrator(model.config.integrator);
  if (!integrator) return Error("config", "integrator", integrator.failure().rule);
  TreeData d;
  d.state = tm.initial;
  d.integrator = std::move(integrator.value());
  const int n = tm.body.jointCount();
  d.loads.gravity_W = model.scene.gravity_W;
  d.loads.applied.assign(tm.body.bodyCount(), nullptr);
  d.loads.effort = Eigen::VectorXd::Zero(n);
  d.controller_effort = Eigen::VectorXd::Zero(n);
  d.held_effort = Eigen::VectorXd::Zero(n);
  d.clamped_steps.assign(n, 0);
  d.drift_loads.applied.assign(tm.body.bodyCount(), nullptr);
  d.drift_loads.effort = Eigen::VectorXd::Zero(n);
  d.contact_shift = Eigen::VectorXd::Zero(tm.body.velocityCount());
  d.contact_nu = Eigen::VectorXd::Zero(tm.body.velocityCount());
  d.limited_end.q = Eigen::VectorXd::Zero(n);
  d.limited_end.v = Eigen::VectorXd::Zero(n);
  return d;
}

void writeTreeBodies(const Model& model, Data& data, int t) {
  const TreeModel& tm = model.trees[t];
  dynamics::TreeKinematics& kin = data.tree_scratch.write_kin;
  dynamics::treeKinematics(tm.body, data.trees[t].state, kin);
  for (int b = tm.body.floating() ? 0 : 1; b < tm.body.bodyCount(); ++b) {
    MovingBodyData& body = data.bodies[tm.movingOf(b)];
    body.state = {kin.M_W[b], kin.omega[b]};
    body.last_path = StepPath::kStepped;
  }
}

Result<Data> makeData(const Model& model) {
  Data data;
  const int n = static_cast<int>(model.moving.size());
  data.bodies.reserve(n);
  for (int i = 0; i < n; ++i) {
    auto b = makeBodyData(model, model.moving[i].initial, i);
    if (!b) return b.failure();
    data.bodies.push_back(std::move(b.value()));
  }
  data.coasting.assign(n, 0);
  data.dirty_list.reserve(n);
  for (int t = 0; t < static_cast<int>(model.trees.size()); ++t) {
    auto td = makeTreeData(model, t);
    if (!td) return td.failure();
    data.trees.push_back(std::move(td.value()));
  }
  return data;
}

}  // namespace sim
}  // namespace cga_rigid_sim
