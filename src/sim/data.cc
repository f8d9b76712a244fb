// makeData: the changing part of a World at its initial state.
#include "cga_rigid_sim/sim/data.h"

namespace cga_rigid_sim {
namespace sim {

Result<MovingBodyData> makeBodyData(const Model& model, const dynamics::BodyState& initial) {
  auto integrator = dynamics::makeIntegrator(model.config.integrator);
  if (!integrator) return Error("config", "integrator", integrator.error());
  MovingBodyData b;
  b.state = initial;
  b.integrator = std::move(integrator.value());
  b.loads.setGravity(model.scene.gravity_W);
  return b;
}

Result<Data> makeData(const Model& model) {
  Data data;
  const int n = static_cast<int>(model.moving.size());
  data.bodies.reserve(n);
  for (int i = 0; i < n; ++i) {
    auto b = makeBodyData(model, model.moving[i].initial);
    if (!b) return b.failure();
    data.bodies.push_back(std::move(b.value()));
  }
  data.dirty_list.reserve(n);
  return data;
}

}  // namespace sim
}  // namespace cga_rigid_sim
