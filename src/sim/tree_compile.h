// compileTrees (tree_compile.cc): Model::trees, tree_of_moving, tree_body_of_moving and
// joint_by_name from the scene's joints; refuses a joint the scene got wrong (input "scene") and
// an integrator with no tree form when there are joints (input "config").
#pragma once

#include <optional>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/sim/model.h"

namespace cga_rigid_sim {
namespace sim {

std::optional<Error> compileTrees(Model& model);

}  // namespace sim
}  // namespace cga_rigid_sim
