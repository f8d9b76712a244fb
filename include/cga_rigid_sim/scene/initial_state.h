// The initial-state dictionary (doc/initial_state.md): initial poses and velocities per body,
// and initial positions and velocities per joint, applied to a loaded scene.
#pragma once

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/param_value.h"
#include "cga_rigid_sim/scene/scene.h"

namespace cga_rigid_sim {
namespace scene {

/// Applies an initial-state dictionary (doc/initial_state.md) to the bodies' initial poses and
/// velocities and the joints' initial positions and velocities, then places the joints' child
/// bodies again (placeJointChildren). A joint position outside the joint's limits is clamped
/// into them, with a warning in Scene::warnings. On error the scene is left unchanged and the
/// message names the body or joint and the key ("<source>: initial_state.<name>.<key>: <rule>").
/// loadUrdf* call it with SceneOptions::initial_state.
Result<bool> applyInitialState(Scene& scene, const ParamValue& initial_state);

/// Sets the initial pose M_WB0 of every joint's child body from its parent body's and the
/// joint's initial position q0, down the tree (Scene::joints is parent first; joint.h):
///   M_WBc = M_WBp M_PJ exp(−½ q0 S) M_JC,   M_WBp = 1 when the parent is the world,
/// normalised to a unit motor. Child bodies' Ω_B0 are left as they are (zero).
void placeJointChildren(Scene& scene);

}  // namespace scene
}  // namespace cga_rigid_sim
