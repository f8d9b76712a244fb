// What a loaded scene is, on one screen (the node logs it on load; the scene_summary app prints
// it).
#pragma once

#include <string>

#include "cga_rigid_sim/scene/scene.h"

namespace cga_rigid_sim {
namespace scene {

/// The one-screen summary printed on load: bodies, links merged into each, mass, principal
/// moments, inertia class, integrator path under `integrator`, active loads.
std::string sceneSummary(const Scene& scene, const std::string& integrator);

}  // namespace scene
}  // namespace cga_rigid_sim
