// Checks the fuzz targets make on what the core accepted: a loaded scene holds only finite
// numbers and a moving body has an inertia. A broken check aborts (a finding for libFuzzer).
#pragma once

#include <string>

#include "cga_rigid_sim/scene/scene.h"

namespace cga_rigid_sim {
namespace fuzz {

/// Aborts with `what` and the reason on stderr.
[[noreturn]] void fail(const std::string& what);

/// Every body's initial pose and velocity, inertia, link placement and shape pose is finite,
/// every moving body has an inertia, and every joint's initial position and velocity is finite.
void checkSceneFinite(const scene::Scene& scene, const std::string& what);

}  // namespace fuzz
}  // namespace cga_rigid_sim
