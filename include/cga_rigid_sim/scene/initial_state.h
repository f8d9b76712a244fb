// The initial-state dictionary (doc/initial_state.md): initial poses and velocities per body,
// applied to a loaded scene.
#pragma once

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/scene/scene.h"

namespace cga_rigid_sim {
namespace scene {

/// Applies an initial-state dictionary (doc/initial_state.md) to the bodies' initial poses and
/// velocities. On error the scene is left unchanged and the message names the body and the key
/// ("<source>: initial_state.<body>.<key>: <rule>"). loadUrdf* call it with
/// SceneOptions::initial_state.
Result<bool> applyInitialState(Scene& scene, const ParamValue& initial_state);

}  // namespace scene
}  // namespace cga_rigid_sim
