// compileTrees: the scene's joints → Model::trees (doc/articulated.md#trees). Called by
// compileModel once every body has its index.
#include "sim/tree_compile.h"

#include <cmath>
#include <unordered_map>

#include "cga_rigid_sim/math/union_find.h"
#include "cga_rigid_sim/sim/model.h"
#include "cga_rigid_sim/tree/tree_integrator.h"
#include "sim/input/input_rules.h"

namespace cga_rigid_sim {
namespace sim {

namespace {

std::optional<Error> checkJoint(const Model& model, const scene::JointModel& j) {
  const std::string where = "joint '" + j.name + "'";
  const int n = static_cast<int>(model.scene.bodies.size());
  if (j.name.empty()) return Error("scene", "joint", "has no name");
  if (model.joint_by_name.count(j.name)) return Error("scene", where, "name used twice");
  if (j.child_body < 0 || j.child_body >= n || model.moving_of_body[j.child_body] < 0)
    return Error("scene", where, "its child must be a moving body");
  if (j.parent_body >= n || j.parent_body == j.child_body)
    return Error("scene", where, "parent body out of range");
  if (!j.M_PJ.allFinite() || !j.M_JC.allFinite())
    return Error("scene", where, "joint placement not finite");
  if (!j.axis.allFinite() || !(j.axis.norm() > 0))
    return Error("scene", where, "axis must be finite and non-zero");
  const scene::JointLimits& l = j.limits;
  if (std::isnan(l.lower) || std::isnan(l.upper) || l.lower > l.upper)
    return Error("scene", where, "limits: lower must be <= upper");
  if (!(l.effort >= 0) || !(l.velocity >= 0))
    return Error("scene", where, "effort and velocity limits must be >= 0");
  if (!std::isfinite(j.damping) || j.damping < 0 || !std::isfinite(j.friction) || j.friction < 0)
    return Error("scene", where, "damping and friction must be finite and >= 0");
  if (!std::isfinite(j.initial_position) || !std::isfinite(j.initial_velocity))
    return Error("scene", where, "initial position and velocity must be finite");
  return std::nullopt;
}

}  // namespace

std::optional<Error> compileTrees(Model& model) {
  const int moving = static_cast<int>(model.moving.size());
  model.tree_of_moving.assign(moving, -1);
  model.tree_body_of_moving.assign(moving, -1);
  model.trees.clear();
  model.joint_by_name.clear();
  if (model.scene.joints.empty()) return std::nullopt;
  auto integrator = dynamics::makeTreeIntegrator(model.config.integrator);
  if (!integrator) return Error("config", "integrator", integrator.failure().rule);

  // Joints per tree, in scene order (parent first), before the ArticulatedBody is built.
  struct Building {
    std::string name;
    int base_moving = -1;
    std::vector<dynamics::TreeJoint> joints;
    std::vector<int> link_moving, scene_joint;
    std::vector<double> q0, v0;
  };
  std::vector<Building> trees;
  const double lambda = model.lambda;
  // Joints on the ground (the world or a static body) each start a fixed-base tree of their
  // own, except that joints coupled by <mimic> share one (a gripper's fingers on a fixed palm):
  // the sets of joints connected by parenthood and mimic, by union–find over scene joints.
  const int joint_count = static_cast<int>(model.scene.joints.size());
  math::UnionFind sets;
  sets.reset(joint_count);
  std::vector<int> joint_of_child(model.scene.bodies.size(), -1);
  for (int sj = 0; sj < joint_count; ++sj) {
    const int child = model.scene.joints[sj].child_body;
    if (child >= 0 && child < static_cast<int>(joint_of_child.size())) joint_of_child[child] = sj;
  }
  for (int sj = 0; sj < joint_count; ++sj) {
    const scene::JointModel& j = model.scene.joints[sj];
    if (j.parent_body >= 0 && j.parent_body < static_cast<int>(joint_of_child.size()) &&
        joint_of_child[j.parent_body] >= 0)
      sets.join(sj, joint_of_child[j.parent_body]);
    if (j.mimic && j.mimic->leader >= 0 && j.mimic->leader < joint_count)
      sets.join(sj, j.mimic->leader);
  }
  std::unordered_map<int, int> ground_tree;  // a set's fixed-base tree
  for (int sj = 0; sj < joint_count; ++sj) {
    const scene::JointModel& j = model.scene.joints[sj];
    if (auto e = checkJoint(model, j)) return e;
    const int child = model.moving_of_body[j.child_body];
    if (model.tree_of_moving[child] >= 0)
      return Error("scene", "joint '" + j.name + "'", "its child already has a parent joint");
    const int parent_moving = j.parent_body >= 0 ? model.moving_of_body[j.parent_body] : -1;
    dynamics::TreeJoint tj;
    tj.M_PJ = j.M_PJ;
    int tree = -1;
    if (parent_moving < 0) {  // the world or a static body: a fixed-base tree, new or its set's
      if (j.parent_body >= 0) tj.M_PJ = model.scene.bodies[j.parent_body].M_WB0 * j.M_PJ;
      const auto [it, added] = ground_tree.emplace(sets.find(sj), static_cast<int>(trees.size()));
      tree = it->second;
      if (added) trees.push_back({j.parent_link, -1, {}, {}, {}, {}, {}});
      tj.parent = 0;
    } else if (model.tree_of_moving[parent_moving] >= 0) {  // further down a tree
      tree = model.tree_of_moving[parent_moving];
      tj.parent = model.tree_body_of_moving[parent_moving];
    } else {  // a free body with joints: the root of a floating-base tree
      tree = static_cast<int>(trees.size());
      trees.push_back({model.scene.bodies[j.parent_body].name, parent_moving, {}, {}, {}, {}, {}});
      model.tree_of_moving[parent_moving] = tree;
      model.tree_body_of_moving[parent_moving] = 0;
      tj.parent = 0;
    }
    Building& t = trees[tree];
    tj.kind = j.type == scene::JointType::kPrismatic ? dynamics::JointKind::kPrismatic
                                                     : dynamics::JointKind::kRevolute;
    tj.M_JC = j.M_JC;
    tj.axis = j.axis.normalized();
    tj.inertia = model.moving[child].inertia;
    tj.damping = j.damping;
    tj.friction = j.friction;
    if (j.type != scene::JointType::kContinuous) {
      tj.lower = j.limits.lower;
      tj.upper = j.limits.upper;
    }
    tj.effort_limit = j.limits.effort;
    t.joints.push_back(tj);
    t.link_moving.push_back(child);
    t.scene_joint.push_back(sj);
    t.q0.push_back(j.initial_position);
    t.v0.push_back(j.initial_velocity);
    model.tree_of_moving[child] = tree;
    model.tree_body_of_moving[child] = static_cast<int>(t.joints.size());
    model.joint_by_name[j.name] = {tree, static_cast<int>(t.joints.size()) - 1};
  }
  (void)lambda;
  // Mimic joints: the leader's place in the same tree (the loader refuses other cases).
  for (int tree = 0; tree < static_cast<int>(trees.size()); ++tree) {
    Building& t = trees[tree];
    for (std::size_t k = 0; k < t.joints.size(); ++k) {
      const scene::JointModel& j = model.scene.joints[t.scene_joint[k]];
      if (!j.mimic) continue;
      const auto leader = j.mimic->leader >= 0 && j.mimic->leader < joint_count
                              ? model.joint_by_name.find(model.scene.joints[j.mimic->leader].name)
                              : model.joint_by_name.end();
      if (leader == model.joint_by_name.end() || leader->second.first != tree ||
          model.scene.joints[j.mimic->leader].mimic)
        return Error("scene", "joint '" + j.name + "'",
                     "<mimic>: its leader must be an independent joint of the same tree");
      if (!std::isfinite(j.mimic->multiplier) || !std::isfinite(j.mimic->offset))
        return Error("scene", "joint '" + j.name + "'",
                     "<mimic>: multiplier and offset must be finite");
      t.joints[k].mimic = leader->second.second;
      t.joints[k].mimic_multiplier = j.mimic->multiplier;
      t.joints[k].mimic_offset = j.mimic->offset;
    }
  }
  for (Building& t : trees) {
    std::optional<dynamics::Inertia> base;
    if (t.base_moving >= 0) base = model.moving[t.base_moving].inertia;
    TreeModel tm{t.name,        dynamics::ArticulatedBody(base, t.joints, model.lambda),
                 t.base_moving, t.link_moving,
                 t.scene_joint, {}};
    dynamics::TreeState& s = tm.initial;
    if (t.base_moving >= 0) {
      s.M_W0 = model.moving[t.base_moving].initial.M_WB;
      s.omega_0 = model.moving[t.base_moving].initial.omega_B;
    }
    s.q = Eigen::Map<const Eigen::VectorXd>(t.q0.data(), t.q0.size());
    s.v = Eigen::Map<const Eigen::VectorXd>(t.v0.data(), t.v0.size());
    dynamics::applyMimic(tm.body, s);  // (the scene's followers agree; exact to the same rounding)
    // Every link's initial state from the joints (the scene's M_WB0 agrees; Ω from q̇).
    dynamics::TreeKinematics kin;
    dynamics::treeKinematics(tm.body, s, kin);
    for (int b = 1; b < tm.body.bodyCount(); ++b)
      model.moving[tm.link_moving[b - 1]].initial = {kin.M_W[b], kin.omega[b]};
    model.trees.push_back(std::move(tm));
  }
  return std::nullopt;
}

}  // namespace sim
}  // namespace cga_rigid_sim
