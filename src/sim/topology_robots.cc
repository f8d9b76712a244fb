// Spawning and deleting whole robots (topology.h, doc/node.md#spawning-robots): a URDF with
// joints (or any URDF given a namespace) is loaded, its names prefixed, placed, and compiled on
// its own by compileModel and makeData — the path a scene takes — and the result is appended
// at the end of the world's Model and Data, so that every index the world already has stays
// valid and nothing the world already simulates is touched. Deleting removes the ranges again
// and shifts what follows.
#include <algorithm>
#include <limits>
#include <set>

#include "cga_rigid_sim/scene/placement.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "contact/contact_detection.h"
#include "contact/self_collision_rules.h"
#include "sim/controllers/controllers.h"
#include "sim/input/wrench_schedule.h"
#include "sim/state_edit.h"
#include "sim/topology.h"

namespace cga_rigid_sim {
namespace sim {
namespace {

const std::string kInput = "spawn_urdf";

// x in [first, first + count) is gone; past it, it shifts down by count.
bool inRange(int x, int first, int count) { return x >= first && x < first + count; }
void shiftDown(int& x, int first, int count) {
  if (x >= first + count) x -= count;
}

// A ROS graph name to prefix tf frames and topics with: segments of a letter followed by
// letters, digits and '_', joined by single '/' (ros::names::validate's rule for relative
// names; no leading '/' or '~', as tf2 frame ids carry none).
std::optional<Error> checkNamespace(const std::string& ns) {
  bool segment_start = true;
  for (std::size_t k = 0; k < ns.size(); ++k) {
    const char c = ns[k];
    const bool letter = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z');
    const bool ok = c == '/' ? !segment_start && k + 1 < ns.size()
                             : (letter || (!segment_start && ((c >= '0' && c <= '9') || c == '_')));
    if (!ok)
      return Error(kInput, "robot_namespace",
                   "'" + ns +
                       "' is not a valid ROS name: segments start with a letter and hold "
                       "letters, digits and '_', joined by single '/' (none leading or trailing)");
    segment_start = c == '/';
  }
  return std::nullopt;
}

// Every name of the loaded robot prefixed: bodies, links, collision shapes, joints, the
// links its self-collision rules name.
void prefixNames(scene::Scene& robot, const std::string& prefix) {
  if (prefix.empty()) return;
  std::set<std::string> links;  // as written
  for (const scene::BodyModel& b : robot.bodies)
    for (const scene::LinkFrame& l : b.links) links.insert(l.link);
  for (scene::BodyModel& b : robot.bodies) {
    b.name = prefix + b.name;
    for (scene::LinkFrame& l : b.links) l.link = prefix + l.link;
    for (std::string& j : b.merged_joints) j = prefix + j;
    for (scene::CollisionShape& s : b.shapes) s.name = prefix + s.name;
  }
  for (scene::JointModel& j : robot.joints) {
    j.name = prefix + j.name;
    if (j.parent_body >= 0) j.parent_link = prefix + j.parent_link;
    j.child_link = prefix + j.child_link;
    if (j.mimic) j.mimic->written = prefix + j.mimic->written;
  }
  std::map<std::string, bool> gazebo_links;
  for (const auto& [link, value] : robot.self_collision.gazebo_links)
    gazebo_links.emplace(prefix + link, value);
  robot.self_collision.gazebo_links = std::move(gazebo_links);
  // Its sensors and drives: the links and joints they name, and the tf frames they publish in
  // (a link's frame is the prefixed link; the drives' odometry and base frames are the robot's
  // own). Their topics took the namespace when the URDF was read (plugin_namespace).
  for (scene::SensorModel& s : robot.sensors.sensors) {
    s.link = prefix + s.link;
    if (!s.joint.empty()) s.joint = prefix + s.joint;
    if (!s.reference_link.empty() && s.reference_link != "world")
      s.reference_link = prefix + s.reference_link;
    if (links.count(s.frame_id)) s.frame_id = prefix + s.frame_id;
  }
  for (scene::DriveModel& d : robot.sensors.drives) {
    for (auto* joints : {&d.left_joints, &d.right_joints})
      for (std::string& j : *joints) j = prefix + j;
    d.odometry_frame = prefix + d.odometry_frame;
    d.robot_base_frame = prefix + d.robot_base_frame;
  }
}

// The robot moved as a whole so that its root link sits at pose_root: a robot rooted at the
// world frame (a static body, or a joint on the world) has that frame moved there and must not
// move; a free robot has its root body (the URDF's root link's) placed with the velocities and
// the other bodies carried along (a tree's links then follow from its joints, at rest).
std::optional<Error> place(scene::Scene& robot, double lambda, const std::string& world_frame,
                           const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                           const Eigen::Vector3d& w_W) {
  bool rooted = false;
  for (const scene::BodyModel& b : robot.bodies) rooted = rooted || b.is_static;
  for (const scene::JointModel& j : robot.joints) rooted = rooted || j.parent_body < 0;
  cga::Motor T;  // the motion applied to every pose of the loaded robot
  if (rooted) {
    if (!v_W.isZero(0.0) || !w_W.isZero(0.0))
      return Error(
          kInput, v_W.isZero(0.0) ? "angular_velocity" : "linear_velocity",
          "must be zero: the robot is fixed to the world (its root link is '" + world_frame + "')");
    const Eigen::Quaterniond R(pose_root.linear());
    T = cga::Motor::fromPose(R.normalized(), pose_root.translation(), lambda);
  } else {
    scene::BodyModel& root = robot.bodies.front();
    const dynamics::BodyState s0 =
        scene::placedState(root.links.front().M_BL, pose_root, v_W, w_W, lambda);
    T = (s0.M_WB * root.M_WB0.reverse()).normalized();
    root.M_WB0 = s0.M_WB;
    root.omega_B0 = s0.omega_B;
  }
  for (std::size_t k = rooted ? 0 : 1; k < robot.bodies.size(); ++k)
    robot.bodies[k].M_WB0 = (T * robot.bodies[k].M_WB0).normalized();
  for (scene::JointModel& j : robot.joints)
    if (j.parent_body < 0) j.M_PJ = (T * j.M_PJ).normalized();
  return std::nullopt;
}

// A name of the robot that the world already has (a body, link, joint or robot), or none.
std::optional<Error> checkClashes(const Model& model, const Model& part, const std::string& name) {
  const auto taken = [&model](const std::string& n) -> std::string {
    if (model.findRobot(n) >= 0) return "robot '" + n + "'";
    if (model.body_by_name.count(n)) return "body '" + n + "'";
    const auto l = model.link_owner.find(n);
    if (l != model.link_owner.end())
      return "link '" + n + "' (of body '" + model.scene.bodies[l->second.first].name + "')";
    if (n == model.config.world_frame) return "the world frame '" + n + "'";
    return "";
  };
  if (const std::string t = taken(name); !t.empty())
    return Error(kInput, "name", "the world already has " + t);
  for (const auto& [link, owner] : part.link_owner) {
    if (link == name)
      return Error(kInput, "name", "'" + name + "' is the name of one of the robot's links");
    if (const std::string t = taken(link); !t.empty())
      return Error(kInput, "robot_namespace",
                   "the robot's link '" + link + "' clashes: the world already has " + t +
                       " (spawn it under another namespace)");
  }
  for (const auto& [joint, at] : part.joint_by_name)
    if (model.joint_by_name.count(joint))
      return Error(kInput, "robot_namespace",
                   "the robot's joint '" + joint +
                       "' clashes with a joint the world already has (spawn it under another "
                       "namespace)");
  return std::nullopt;
}

// Appends the compiled robot (part, its data) at the end of the world's model and data.
void append(Model& model, Data& data, Model part, Data part_data, RobotModel robot) {
  const int b0 = static_cast<int>(model.scene.bodies.size());
  const int m0 = static_cast<int>(model.moving.size());
  const int j0 = static_cast<int>(model.scene.joints.size());
  const int t0 = static_cast<int>(model.trees.size());
  for (scene::BodyModel& b : part.scene.bodies) appendBody(model, std::move(b));
  // appendBody took the moving bodies' initial states from the scene; a tree's links have
  // theirs from the joints (compileTrees).
  for (std::size_t i = 0; i < part.moving.size(); ++i)
    model.moving[m0 + i].initial = part.moving[i].initial;
  for (scene::JointModel j : part.scene.joints) {
    if (j.parent_body >= 0) j.parent_body += b0;
    j.child_body += b0;
    if (j.mimic) j.mimic->leader += j0;
    model.scene.joints.push_back(std::move(j));
  }
  for (std::size_t i = 0; i < part.moving.size(); ++i) {
    model.tree_of_moving[m0 + i] = part.tree_of_moving[i] >= 0 ? part.tree_of_moving[i] + t0 : -1;
    model.tree_body_of_moving[m0 + i] = part.tree_body_of_moving[i];
  }
  for (TreeModel t : part.trees) {
    if (t.base_moving >= 0) t.base_moving += m0;
    for (int& m : t.link_moving) m += m0;
    for (int& sj : t.scene_joint) sj += j0;
    model.trees.push_back(std::move(t));
  }
  for (const auto& [joint, at] : part.joint_by_name)
    model.joint_by_name[joint] = {at.first + t0, at.second};
  model.self_collision.appendRobot(part.self_collision, b0);
  for (std::string& w : part.scene.warnings) model.scene.warnings.push_back(std::move(w));
  for (scene::SensorModel& s : part.scene.sensors.sensors)
    model.scene.sensors.sensors.push_back(std::move(s));
  for (scene::DriveModel& d : part.scene.sensors.drives)
    model.scene.sensors.drives.push_back(std::move(d));

  for (MovingBodyData& b : part_data.bodies) data.bodies.push_back(std::move(b));
  data.coasting.resize(data.bodies.size(), 0);
  data.dirty_list.reserve(data.bodies.size());
  for (TreeData& t : part_data.trees) data.trees.push_back(std::move(t));

  robot.first_body = b0;
  robot.body_count = static_cast<int>(part.scene.bodies.size());
  robot.first_moving = m0;
  robot.moving_count = static_cast<int>(part.moving.size());
  robot.first_joint = j0;
  robot.joint_count = static_cast<int>(part.scene.joints.size());
  robot.first_tree = t0;
  robot.tree_count = static_cast<int>(part.trees.size());
  model.robots.push_back(std::move(robot));
}

}  // namespace

void removeSensorsOf(Model& model, int b0, int nb) {
  const auto gone = [&](const std::string& link) {
    const auto owner = model.link_owner.find(link);
    return owner != model.link_owner.end() && inRange(owner->second.first, b0, nb);
  };
  auto& sensors = model.scene.sensors.sensors;
  sensors.erase(std::remove_if(sensors.begin(), sensors.end(),
                               [&](const scene::SensorModel& s) { return gone(s.link); }),
                sensors.end());
  auto& drives = model.scene.sensors.drives;
  drives.erase(std::remove_if(drives.begin(), drives.end(),
                              [&](const scene::DriveModel& d) {
                                const int j = model.scene.findJoint(d.left_joints.front());
                                return j < 0 || gone(model.scene.joints[j].child_link);
                              }),
               drives.end());
}

Result<bool> spawnRobot(Model& model, Data& data, const std::string& name,
                        const SpawnOptions& options, scene::Scene robot,
                        const Eigen::Isometry3d& pose_root, const Eigen::Vector3d& v_W,
                        const Eigen::Vector3d& w_W) {
  if (auto e = checkNamespace(options.robot_namespace)) return *e;
  const std::string prefix = options.robot_namespace.empty() ? "" : options.robot_namespace + "/";
  prefixNames(robot, prefix);
  if (auto e = place(robot, model.lambda, model.config.world_frame, pose_root, v_W, w_W)) return *e;
  // The robot compiled on its own, by the path a scene takes: its bodies, trees, initial
  // states, and self-collision table (the robot's own rules under the world's mode).
  auto part = compileModel(std::move(robot), model.config);
  if (!part) return Error(kInput + " '" + name + "'", "", part.failure().message());
  if (auto e = checkClashes(model, *part, name)) return *e;
  auto part_data = makeData(*part);
  if (!part_data) return part_data.failure();
  {
    auto cache = makeCollisionCache();
    leaveOutInitialOverlaps(*part, *part_data, *cache);
  }
  const std::uint64_t version = model.topology_version;
  const std::size_t warnings = model.scene.warnings.size();
  RobotModel r;
  r.name = name;
  r.name_space = options.robot_namespace;
  append(model, data, std::move(*part), std::move(*part_data), std::move(r));
  const int index = static_cast<int>(model.robots.size()) - 1;
  ++model.topology_version;

  // Its controllers, under its namespace; a refusal takes the robot out again, leaving the
  // world as it was (the robot was appended at the end, so removing it restores every index).
  if (!options.controller_names.empty() || !options.controllers.isNone()) {
    auto loaded = loadRobotControllers(model, data, index, options.controllers,
                                       options.controller_names, options.pid_gains);
    if (!loaded) {
      // (Deleting clears the last step's contacts; none of them involves the robot.)
      std::vector<Contact> contacts = data.contacts;
      deleteRobot(model, data, index);
      data.contacts = std::move(contacts);
      model.topology_version = version;
      model.scene.warnings.resize(warnings);
      return Error(kInput, "controllers", loaded.failure().message());
    }
    for (const std::string& w : *loaded)
      model.scene.warnings.push_back("spawn_urdf '" + name + "': " + w);
  }
  return true;
}

Result<bool> deleteRobot(Model& model, Data& data, int robot) {
  const RobotModel r = model.robots[robot];
  const int b0 = r.first_body, nb = r.body_count;
  const int m0 = r.first_moving, nm = r.moving_count;
  const int j0 = r.first_joint, nj = r.joint_count;
  const int t0 = r.first_tree, nt = r.tree_count;

  // Data: the bodies' and trees' inputs go with them (last first, so that each removal's
  // renumbering leaves the ones still to remove where they were), then their data.
  for (int i = m0 + nm - 1; i >= m0; --i) {
    data.queue.removeBody(i);
    removeActiveWrenchesOf(data, i);
  }
  for (int t = t0 + nt - 1; t >= t0; --t) data.queue.removeTree(t);
  std::size_t out = 0;
  for (int d : data.dirty_list) {
    if (inRange(d, m0, nm)) continue;
    shiftDown(d, m0, nm);
    data.dirty_list[out++] = d;
  }
  data.dirty_list.resize(out);
  data.bodies.erase(data.bodies.begin() + m0, data.bodies.begin() + m0 + nm);
  data.coasting.erase(data.coasting.begin() + m0, data.coasting.begin() + m0 + nm);
  data.trees.erase(data.trees.begin() + t0, data.trees.begin() + t0 + nt);
  removeControllersOfTrees(data, t0, nt);
  // Reports of past events that name its trees or bodies say "its body" from now on.
  constexpr int kGone = std::numeric_limits<int>::max();
  TreeFaults& f = data.tree_faults;
  if (inRange(f.tree, t0, nt)) f.tree = kGone;
  shiftDown(f.tree, t0, nt);
  QueuedInput& refused = data.start_refusals.input;
  if (inRange(refused.tree, t0, nt)) refused.tree = kGone;
  if (inRange(refused.body, m0, nm)) refused.body = kGone;
  shiftDown(refused.tree, t0, nt);
  shiftDown(refused.body, m0, nm);
  data.contacts.clear();  // they name bodies by index: the next step finds them again

  // Model: its sensors and drives out (they name its links and joints), names out, then the
  // ranges, then every index past them shifts down.
  removeSensorsOf(model, b0, nb);
  for (int j = b0; j < b0 + nb; ++j) {
    for (const auto& l : model.scene.bodies[j].links) model.link_owner.erase(l.link);
    model.body_by_name.erase(model.scene.bodies[j].name);
  }
  for (int sj = j0; sj < j0 + nj; ++sj) model.joint_by_name.erase(model.scene.joints[sj].name);
  model.scene.bodies.erase(model.scene.bodies.begin() + b0, model.scene.bodies.begin() + b0 + nb);
  model.moving_of_body.erase(model.moving_of_body.begin() + b0,
                             model.moving_of_body.begin() + b0 + nb);
  model.self_collision.eraseBodies(b0, nb);
  model.moving.erase(model.moving.begin() + m0, model.moving.begin() + m0 + nm);
  model.tree_of_moving.erase(model.tree_of_moving.begin() + m0,
                             model.tree_of_moving.begin() + m0 + nm);
  model.tree_body_of_moving.erase(model.tree_body_of_moving.begin() + m0,
                                  model.tree_body_of_moving.begin() + m0 + nm);
  model.scene.joints.erase(model.scene.joints.begin() + j0, model.scene.joints.begin() + j0 + nj);
  model.trees.erase(model.trees.begin() + t0, model.trees.begin() + t0 + nt);

  for (auto& m : model.moving_of_body) shiftDown(m, m0, nm);
  for (auto& m : model.moving) shiftDown(m.body, b0, nb);
  for (auto& t : model.tree_of_moving) shiftDown(t, t0, nt);
  for (auto& t : model.trees) {
    shiftDown(t.base_moving, m0, nm);
    for (int& m : t.link_moving) shiftDown(m, m0, nm);
    for (int& sj : t.scene_joint) shiftDown(sj, j0, nj);
  }
  for (auto& joint : model.scene.joints) {
    shiftDown(joint.parent_body, b0, nb);
    shiftDown(joint.child_body, b0, nb);
    if (joint.mimic) shiftDown(joint.mimic->leader, j0, nj);
  }
  for (auto& kv : model.joint_by_name) shiftDown(kv.second.first, t0, nt);
  for (auto& kv : model.body_by_name) shiftDown(kv.second, b0, nb);
  for (auto& kv : model.link_owner) shiftDown(kv.second.first, b0, nb);
  model.robots.erase(model.robots.begin() + robot);
  for (RobotModel& other : model.robots) {
    shiftDown(other.first_body, b0, nb);
    shiftDown(other.first_moving, m0, nm);
    shiftDown(other.first_joint, j0, nj);
    shiftDown(other.first_tree, t0, nt);
  }
  ++model.topology_version;
  return true;
}

}  // namespace sim
}  // namespace cga_rigid_sim
