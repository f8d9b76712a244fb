// Model: what a World simulates and does not change while it steps — the scene's bodies with
// their names, inertias, link frames and initial states, the articulated trees, and the
// configuration. Compiled once from a scene::Scene (compileModel); spawnUrdf and deleteBody
// edit it together with the Data (sim/topology.h), nothing else does.
//
// Two index spaces:
//   body index j   — position in scene.bodies, every body (moving and static);
//   moving index i — position in `moving`, the moving bodies only, in scene order. Every
//                    per-moving-body array of the Model and of the Data is indexed by i.
// The step only touches moving indices; names and body indices serve inputs and reports.
#pragma once

#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "cga_rigid_sim/body/body_state.h"
#include "cga_rigid_sim/body/inertia.h"
#include "cga_rigid_sim/contact/self_collision.h"
#include "cga_rigid_sim/curved/curved_inertia.h"
#include "cga_rigid_sim/result.h"
#include "cga_rigid_sim/scene/scene.h"
#include "cga_rigid_sim/sim/world_config.h"
#include "cga_rigid_sim/tree/articulated_body.h"

namespace cga_rigid_sim {
namespace sim {

/// The constant part of one moving body.
struct MovingBody {
  int body = -1;                ///< its body index j (scene.bodies)
  dynamics::Inertia inertia;    ///< mass and principal moments, frame B
  dynamics::BodyState initial;  ///< the state reset() returns to
  /// Curved space only (config.curvature): its 1-up inertia (doc/curved_space.md#inertia).
  std::optional<dynamics::CurvedInertia> curved_inertia;
};

/// An articulated tree (doc/articulated.md): its dynamics model and where its bodies are. Every
/// link body of a tree is also a moving body (its state is written by the tree stage, so
/// reports, tf, wrenches and impulses address it like any body); the tree's base is a floating
/// root (a moving body) or the world (fixed base).
struct TreeModel {
  std::string name;  ///< the root body's name (floating) or the first joint's parent link
  dynamics::ArticulatedBody body;
  int base_moving = -1;          ///< moving index of the floating root; −1 for a fixed base
  std::vector<int> link_moving;  ///< per joint k: moving index of its child body
  std::vector<int> scene_joint;  ///< per joint k: index in scene.joints
  dynamics::TreeState initial;   ///< the state reset() returns to
  /// Moving index of tree body b (0: the base; −1 for a fixed base).
  int movingOf(int b) const { return b == 0 ? base_moving : link_moving[b - 1]; }
};

/// A robot spawned at run time (World::spawnUrdf with a robot_namespace or joints,
/// doc/node.md#spawning-robots): its bodies, joints and trees, each a contiguous range of the
/// Model's (a robot is appended at the end; deleting anything before it shifts its ranges).
struct RobotModel {
  std::string name;        ///< the robot's name (World::deleteBody removes it whole by it)
  std::string name_space;  ///< prefixed to its links and joints ("r1" → "r1/link1"), or empty
  int first_body = 0, body_count = 0;      ///< body indices j
  int first_moving = 0, moving_count = 0;  ///< moving indices i
  int first_joint = 0, joint_count = 0;    ///< scene.joints indices
  int first_tree = 0, tree_count = 0;      ///< trees indices
};

struct Model {
  WorldConfig config;
  /// Set when config.curvature is (sim/curved_bodies.h).
  std::optional<dynamics::CurvedSpace> curved_space;
  double lambda = 1.0;  ///< CGA length scale, m (the scene's)
  scene::Scene scene;   ///< every body: names, links (M_BL), static poses, initial states

  /// Per body j: its moving index i, or −1 for a static body.
  std::vector<int> moving_of_body;
  /// Per moving body i.
  std::vector<MovingBody> moving;

  /// Articulated trees, and per moving body i its tree and body index in it (−1: a free body).
  std::vector<TreeModel> trees;
  std::vector<int> tree_of_moving;
  std::vector<int> tree_body_of_moving;
  /// Joint name → (tree, joint index in the tree).
  std::map<std::string, std::pair<int, int>> joint_by_name;
  /// Which pairs of one robot's bodies collide (decided when the World is made).
  SelfCollision self_collision;

  /// The robots spawned at run time, in the order they were spawned.
  std::vector<RobotModel> robots;

  /// Name look-ups (inputs and reports; never used by the step).
  std::map<std::string, int> body_by_name;                // body name → j
  std::map<std::string, std::pair<int, int>> link_owner;  // link → (j, link index in the body)

  /// Bumped whenever the set of bodies changes (spawn, delete).
  std::uint64_t topology_version = 0;

  /// The body index of a body given by its name or, failing that, by any of its links; −1.
  int resolveBody(const std::string& name) const;
  /// The body index of a body given by its name only; −1.
  int findBody(const std::string& name) const;
  /// The index in `robots` of the robot called `name`; −1.
  int findRobot(const std::string& name) const;
  /// The index in `robots` of the spawned robot body j belongs to; −1.
  int robotOfBody(int j) const;
  /// The scene body of moving body i.
  const scene::BodyModel& bodyOf(int i) const { return scene.bodies[moving[i].body]; }
};

/// Checks the configuration and the scene and compiles the Model: refuses dt ≤ 0 or not
/// finite, limits not finite and > 0, an empty world frame, an unknown integrator, λ ≤ 0,
/// gravity not finite, and a scene that is not consistent (a body without name or links,
/// duplicate body or link names, a link named like the world frame, a moving body without
/// inertia, an initial state that is not finite). Errors have input "config" or "scene".
Result<Model> compileModel(scene::Scene scene, const WorldConfig& config);

/// Adds scene body `body` (already checked) at the end: body index, moving index, names.
/// Returns its body index. Used by compileModel and by spawning (sim/topology.h).
int appendBody(Model& model, scene::BodyModel body);

}  // namespace sim
}  // namespace cga_rigid_sim
