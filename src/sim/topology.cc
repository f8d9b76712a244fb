#include "sim/topology.h"

#include "cga_rigid_sim/scene/placement.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "sim/input/input_rules.h"
#include "sim/input/wrench_schedule.h"
#include "sim/state_edit.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

// The URDF loaded with the world's λ, gravity, world frame and inertia rule (source
// "spawn_urdf '<name>'").
Result<scene::Scene> loadSpawned(const Model& model, const std::string& name,
                                 const std::string& urdf, const std::string& robot_namespace) {
  scene::SceneOptions options;
  options.plugin_namespace = robot_namespace;  // as Gazebo's spawn service sets robotNamespace
  options.lambda = model.lambda;
  options.gravity_W = model.scene.gravity_W;
  options.world_frame = model.config.world_frame;
  options.triangle_policy = model.config.triangle_policy;
  return scene::loadUrdfString(urdf, "spawn_urdf '" + name + "'", options);
}

// The URDF's single moving body, renamed `name` (body and root link), or the refusal.
// The loader's warnings (e.g. a relaxed inertia) are added to `warnings`.
Result<scene::BodyModel> spawnedBody(const Model& model, const std::string& name,
                                     const scene::Scene& loaded,
                                     std::vector<std::string>& warnings) {
  const std::string source = "spawn_urdf '" + name + "'";
  int moving = 0, fixed = 0;
  for (const auto& b : loaded.bodies) (b.is_static ? fixed : moving) += 1;
  if (moving != 1 || fixed != 0)
    return Error(source, "",
                 "the URDF must hold exactly one body, a moving one (it has " +
                     std::to_string(moving) + " moving and " + std::to_string(fixed) +
                     " static); with a robot_namespace it is spawned as a robot");
  scene::BodyModel body = loaded.bodies.front();
  if (!body.inertia) return Error(source, "", "the body has no inertia");
  // The body and its root link take the new name (body name = root link name).
  body.name = name;
  body.links.front().link = name;
  for (std::size_t li = 0; li < body.links.size(); ++li) {
    const std::string& link = body.links[li].link;
    const auto owner = model.link_owner.find(link);
    if (owner != model.link_owner.end())
      return Error(source, "",
                   "link '" + link + "' already exists in the world (body '" +
                       model.scene.bodies[owner->second.first].name + "')");
    for (std::size_t lj = 0; lj < li; ++lj)
      if (body.links[lj].link == link)
        return Error(
            source, "",
            "link '" + link + "' would appear twice (the root link is renamed '" + name + "')");
    if (link == model.config.world_frame)
      return Error(source, "", "link '" + link + "' has the name of the world frame");
  }
  warnings = loaded.warnings;
  return body;
}

}  // namespace

Result<bool> spawnUrdf(Model& model, Data& data, const std::string& name, const std::string& urdf,
                       const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                       const Eigen::Vector3d& w_W, const SpawnOptions& options) {
  const std::string what = "spawn_urdf";
  if (name.empty()) return Error(what, "name", "must not be empty");
  if (name == model.config.world_frame)
    return Error(what, "name", "'" + name + "' is the name of the world frame");
  if (model.body_by_name.count(name))
    return Error(what, "name", "body '" + name + "' already exists");
  if (model.findRobot(name) >= 0) return Error(what, "name", "robot '" + name + "' already exists");
  if (auto e = checkStateInput(what, pose_root, v_W, w_W)) return *e;
  auto scene = loadSpawned(model, name, urdf, options.robot_namespace);
  if (!scene) return scene.failure();
  // A robot: joints, or a namespace asked for.
  if (!options.robot_namespace.empty() || !scene->joints.empty())
    return spawnRobot(model, data, name, options, std::move(*scene), pose_root, v_W, w_W);
  std::vector<std::string> warnings;
  auto spawned = spawnedBody(model, name, *scene, warnings);
  if (!spawned) return spawned.failure();
  scene::BodyModel body = std::move(spawned.value());
  // The placement is its initial state for reset().
  const dynamics::BodyState s0 =
      scene::placedState(body.links.front().M_BL, pose_root, v_W, w_W, model.lambda);
  body.M_WB0 = s0.M_WB;
  body.omega_B0 = s0.omega_B;

  // Model and Data together; the data first, as it is the only part that can fail (for an
  // unknown integrator, which compileModel refused).
  auto b = makeBodyData(model, s0);
  if (!b) return b.failure();
  appendBody(model, std::move(body));
  data.bodies.push_back(std::move(b.value()));
  data.coasting.push_back(0);
  for (auto& w : warnings) model.scene.warnings.push_back(std::move(w));
  // Its sensors, the root link's under its new name.
  const std::string& root = scene->bodies.front().links.front().link;
  for (scene::SensorModel s : scene->sensors.sensors) {
    for (std::string* link : {&s.link, &s.reference_link, &s.frame_id})
      if (*link == root) *link = name;
    model.scene.sensors.sensors.push_back(std::move(s));
  }
  data.dirty_list.reserve(data.bodies.size());
  ++model.topology_version;
  return true;
}

