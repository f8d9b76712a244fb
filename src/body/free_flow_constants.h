// The constants of the exact free flow (free_flow_constants.cc), for the flow (free_flow.cc).
// Internal.
#pragma once

#include <Eigen/Geometry>

#include "cga_rigid_sim/body/free_flow.h"
#include "cga_rigid_sim/body/inertia.h"

namespace cga_rigid_sim {
namespace dynamics {
namespace free_flow {

// Rebuilds the cache from the current rotational state: the rotor r and body w for the moments of
// `inertia`, by inertia class (the still, uniform, symmetric, elliptic and separatrix paths).
void build(const Inertia& inertia, const Eigen::Quaterniond& r, const Eigen::Vector3d& w,
           FreeFlowCache& c);

}  // namespace free_flow
}  // namespace dynamics
}  // namespace cga_rigid_sim
