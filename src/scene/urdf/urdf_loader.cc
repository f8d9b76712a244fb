// URDF → Scene (doc/urdf.md): the loader's pipeline (Loader::load), its cross-check with
// urdfdom, and the entry points loadUrdfFile and loadUrdfString.
//
// Pipeline: (1) our own XML pass (urdf_xml*.cc: structure, numbers, collisions and their contact
// parameters, extension elements, tree), (2) urdfdom parses the model, (3) each link's collision
// meshes are read and its mass properties found in its own frame, from <inertial> or from
// collision geometry, validated per link (urdf_link_mass.cc), (4) bodies: links joined by fixed
// joints merge into one body (composite mass, centre of mass, parallel-axis inertia, the links'
// collision shapes placed in B), floating joints start free bodies, links fixed to the world
// frame form static bodies, revolute, continuous and prismatic joints start moving bodies and
// become Scene::joints (parent first) (urdf_bodies.cc, urdf_joints.cc; mimics: urdf_mimic.cc;
// tf names: urdf_tf_frames.cc), (5) the joints' default initial positions (0, clamped into the
// limits) and the child bodies placed by them, then the initial-state dictionary
// (initial_state.cc). Any error returns before a Scene exists: never a partial scene.
//
// Initial-state dictionary (SceneOptions::initial_state; ROS parameter ~initial_state; full
// text in doc/initial_state.md). A map from body name (= the body's root link name) to a map of
// optional keys:
//   position:              [x, y, z]      root link origin, world frame, m
//   orientation:           [x, y, z, w]   root link attitude, unit quaternion (normalised if
//                                         nearly unit, refused otherwise: rotation_rule.h)
//   rpy:                   [r, p, y]      the same as fixed-axis roll, pitch, yaw (rad);
//                                         give orientation or rpy, not both
//   linear_velocity:       [vx, vy, vz]   of the centre of mass, world axes, m/s
//   angular_velocity:      [wx, wy, wz]   world axes, rad/s
//   linear_velocity_body:  [vx, vy, vz]   of the centre of mass, root link axes, m/s
//   angular_velocity_body: [wx, wy, wz]   root link axes, rad/s
// (a velocity and its _body variant exclude each other). Keys left out keep the URDF pose and
// zero velocity. A joint's name (revolute, continuous, prismatic) maps to
//   position: q    rad or m, clamped into the joint's limits with a warning
//   velocity: q̇    rad/s or m/s
// (either optional); the bodies a joint moves take no entry of their own. Unknown bodies or keys,
// static bodies, wrong types or lengths, non-finite numbers are refused with a message naming the
// body and the key. Example (YAML, as in config/tennis_racket.yaml):
//   initial_state:
//     racket_handle:
//       position: [0.0, 0.0, 1.5]
//       rpy: [0.0, 0.0, 0.0]
//       angular_velocity_body: [0.01, 10.0, 0.01]
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"

#include <urdf_parser/urdf_parser.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/scene/initial_state.h"
#include "scene/urdf/urdf_loading.h"