Result<bool> deleteBody(Model& model, Data& data, const std::string& body) {
  if (const int r = model.findRobot(body); r >= 0) return deleteRobot(model, data, r);
  const int j = model.findBody(body);
  if (j < 0) return Error("delete_body", "body", "unknown body '" + body + "'");
  if (const int r = model.robotOfBody(j); r >= 0)
    return Error("delete_body", "body",
                 "body '" + body + "' belongs to the spawned robot '" + model.robots[r].name +
                     "' (delete the robot whole, by its name)");
  const int i = model.moving_of_body[j];
  // Trees: a link or the root of a tree, or the static body a tree hangs from, stays.
  if (i >= 0 && model.tree_of_moving[i] >= 0)
    return Error("delete_body", "body",
                 "body '" + body + "' belongs to the articulated tree '" +
                     model.trees[model.tree_of_moving[i]].name +
                     "' (deleting parts of a tree is not supported)");
  for (const auto& joint : model.scene.joints)
    if (joint.parent_body == j)
      return Error("delete_body", "body",
                   "body '" + body + "' carries joint '" + joint.name +
                       "' of an articulated tree (deleting it is not supported)");

  // Data: its inputs go with it; moving indices after it shift down by one.
  if (i >= 0) {
    data.queue.removeBody(i);
    removeActiveWrenchesOf(data, i);
    std::size_t out = 0;
    for (int d : data.dirty_list) {
      if (d == i) continue;
      data.dirty_list[out++] = d > i ? d - 1 : d;
    }
    data.dirty_list.resize(out);
    data.bodies.erase(data.bodies.begin() + i);
    data.coasting.erase(data.coasting.begin() + i);
  }
  // Contacts name bodies by index: the next step finds them again.
  data.contacts.clear();

  // Model: its sensors and names out, body indices after j and moving indices after i shift
  // down by one.
  removeSensorsOf(model, j, 1);
  for (const auto& l : model.scene.bodies[j].links) model.link_owner.erase(l.link);
  model.body_by_name.erase(body);
  model.scene.bodies.erase(model.scene.bodies.begin() + j);
  model.moving_of_body.erase(model.moving_of_body.begin() + j);
  model.self_collision.eraseBody(j);
  if (i >= 0) {
    model.moving.erase(model.moving.begin() + i);
    model.tree_of_moving.erase(model.tree_of_moving.begin() + i);
    model.tree_body_of_moving.erase(model.tree_body_of_moving.begin() + i);
    for (auto& t : model.trees) {
      if (t.base_moving > i) --t.base_moving;
      for (auto& m : t.link_moving)
        if (m > i) --m;
    }
  }
  for (auto& joint : model.scene.joints) {
    if (joint.parent_body > j) --joint.parent_body;
    if (joint.child_body > j) --joint.child_body;
  }
  for (auto& m : model.moving_of_body)
    if (i >= 0 && m > i) --m;
  for (auto& m : model.moving)
    if (m.body > j) --m.body;
  for (auto& kv : model.body_by_name)
    if (kv.second > j) --kv.second;
  for (auto& kv : model.link_owner)
    if (kv.second.first > j) --kv.second.first;
  for (auto& r : model.robots) {  // robots spawned after it
    if (r.first_body > j) --r.first_body;
    if (i >= 0 && r.first_moving > i) --r.first_moving;
  }
  ++model.topology_version;
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
