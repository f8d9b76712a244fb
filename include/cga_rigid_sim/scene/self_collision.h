// Self-collision rules: which pairs of one robot's links may touch each other
// (doc/contacts.md#self-collision). A scene brings its own rules — Gazebo's <self_collide> in the
// URDF, an SRDF's <disable_collisions> — and the World combines them with a mode (the node's
// ~self_collision) once, when it is created, into the list of pairs contact detection tests.
//
// A "robot" here is a set of bodies joined by joints (with the static body a fixed-base tree
// hangs on). Links of different robots, free bodies and obstacles always collide; the rules
// below only ever remove pairs of links of one robot.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <vector>

namespace cga_rigid_sim {
namespace scene {

/// How the pairs of one robot's links are chosen (the node's ~self_collision):
///   kAuto  every pair except a link and its parent, pairs that already overlap at the initial
///          configuration (the rule of MoveIt's setup assistant), pairs an SRDF disables, and
///          pairs Gazebo would not collide where the URDF carries <self_collide>;
///   kAll   every pair except a link and its parent;
///   kNone  no pair: a robot never touches itself.
enum class SelfCollisionMode { kAuto, kAll, kNone };
const char* toString(SelfCollisionMode mode);
/// "auto", "all", "none"; nothing for any other text.
std::optional<SelfCollisionMode> parseSelfCollisionMode(const std::string& text);

/// Two links named in a rule, and where the rule was written.
struct LinkPair {
  std::string link1, link2;
  std::string reason;  ///< the SRDF's reason attribute, if any
  int line = 0;
};

/// The rules a scene carries (Scene::self_collision).
struct SelfCollisionRules {
  /// Gazebo's <gazebo><self_collide> (the whole model) and <gazebo reference="link">
  /// <self_collide> (one link), unset where the URDF does not say. In Gazebo two links of one
  /// model collide when either link's value (the model's where the link has none; false where
  /// neither says) is true, and never a link and its parent.
  std::optional<bool> gazebo_model;
  std::map<std::string, bool> gazebo_links;
  /// An SRDF's rules (srdf.h); srdf_source is empty when none was given.
  std::string srdf_source;
  std::vector<LinkPair> srdf_disabled;             ///< <disable_collisions link1 link2>
  std::vector<std::string> srdf_disabled_links;    ///< <disable_default_collisions link>
  std::vector<LinkPair> srdf_enabled;              ///< <enable_collisions link1 link2>

  bool hasGazebo() const { return gazebo_model.has_value() || !gazebo_links.empty(); }
  bool hasSrdf() const { return !srdf_source.empty(); }
};

}  // namespace scene
}  // namespace cga_rigid_sim
