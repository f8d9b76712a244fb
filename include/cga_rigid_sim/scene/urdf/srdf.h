// SRDF: the collision rules of a semantic robot description (MoveIt's format), read into a
// loaded scene. Of the SRDF only <disable_collisions link1 link2 reason>,
// <disable_default_collisions link> and <enable_collisions link1 link2> concern a simulator;
// groups, end effectors, virtual and passive joints and named states are valid and ignored.
#pragma once

#include <optional>
#include <string>

#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/scene.h"

namespace cga_rigid_sim {
namespace scene {

/// Reads the SRDF text `xml` (named `source` in messages: a file name or
/// "robot_description_semantic") into scene.self_collision. Refuses, naming the source, the line
/// and the rule, and leaving the scene unchanged: malformed XML, a top element that is not
/// <robot>, a rule without its link attributes, a link the scene does not have, a pair of a
/// link with itself.
std::optional<Error> applySrdf(Scene& scene, const std::string& xml, const std::string& source);

}  // namespace scene
}  // namespace cga_rigid_sim