namespace cga_rigid_sim {
namespace scene {
namespace {

// The text-size bound's message (kMaxUrdfBytes).
std::string textTooLarge(std::uintmax_t bytes) {
  return "the robot description is " + std::to_string(bytes) + " bytes long; the loader reads " +
         "at most " + std::to_string(kMaxUrdfBytes) + " bytes (kMaxUrdfBytes, 128 MiB; " +
         "doc/urdf.md#bounds)";
}

}  // namespace

namespace detail {

std::optional<Error> Loader::checkOptions() const {
  if (!std::isfinite(options_.lambda) || !(options_.lambda > 0))
    return fail(0, "SceneOptions::lambda (the CGA length scale) must be finite and > 0 (got " +
                       formatNumber(options_.lambda, kDigits) + ")");
  if (!options_.gravity_W.allFinite()) return fail(0, "SceneOptions::gravity_W must be finite");
  if (options_.world_frame.empty()) return fail(0, "SceneOptions::world_frame must not be empty");
  return std::nullopt;
}

// urdfdom keeps a link whose <inertial> it cannot read, with mass 0, and only says so on the
// console. Our XML pass uses the same number syntax, so the two readings must agree; if they
// ever do not, refuse rather than simulate a different body.
std::optional<Error> Loader::crossCheck(const urdf::ModelInterface& model) const {
  if (model.links_.size() != xml_.links.size())
    return fail(0, "urdfdom read " + std::to_string(model.links_.size()) + " links, the loader " +
                       std::to_string(xml_.links.size()) + "; refusing an ambiguous file");
  for (const auto& [name, link] : model.links_) {
    const auto it = xml_.links.find(name);
    if (it == xml_.links.end())
      return fail(0, "urdfdom read a link " + inQuotes(name) + " the loader did not find");
    const bool has = static_cast<bool>(link->inertial);
    if (has != it->second.has_inertial || (has && link->inertial->mass != it->second.mass))
      return fail(it->second.line, "link " + inQuotes(name) +
                                       ": urdfdom could not read its <inertial> (see its "
                                       "console message); refusing rather than guessing");
    // The collision shapes: the same number, in the same order, of the same kinds.
    const auto& ours = it->second.collisions;
    bool same = link->collision_array.size() == ours.size();
    for (std::size_t k = 0; same && k < ours.size(); ++k) {
      const urdf::GeometrySharedPtr& g = link->collision_array[k]->geometry;
      using Kind = CollisionShape::Kind;
      const int urdfdom_type = g ? g->type : -1;
      const int our_type = ours[k].shape.kind == Kind::kBox        ? urdf::Geometry::BOX
                           : ours[k].shape.kind == Kind::kSphere   ? urdf::Geometry::SPHERE
                           : ours[k].shape.kind == Kind::kCylinder ? urdf::Geometry::CYLINDER
                                                                   : urdf::Geometry::MESH;
      same = urdfdom_type == our_type;
    }
    if (!same)
      return fail(it->second.line, "link " + inQuotes(name) +
                                       ": urdfdom read its <collision> elements differently "
                                       "from the loader; refusing rather than guessing");
  }
  // The joints: the same names and, for the articulated ones, the same types.
  if (model.joints_.size() != xml_.joints.size())
    return fail(0, "urdfdom read " + std::to_string(model.joints_.size()) + " joints, the loader " +
                       std::to_string(xml_.joints.size()) + "; refusing an ambiguous file");
  for (const auto& [name, joint] : model.joints_) {
    const auto it = xml_.joints.find(name);
    if (it == xml_.joints.end())
      return fail(0, "urdfdom read a joint " + inQuotes(name) + " the loader did not find");
    const std::optional<JointType>& ours = it->second.type;
    const bool same = joint->type == urdf::Joint::REVOLUTE     ? ours == JointType::kRevolute
                      : joint->type == urdf::Joint::CONTINUOUS ? ours == JointType::kContinuous
                      : joint->type == urdf::Joint::PRISMATIC  ? ours == JointType::kPrismatic
                                                               : !ours.has_value();
    if (!same)
      return fail(it->second.line, "joint " + inQuotes(name) +
                                       ": urdfdom read its type differently from the loader; "
                                       "refusing rather than guessing");
  }
  return std::nullopt;
}
Result<Scene> Loader::load(const std::string& xml) {
  if (auto err = checkOptions()) return *err;
  if (xml.size() > kMaxUrdfBytes) return fail(0, textTooLarge(xml.size()));
  auto checked = detail::readUrdfXml(xml, source_, options_.world_frame, options_.plugin_namespace);
  if (!checked) return Error{checked.error()};
  xml_ = std::move(*checked);

  urdf::ModelInterfaceSharedPtr model;
  try {
    model = urdf::parseURDF(xml);
  } catch (const std::exception& e) {
    return fail(0, std::string("urdfdom refused the robot description: ") + e.what());
  }
  if (!model || !model->getRoot())
    return fail(0,
                "urdfdom refused the robot description (its reason is printed on the "
                "console by console_bridge); the loader's own checks of the XML, names, "
                "joints and inertials passed, so look at <visual>, <material> and the other "
                "elements urdfdom reads");
  if (auto err = crossCheck(*model)) return *err;
  model_ = model.get();

  // (3) every link's mass properties in its own frame, in document order (so an error names
  // the first link and mesh the user wrote that fails).
  const urdf::LinkConstSharedPtr root = model->getRoot();
  const bool rooted_in_world = tfFrame(root->name) == options_.world_frame;
  std::vector<std::pair<const std::string*, const urdf::LinkSharedPtr*>> in_order;
  for (const auto& entry : model->links_) in_order.emplace_back(&entry.first, &entry.second);
  std::sort(in_order.begin(), in_order.end(), [&](const auto& a, const auto& b) {
    return xml_.links.at(*a.first).order < xml_.links.at(*b.first).order;
  });
  for (const auto& [name_ptr, link_ptr] : in_order) {
    const std::string& name = *name_ptr;
    const urdf::LinkSharedPtr& link = *link_ptr;
    detail::LinkXml& lx = xml_.links.at(name);
    if (rooted_in_world && name == options_.world_frame) {
      if (lx.has_inertial || lx.has_mass_from_geometry)
        warnings_.push_back(source_ + ":" + std::to_string(lx.line) + ": link " + inQuotes(name) +
                            " is the world frame: its mass is ignored");
      if (!lx.collisions.empty())
        warnings_.push_back(source_ + ":" + std::to_string(lx.line) + ": link " + inQuotes(name) +
                            " is the world frame: its collisions are ignored (to make an "
                            "obstacle, fix a link to it with a fixed joint)");
      continue;
    }
    if (auto err = loadCollisionMeshes(name, &lx.collisions)) return *err;
    Result<LinkMass> lm = lx.has_mass_from_geometry
                              ? linkMassFromGeometry(name, lx.mass_from_geometry, lx.collisions)
                          : link->inertial ? linkMassFromInertial(*link)
                                           : LinkMass{};
    if (!lm) return Error{lm.error()};
    masses_.emplace(name, *lm);
  }

  findCarried();

  // (4) bodies, and the joints that start them.
  std::vector<BodyRoot> roots;
  if (rooted_in_world) {
    for (const auto& j : childJoints(*root)) {
      const urdf::Link* child = model->getLink(j->child_link_name).get();
      const Eigen::Isometry3d X_WJ = toIsometry(j->parent_to_joint_origin_transform);
      if (weldsMassless(*j))  // nothing with mass moves: a static body where the joint rests
        roots.push_back({child, X_WJ * weldedMotion(*j), true});
      else if (xml_.joints.at(j->name)
                   .type)  // revolute, continuous, prismatic: hinged to the world
        roots.push_back({child, X_WJ, false, j.get(), -1, X_WJ});
      else
        roots.push_back({child, X_WJ, j->type == urdf::Joint::FIXED});
    }
  } else {
    roots.push_back({root.get(), Eigen::Isometry3d::Identity(), false});
  }
  Scene scene;
  scene.source = source_;
  scene.robot_name = model->getName();
  scene.lambda = options_.lambda;
  scene.gravity_W = options_.gravity_W;
  for (std::size_t k = 0; k < roots.size(); ++k) {
    const BodyRoot r = roots[k];  // copy: buildBody may grow `roots`
    auto body = buildBody(r, static_cast<int>(k), &roots);
    if (!body) return Error{body.error()};
    if (r.joint) scene.joints.push_back(jointModel(r, static_cast<int>(k), *body));
    scene.bodies.push_back(std::move(*body));
  }
  std::vector<int> document_order(scene.bodies.size());
  for (std::size_t k = 0; k < document_order.size(); ++k) document_order[k] = static_cast<int>(k);
  std::stable_sort(document_order.begin(), document_order.end(), [&](int a, int b) {
    return xml_.links.at(scene.bodies[a].name).order < xml_.links.at(scene.bodies[b].name).order;
  });
  orderParentFirst(&scene, document_order);
  if (auto err = resolveMimics(&scene)) return *err;
  if (auto err = nameFramesForTf(&scene)) return *err;

  // (5) the joints' initial positions and the bodies they place, then the initial state.
  setDefaultInitialPositions(&scene);
  placeJointChildren(scene);
  scene.self_collision.gazebo_model = xml_.self_collide_model;
  scene.self_collision.gazebo_links = std::move(xml_.self_collide_links);
  scene.sensors = std::move(xml_.sensors);
  scene.warnings = std::move(xml_.warnings);
  scene.warnings.insert(scene.warnings.end(), warnings_.begin(), warnings_.end());

  auto applied = applyInitialState(scene, options_.initial_state);
  if (!applied) return Error{applied.error()};
  return scene;
}

}  // namespace detail

Result<Scene> loadUrdfFile(const std::string& path, const SceneOptions& options) {
  namespace fs = std::filesystem;
  std::error_code ec;
  if (fs::is_directory(path, ec))
    return Error{"cannot read URDF file '" + path + "': it is a directory"};
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > kMaxUrdfBytes) return Error{path + ": " + textTooLarge(size)};
  std::ifstream file(path, std::ios::binary);
  if (!file) return Error{"cannot read URDF file '" + path + "': " + std::strerror(errno)};
  std::ostringstream text;
  text << file.rdbuf();
  const std::string base_dir = fs::path(path).parent_path().string();
  return detail::Loader(path, base_dir, options).load(text.str());
}

Result<Scene> loadUrdfString(const std::string& xml, const std::string& source,
                             const SceneOptions& options) {
  const std::string base_dir;  // meshes: relative to the current directory
  return detail::Loader(source, base_dir, options).load(xml);
}

}  // namespace scene
}  // namespace cga_rigid_sim
