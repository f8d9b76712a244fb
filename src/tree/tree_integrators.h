// Constructors of the tree integrators (tree_integrator.h), for the registry. Internal.
#pragma once

#include <memory>

#include "cga_rigid_sim/tree/tree_integrator.h"

namespace cga_rigid_sim {
namespace dynamics {

std::unique_ptr<TreeIntegrator> makeMidpointTreeIntegrator(bool fourth_order);
std::unique_ptr<TreeIntegrator> makeExplicitTreeIntegrator(bool rk4);

}  // namespace dynamics
}  // namespace cga_rigid_sim
