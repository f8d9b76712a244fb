// URDF → Scene (doc/urdf.md).
//
// Pipeline: (1) our own XML pass (urdf_xml.cc: structure, numbers, collisions and their contact
// parameters, extension elements, tree), (2) urdfdom parses the model, (3) each link's collision
// meshes are read and its mass properties found in its own frame, from <inertial> or from
// collision geometry, validated per link, (4) bodies: links joined by fixed joints merge into
// one body (composite mass, centre of mass, parallel-axis inertia, the links' collision shapes
// placed in B), floating joints start free bodies, links fixed to the world frame form static
// bodies, revolute, continuous and prismatic joints start moving bodies and become
// Scene::joints (parent first), (5) the joints' default initial positions (0, clamped into the
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

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <exception>
#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <sstream>
#include <unordered_map>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/scene/initial_state.h"
#include "cga_rigid_sim/scene/mass_properties.h"
#include "cga_rigid_sim/scene/mesh.h"
#include "scene/urdf/urdf_xml.h"

namespace cga_rigid_sim {
namespace scene {

namespace {

// The inertia repairs (doc/urdf.md#inertias-from-cad) are made by default, with a warning; the
// strict option refuses instead, and its messages say how to accept the repair.
const char* const kRelaxHint =
    " (refused because ~relax_inertia is false, SceneOptions::triangle_policy = kRefuse; by "
    "default the loader repairs this with a warning)";
const char* const kRepairedNote = " (~relax_inertia:=false refuses this instead)";
// A moving body with no mass of its own that carries massive links through further joints
// (the dummy link between two joints of a universal joint) gets this fraction of what it
// carries: mass and moments negligible in the dynamics, and every body of the tree physical.
constexpr double kPlaceholderFraction = 1e-6;

// A link's tf frame name: its name without leading '/' (tf2 refuses frame ids that start with
// one; ROS 1 descriptions written for tf (1) often have them).
std::string tfFrame(const std::string& link) {
  const std::size_t start = link.find_first_not_of('/');
  return start == std::string::npos ? std::string() : link.substr(start);
}

// Numbers in messages: 10 significant digits show a triangle inequality broken in the 8th.
constexpr int kDigits = 10;

Eigen::Isometry3d toIsometry(const urdf::Pose& p) {
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  X.linear() = Eigen::Quaterniond(p.rotation.w, p.rotation.x, p.rotation.y, p.rotation.z)
                   .normalized()
                   .toRotationMatrix();
  X.translation() << p.position.x, p.position.y, p.position.z;
  return X;
}

// Where a joint welded for want of mass stays: its default initial position (0 clamped into
// its limits).
double weldedPosition(const detail::JointXml& j) {
  const JointLimits& l = j.limits;
  return l.has_position ? std::clamp(0.0, l.lower, l.upper) : 0.0;
}

// Everything the loader needs in one place while it runs.
class Loader {
 public:
  Loader(const std::string& source, const std::string& base_dir, const SceneOptions& options)
      : source_(source), base_dir_(base_dir), options_(options) {}

  Result<Scene> load(const std::string& xml);

 private:
  struct LinkMass {
    bool massive = false;
    MassProperties in_link;  // link frame
  };
  // The root link of a body to build. A body started by a revolute, continuous or prismatic
  // joint also knows that joint, its parent body and the joint frame J in the parent's B.
  struct BodyRoot {
    const urdf::Link* link = nullptr;
    /// The root link's pose with every joint above it at 0 (the floating bodies below it start
    /// there).
    Eigen::Isometry3d X_WR = Eigen::Isometry3d::Identity();
    bool is_static = false;
    const urdf::Joint* joint = nullptr;  ///< the articulated joint that starts the body
    int parent = -1;                     ///< the parent's index in the roots (−1: the world)
    Eigen::Isometry3d X_PJ = Eigen::Isometry3d::Identity();  ///< J in B_p (in W for the world)
  };

  Error fail(int line, const std::string& what) const {
    return Error{source_ + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what};
  }
  int linkLine(const std::string& link) const {
    const auto it = xml_.links.find(link);
    return it == xml_.links.end() ? 0 : it->second.line;
  }
  std::optional<Error> checkOptions() const;
  std::optional<Error> crossCheck(const urdf::ModelInterface& model) const;
  Result<LinkMass> linkMassFromInertial(const urdf::Link& link);
  std::optional<Error> loadCollisionMeshes(const std::string& link,
                                           std::vector<detail::CollisionGeometry>* collisions);
  Result<LinkMass> linkMassFromGeometry(
      const std::string& link, const detail::MassFromGeometry& spec,
      const std::vector<detail::CollisionGeometry>& collisions) const;
  Result<BodyModel> buildBody(const BodyRoot& root, int index, std::vector<BodyRoot>* more_roots);
  JointModel jointModel(const BodyRoot& root, int index, const BodyModel& child) const;
  static void orderParentFirst(Scene* scene, const std::vector<int>& document_order);
  std::optional<Error> resolveMimics(Scene* scene) const;
  std::optional<Error> nameFramesForTf(Scene* scene);
  void setDefaultInitialPositions(Scene* scene);
  std::vector<urdf::JointSharedPtr> childJoints(const urdf::Link& link) const;
  bool weldsMassless(const urdf::Joint& j);
  Eigen::Isometry3d weldedMotion(const urdf::Joint& j) const;

  const std::string& source_;
  const std::string& base_dir_;
  const SceneOptions& options_;
  detail::UrdfXml xml_;
  const urdf::ModelInterface* model_ = nullptr;
  std::unordered_map<std::string, LinkMass> masses_;
  // Per link: the mass (kg) and the largest principal moment (kg m²) of it and every link below
  // it through fixed and moving joints (not floating ones: they start other free bodies).
  struct Carried {
    double mass = 0.0, moment = 0.0;
  };
  std::unordered_map<std::string, Carried> carried_;
  void findCarried();
  bool strict() const { return options_.triangle_policy == dynamics::TrianglePolicy::kRefuse; }
  std::string warnAt(int line) const { return source_ + ":" + std::to_string(line) + ": "; }
  std::map<std::string, TriangleMesh> meshes_;  // by resolved path: each file read once
  std::vector<std::string> warnings_;
};

// The text-size bound's message (kMaxUrdfBytes).
std::string textTooLarge(std::uintmax_t bytes) {
  return "the robot description is " + std::to_string(bytes) + " bytes long; the loader reads " +
         "at most " + std::to_string(kMaxUrdfBytes) + " bytes (kMaxUrdfBytes, 128 MiB; " +
         "doc/urdf.md#bounds)";
}

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

// One link's <inertial>: mass, centre of mass and inertia in the link frame. URDF gives the
// tensor in the inertial frame I (origin xyz at the centre of mass, axes turned by rpy):
// J_L = R_LI J_I R_LIᵀ.
Result<Loader::LinkMass> Loader::linkMassFromInertial(const urdf::Link& link) {
  const urdf::Inertial& in = *link.inertial;
  const int line = linkLine(link.name);
  const std::string owner = "link " + inQuotes(link.name);
  Eigen::Matrix3d J_I;
  J_I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
  if (!std::isfinite(in.mass)) return fail(line, owner + ": mass must be a finite number");
  if (!J_I.allFinite()) return fail(line, owner + ": inertia entries must be finite numbers");
  if (in.mass < 0)
    return fail(line, owner + ": negative mass " + formatNumber(in.mass, kDigits) +
                          " kg (a link's mass must be > 0, or 0 for a massless link)");
  LinkMass out;
  if (in.mass == 0) {
    if (!J_I.isZero(0.0)) {
      const std::string what = owner + ": mass is 0 but the inertia is not";
      if (strict())
        return fail(line, what +
                              "; a massless link must have zero inertia (or give the link its "
                              "mass)" +
                              kRelaxHint);
      // No mass distribution of mass 0 has a moment: the nearest physical inertia is none.
      warnings_.push_back(warnAt(line) + what + " (" + formatNumber(in.ixx, kDigits) + ", " +
                          formatNumber(in.iyy, kDigits) + ", " + formatNumber(in.izz, kDigits) +
                          " kg m^2 on the diagonal): the inertia is dropped, the link is massless" +
                          kRepairedNote);
    }
    return out;  // massless: contributes nothing
  }
  // A link's own inertia must be physical: positive semi-definite (a point mass or a thin rod
  // has zero moments, which merging can fill) and obeying the triangle inequality.
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(J_I);
  Eigen::Vector3d m = eig.eigenvalues();  // ascending
  const double scale = m.cwiseAbs().maxCoeff();
  if (m[0] < -dynamics::kTriangleRelSlack * scale)
    return fail(line, owner +
                          ": inertia tensor is not positive semi-definite (principal "
                          "moments " +
                          formatNumber(m[0], kDigits) + ", " + formatNumber(m[1], kDigits) + ", " +
                          formatNumber(m[2], kDigits) +
                          " kg m^2); no mass distribution has a negative moment");
  if (m[2] > (m[0] + m[1]) * (1.0 + dynamics::kTriangleRelSlack)) {
    const std::string broken = owner +
                               ": inertia breaks the triangle inequality I1 + I2 >= I3 "
                               "(principal moments " +
                               formatNumber(m[0], kDigits) + " + " + formatNumber(m[1], kDigits) +
                               " < " + formatNumber(m[2], kDigits) + " kg m^2)";
    if (strict()) return fail(line, broken + kRelaxHint);
    // Nearest physical moments (Euclidean distance): project onto I1 + I2 = I3 along (1, 1, −1).
    const double d = (m[2] - m[0] - m[1]) / 3.0;
    m += Eigen::Vector3d(d, d, -d);
    J_I = eig.eigenvectors() * m.asDiagonal() * eig.eigenvectors().transpose();
    warnings_.push_back(warnAt(line) + broken + ": using the nearest physical moments " +
                        formatNumber(m[0], kDigits) + ", " + formatNumber(m[1], kDigits) + ", " +
                        formatNumber(m[2], kDigits) + " kg m^2 (principal axes kept)" +
                        kRepairedNote);
  }
  MassProperties p;
  p.mass = in.mass;
  p.J_F = J_I;
  out.massive = true;
  out.in_link = transformed(p, toIsometry(in.origin));
  return out;
}

// Every collision mesh of a link: its file name resolved, the file read (once per file) and the
// URDF scale applied, in the shape frame S. Errors end with "[collision '<name>']".
std::optional<Error> Loader::loadCollisionMeshes(
    const std::string& link, std::vector<detail::CollisionGeometry>* collisions) {
  const std::string owner = "link " + inQuotes(link) + ": ";
  for (detail::CollisionGeometry& g : *collisions) {
    if (g.shape.kind != CollisionShape::Kind::kMesh) continue;
    const std::string tag = " [collision " + inQuotes(g.shape.name) + "]";
    const auto path = resolveMeshPath(g.filename, base_dir_);
    if (!path) return fail(g.geometry_line, owner + path.error() + tag);
    auto read = meshes_.find(*path);
    if (read == meshes_.end()) {
      std::vector<std::string> notes;
      auto mesh = readMeshFile(*path, &notes);
      if (!mesh) return fail(g.geometry_line, owner + mesh.error() + tag);
      for (const std::string& n : notes)
        warnings_.push_back(warnAt(g.geometry_line) + owner + n + tag);
      read = meshes_.emplace(*path, std::move(*mesh)).first;
    }
    if (read->second.triangles.empty())
      return fail(g.geometry_line, owner + "mesh " + inQuotes(*path) +
                                       " has no triangles: a collision mesh needs at least one" +
                                       tag);
    g.shape.mesh_file = *path;
    g.shape.mesh = scaledMesh(read->second, g.scale);
  }
  return std::nullopt;
}

// <cga_rigid_sim:mass_from_geometry>: the collision shapes, each in its origin frame, summed
// (they are taken as disjoint), with the given density or scaled to the given mass.
Result<Loader::LinkMass> Loader::linkMassFromGeometry(
    const std::string& link, const detail::MassFromGeometry& spec,
    const std::vector<detail::CollisionGeometry>& collisions) const {
  using Kind = CollisionShape::Kind;
  const std::string owner = "link " + inQuotes(link);
  const double density = spec.by_mass ? 1.0 : spec.density;
  std::vector<MassProperties> parts;
  for (const auto& g : collisions) {
    const CollisionShape& s = g.shape;
    MassProperties p;
    switch (s.kind) {
      case Kind::kBox:
        p = boxMassProperties(s.size, density);
        break;
      case Kind::kCylinder:
        p = cylinderMassProperties(s.radius, s.length, density);
        break;
      case Kind::kSphere:
        p = sphereMassProperties(s.radius, density);
        break;
      case Kind::kMesh: {
        // Only here must a mesh be closed: a volume needs a closed surface.
        auto mp = meshMassProperties(s.mesh, density, s.mesh_file);
        if (!mp)
          return fail(g.geometry_line,
                      owner + ": " + mp.error() + " [collision " + inQuotes(s.name) + "]");
        p = *mp;
        break;
      }
    }
    parts.push_back(transformed(p, g.X_LS));
  }
  LinkMass out;
  out.massive = true;
  out.in_link = combine(parts);
  if (spec.by_mass) {
    const double k = spec.mass / out.in_link.mass;
    out.in_link.mass = spec.mass;
    out.in_link.J_F *= k;
  }
  return out;
}

std::vector<urdf::JointSharedPtr> Loader::childJoints(const urdf::Link& link) const {
  // urdfdom lists child joints by name; the document order is what the user wrote.
  std::vector<urdf::JointSharedPtr> joints = link.child_joints;
  std::sort(joints.begin(), joints.end(), [&](const auto& a, const auto& b) {
    return xml_.joints.at(a->name).order < xml_.joints.at(b->name).order;
  });
  return joints;
}

// carried_: a post-order walk over the links (no recursion: deep chains), summing each link's
// mass and keeping the largest moment below it, through fixed and moving joints.
void Loader::findCarried() {
  std::vector<std::pair<const urdf::Link*, bool>> stack{{model_->getRoot().get(), false}};
  while (!stack.empty()) {
    const auto [link, done] = stack.back();
    stack.pop_back();
    const auto joints = childJoints(*link);
    if (!done) {  // every link gets its entry, the free bodies' below floating joints too
      stack.emplace_back(link, true);
      for (const auto& j : joints)
        stack.emplace_back(model_->getLink(j->child_link_name).get(), false);
      continue;
    }
    Carried c;
    const auto own = masses_.find(link->name);
    if (own != masses_.end() && own->second.massive) {
      c.mass = own->second.in_link.mass;
      c.moment = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(own->second.in_link.J_F,
                                                                Eigen::EigenvaluesOnly)
                     .eigenvalues()
                     .maxCoeff();
    }
    for (const auto& j : joints) {
      if (j->type == urdf::Joint::FLOATING) continue;
      const Carried& below = carried_.at(j->child_link_name);
      c.mass += below.mass;
      c.moment = std::max(c.moment, below.moment);
    }
    carried_[link->name] = c;
  }
}

// A moving joint whose child carries no mass at all (the link and everything below it: a sensor
// frame on a revolute joint) has no dynamics: nothing resists its motion. By default it is
// welded at its initial position, with a warning (tf keeps publishing the frames below it), unless
// the strict option is set or a <mimic> involves it (then the body is refused for its mass).
bool Loader::weldsMassless(const urdf::Joint& j) {
  const detail::JointXml& xml = xml_.joints.at(j.name);
  if (!xml.type || strict() || carried_.at(j.child_link_name).mass > 0 || xml.mimic) return false;
  for (const auto& [name, other] : xml_.joints)
    if (other.mimic && other.mimic->joint == j.name) return false;
  warnings_.push_back(warnAt(xml.line) + toString(*xml.type) + " joint " + inQuotes(j.name) +
                      " moves link " + inQuotes(j.child_link_name) +
                      ", which carries no mass (no <inertial> there or below it): nothing resists "
                      "its motion, so it is welded at " +
                      formatNumber(weldedPosition(xml), kDigits) +
                      (*xml.type == JointType::kPrismatic ? " m" : " rad") +
                      " like a fixed joint (give the link an <inertial> to simulate the joint)" +
                      kRepairedNote);
  return true;
}

// The welded joint's motion at its default initial position (0 clamped into its limits).
Eigen::Isometry3d Loader::weldedMotion(const urdf::Joint& j) const {
  const detail::JointXml& xml = xml_.joints.at(j.name);
  const double q = weldedPosition(xml);
  Eigen::Isometry3d X = Eigen::Isometry3d::Identity();
  if (*xml.type == JointType::kPrismatic)
    X.translation() = q * xml.axis;
  else
    X.linear() = Eigen::AngleAxisd(q, xml.axis).toRotationMatrix();
  return X;
}

// One body (roots[index]): the links reached from its root link through fixed joints.
// Floating joints met on the way start further free bodies, revolute, continuous and prismatic
// joints further moving bodies hinged to this one (appended to `more_roots`).
Result<BodyModel> Loader::buildBody(const BodyRoot& root, int index,
                                    std::vector<BodyRoot>* more_roots) {
  const double lambda = options_.lambda;
  BodyModel body;
  body.name = root.link->name;
  body.is_static = root.is_static;
  std::vector<std::pair<const urdf::Link*, Eigen::Isometry3d>> links;  // X_RL
  std::vector<BodyRoot> hinged;  // X_PJ holds X_RJ until B is known
  std::vector<std::pair<const urdf::Link*, Eigen::Isometry3d>> stack{
      {root.link, Eigen::Isometry3d::Identity()}};
  while (!stack.empty()) {
    const auto [link, X_RL] = stack.back();
    stack.pop_back();
    links.emplace_back(link, X_RL);
    const auto joints = childJoints(*link);
    // Reverse so the first child joint in the document is visited first.
    for (auto it = joints.rbegin(); it != joints.rend(); ++it) {
      const urdf::Joint& j = **it;
      const urdf::Link* child = model_->getLink(j.child_link_name).get();
      // The joint frame J, which is the child link's frame at q = 0.
      const Eigen::Isometry3d X_RC = X_RL * toIsometry(j.parent_to_joint_origin_transform);
      if (j.type == urdf::Joint::FIXED) {
        body.merged_joints.push_back(j.name);
        stack.emplace_back(child, X_RC);
      } else if (j.type == urdf::Joint::FLOATING) {
        more_roots->push_back({child, root.X_WR * X_RC, false});
      } else if (weldsMassless(j)) {  // nothing with mass moves: welded at its initial position
        body.merged_joints.push_back(j.name);
        stack.emplace_back(child, X_RC * weldedMotion(j));
      } else if (xml_.joints.at(j.name).type) {  // revolute, continuous, prismatic
        hinged.push_back({child, root.X_WR * X_RC, false, &j, index, X_RC});
      } else {  // the XML pass refuses the others first; kept so no joint is ever taken as fixed
        return fail(xml_.joints.at(j.name).line,
                    "joint " + inQuotes(j.name) + " is of a type that is not supported");
      }
    }
  }
  std::reverse(body.merged_joints.begin(), body.merged_joints.end());

  std::string link_list;
  for (const auto& l : links)
    link_list += (link_list.empty() ? "" : ", ") + inQuotes(l.first->name);

  // The body frame B. Static: the root link frame. Moving: origin at the composite centre of
  // mass, axes along the principal axes (dynamics::Inertia picks and orders them).
  Eigen::Isometry3d X_RB = Eigen::Isometry3d::Identity();
  if (!body.is_static) {
    std::vector<MassProperties> parts;
    for (const auto& [link, X_RL] : links) {
      const LinkMass& lm = masses_.at(link->name);
      if (lm.massive) parts.push_back(transformed(lm.in_link, X_RL));
    }
    MassProperties sum = combine(parts);
    const Carried& below = carried_.at(root.link->name);
    if (!(sum.mass > 0) && below.mass > 0 && !strict()) {
      // It carries massive links through further joints: a placeholder of kPlaceholderFraction
      // of what it carries, at its root link's origin.
      sum.mass = kPlaceholderFraction * below.mass;
      sum.J_F = kPlaceholderFraction * below.moment * Eigen::Matrix3d::Identity();
      sum.com_F.setZero();
      warnings_.push_back(warnAt(linkLine(body.name)) + "body " + inQuotes(body.name) +
                          " has no mass of its own (links " + link_list + ") but moves the " +
                          formatNumber(below.mass, kDigits) + " kg below it: given " +
                          formatNumber(sum.mass, kDigits) + " kg and moments " +
                          formatNumber(sum.J_F(0, 0), kDigits) + " kg m^2 (" +
                          formatNumber(kPlaceholderFraction, 1) +
                          " of what it carries; a moving body needs mass and inertia)" +
                          kRepairedNote);
    }
    if (!(sum.mass > 0)) {
      const std::string none = " has no mass: none of its links (" + link_list +
                               ") has an <inertial> with mass > 0 or a <" +
                               detail::kMassFromGeometryElement +
                               ">; a moving body needs mass and inertia (massless links are fine "
                               "only when merged by fixed joints into a body that has mass";
      if (root.joint) {
        const std::string& joint = root.joint->name;
        return fail(linkLine(body.name),
                    "body " + inQuotes(body.name) + none + "); it is a moving body of its own " +
                        "because " + toString(*xml_.joints.at(joint).type) + " joint " +
                        inQuotes(joint) + " moves it (to weld it to its parent instead, make " +
                        inQuotes(joint) + " a fixed joint)");
      }
      return fail(linkLine(body.name), "free body " + inQuotes(body.name) + none +
                                           "; to keep it still, fix it to '" +
                                           options_.world_frame + "' with a fixed joint)");
    }
    std::string warning;
    auto inertia = dynamics::Inertia::fromTensor(body.name, sum.mass, sum.J_F,
                                                 options_.triangle_policy, &warning);
    if (!inertia) {
      std::string what = inertia.error() + " [the body of links " + link_list +
                         (links.size() > 1 ? ", merged by fixed joints" : "") + "]";
      if (inertia.error().find("triangle") != std::string::npos) what += kRelaxHint;
      if (inertia.error().find("positive definite") != std::string::npos)
        what +=
            "; a moving body needs a positive moment of inertia about every axis (e.g. point "
            "masses on one line have none about that line)";
      return fail(linkLine(body.name), what);
    }
    if (!warning.empty()) warnings_.push_back(source_ + ": " + warning + kRepairedNote);
    X_RB.translation() = sum.com_F;
    X_RB.linear() = inertia->rotationFromPrincipal().toRotationMatrix();
    body.inertia = *inertia;
  }
  const Eigen::Isometry3d X_BR = X_RB.inverse();
  for (const auto& [link, X_RL] : links) {
    const Eigen::Isometry3d X_BL = X_BR * X_RL;
    // Each link's shapes move into its one body (the XML reading is not needed after this).
    for (detail::CollisionGeometry& g : xml_.links.at(link->name).collisions) {
      CollisionShape shape = std::move(g.shape);
      shape.M_BS = cga::Motor::fromIsometry(X_BL * g.X_LS, lambda);
      shape.link_index = static_cast<int>(body.links.size());
      body.shapes.push_back(std::move(shape));
    }
    body.links.push_back({link->name, cga::Motor::fromIsometry(X_BL, lambda)});
  }
  // The joints met: their frames J in this body's frame B, M_PJ = M_BL (joint <origin>).
  for (BodyRoot& h : hinged) {
    h.X_PJ = X_BR * h.X_PJ;
    more_roots->push_back(h);
  }
  // With every joint at 0 (a joint's child is placed again at its initial position later).
  body.M_WB0 = cga::Motor::fromIsometry(root.X_WR * X_RB, lambda);
  return body;
}

// The joint that starts the body roots[index] (`child`, built): its frames and what the XML pass
// read. J is the child link's frame at q = 0, and the child link is the body's root link, so
// M_JC = M_BL⁻¹ of the root link.
JointModel Loader::jointModel(const BodyRoot& root, int index, const BodyModel& child) const {
  const detail::JointXml& xml = xml_.joints.at(root.joint->name);
  JointModel j;
  j.name = root.joint->name;
  j.type = *xml.type;
  j.parent_body = root.parent;
  j.child_body = index;
  j.parent_link = root.joint->parent_link_name;
  j.child_link = root.joint->child_link_name;
  j.M_PJ = cga::Motor::fromIsometry(root.X_PJ, options_.lambda);
  j.M_JC = child.links.front().M_BL.reverse();
  j.axis = xml.axis;
  j.limits = xml.limits;
  j.damping = xml.damping;
  j.friction = xml.friction;
  return j;
}

// Bodies in the document order of their root links, except that a joint's parent body comes
// before its child body (a child link may be written before its parent's links): each body is
// preceded by those of its ancestors not yet placed. `document_order` lists the body indices
// sorted by the document order of their root links; the joints' body indices are renumbered and
// the joints sorted by child body, which puts them parent first too.
void Loader::orderParentFirst(Scene* scene, const std::vector<int>& document_order) {
  const std::size_t n = scene->bodies.size();
  std::vector<int> parent(n, -1);
  for (const JointModel& j : scene->joints) parent[j.child_body] = j.parent_body;
  std::vector<int> order, chain;  // order[new index] = old index
  std::vector<bool> placed(n, false);
  for (const int k : document_order) {
    chain.clear();  // k and its ancestors not yet placed, child first (no recursion: deep chains)
    for (int a = k; a >= 0 && !placed[a]; a = parent[a]) chain.push_back(a);
    for (auto it = chain.rbegin(); it != chain.rend(); ++it) {
      placed[*it] = true;
      order.push_back(*it);
    }
  }
  std::vector<int> new_index(n);
  std::vector<BodyModel> bodies;
  bodies.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    new_index[order[i]] = static_cast<int>(i);
    bodies.push_back(std::move(scene->bodies[order[i]]));
  }
  scene->bodies = std::move(bodies);
  for (JointModel& j : scene->joints) {
    if (j.parent_body >= 0) j.parent_body = new_index[j.parent_body];
    j.child_body = new_index[j.child_body];
  }
  std::sort(scene->joints.begin(), scene->joints.end(),
            [](const JointModel& a, const JointModel& b) { return a.child_body < b.child_body; });
}

// Each joint's <mimic>, resolved to the independent joint at the end of its chain (multipliers
// and offsets composed: q = m1 (m2 q_l + o2) + o1), and refused where the constraint cannot be
// simulated: leader and follower in different trees (a tree on a free root and another tree,
// joints on the ground — the world or a static body — belong together), or no position of the
// leader that keeps every follower within its limits.
std::optional<Error> Loader::resolveMimics(Scene* scene) const {
  std::vector<JointModel>& joints = scene->joints;
  std::unordered_map<std::string, int> index;
  std::vector<int> moved_by(scene->bodies.size(), -1);
  for (std::size_t k = 0; k < joints.size(); ++k) {
    index.emplace(joints[k].name, static_cast<int>(k));
    moved_by[joints[k].child_body] = static_cast<int>(k);
  }
  // The free root a joint's tree hangs from, or −1 for the ground.
  const auto rootOf = [&](int k) {
    int body = joints[k].parent_body;
    while (body >= 0 && moved_by[body] >= 0) body = joints[moved_by[body]].parent_body;
    return body < 0 || scene->bodies[body].is_static ? -1 : body;
  };
  const auto rootName = [&](int root) {
    return root < 0 ? "on the ground ('" + options_.world_frame + "' or a link fixed to it)"
                    : "hanging from the free body " + inQuotes(scene->bodies[root].name);
  };
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const detail::JointXml& xml = xml_.joints.at(joints[k].name);
    if (!xml.mimic) continue;
    JointMimic m;
    m.written = xml.mimic->joint;
    m.multiplier = xml.mimic->multiplier;
    m.offset = xml.mimic->offset;
    int leader = index.at(m.written);  // the XML pass checked the chain ends at such a joint
    for (const detail::JointXml* next = &xml_.joints.at(m.written); next->mimic;
         next = &xml_.joints.at(joints[leader].name)) {
      m.offset += m.multiplier * next->mimic->offset;
      m.multiplier *= next->mimic->multiplier;
      leader = index.at(next->mimic->joint);
    }
    m.leader = leader;
    const std::string owner =
        "joint " + inQuotes(joints[k].name) + ": <mimic joint=" + inQuotes(m.written) + ">";
    const int a = rootOf(static_cast<int>(k)), b = rootOf(leader);
    if (a != b)
      return fail(xml.mimic->line, owner + ": " + inQuotes(joints[leader].name) +
                                       " is in another articulated tree (" + rootName(b) +
                                       ", this one " + rootName(a) +
                                       "); a mimic constraint couples joints of one tree");
    if (!std::isfinite(m.multiplier) || !std::isfinite(m.offset))
      return fail(xml.mimic->line, owner + ": the composed multiplier and offset overflow");
    const JointLimits& l = joints[k].limits;
    if (m.multiplier == 0.0 && l.has_position && !(l.lower <= m.offset && m.offset <= l.upper))
      return fail(xml.mimic->line, owner + ": multiplier 0 holds the joint at its offset " +
                                       formatNumber(m.offset, kDigits) + ", outside its limits [" +
                                       formatNumber(l.lower, kDigits) + ", " +
                                       formatNumber(l.upper, kDigits) + "]");
    joints[k].mimic = m;
  }
  for (std::size_t k = 0; k < joints.size(); ++k) {
    const auto [lower, upper] = mimicRange(joints, static_cast<int>(k));
    if (lower <= upper) continue;
    std::string followers;
    for (const JointModel& j : joints)
      if (j.mimic && j.mimic->leader == static_cast<int>(k))
        followers += (followers.empty() ? "" : ", ") + inQuotes(j.name);
    return fail(xml_.joints.at(joints[k].name).line,
                "joint " + inQuotes(joints[k].name) + " and the joints that mimic it (" +
                    followers + ") cannot all be within their limits: mapped to " +
                    inQuotes(joints[k].name) + ", their limits leave no position (" +
                    formatNumber(lower, kDigits) + " > " + formatNumber(upper, kDigits) + ")");
  }
  return std::nullopt;
}

// Links whose names begin with '/' are published on tf without it (tf2 refuses such frame ids),
// and known by that name everywhere else (bodies, initial state, messages), with a warning; two
// links that would become one frame, or a link that would become the world frame, are refused.
std::optional<Error> Loader::nameFramesForTf(Scene* scene) {
  std::unordered_map<std::string, std::string> by_frame;  // tf frame → link, for every link
  std::unordered_map<std::string, std::string> renamed;   // link → its frame, where they differ
  std::vector<std::string> names;
  for (const auto& [name, link] : xml_.links) names.push_back(name);
  std::sort(names.begin(), names.end(),
            [&](const std::string& a, const std::string& b) { return linkLine(a) < linkLine(b); });
  const std::string& world = options_.world_frame;
  const bool has_world_root =
      model_->getRoot()->name != world && tfFrame(model_->getRoot()->name) == world;
  for (const std::string& name : names) {
    const std::string frame = tfFrame(name);
    if (frame.empty())
      return fail(linkLine(name), "link " + inQuotes(name) +
                                      " has no name once its leading '/' is removed (tf2 takes "
                                      "frame ids without it)");
    const bool root = name == model_->getRoot()->name;
    if (frame == world && name != world && !(root && has_world_root))
      return fail(linkLine(name), "link " + inQuotes(name) + " would be published as the tf " +
                                      "frame " + inQuotes(frame) + ", the world frame " +
                                      "(~world_frame), which only the root link may be; rename it");
    const auto [it, added] = by_frame.emplace(frame, name);
    if (!added)
      return fail(linkLine(name), "links " + inQuotes(it->second) + " (line " +
                                      std::to_string(linkLine(it->second)) + ") and " +
                                      inQuotes(name) + " would both be published as the tf " +
                                      "frame " + inQuotes(frame) + " (tf2 takes frame ids " +
                                      "without a leading '/'); rename one");
    if (frame == name) continue;
    renamed.emplace(name, frame);
    warnings_.push_back(warnAt(linkLine(name)) + "link " + inQuotes(name) +
                        " is published on tf as " + inQuotes(frame) +
                        " and known by that name (tf2 refuses frame ids that begin with '/')");
  }
  if (renamed.empty()) return std::nullopt;
  const auto rename = [&](std::string& link) {
    const auto it = renamed.find(link);
    if (it != renamed.end()) link = it->second;
  };
  for (BodyModel& b : scene->bodies) {
    const std::string old_root = b.links.front().link;
    for (LinkFrame& l : b.links) {
      for (CollisionShape& shape : b.shapes)  // default names '<link>#<k>' follow the link
        if (&b.links[shape.link_index] == &l && shape.name.rfind(l.link + "#", 0) == 0)
          shape.name = tfFrame(l.link) + shape.name.substr(l.link.size());
      rename(l.link);
    }
    if (b.name == old_root) b.name = b.links.front().link;
  }
  for (JointModel& j : scene->joints) {
    rename(j.parent_link);
    rename(j.child_link);
  }
  return std::nullopt;
}

// Each joint starts at q = 0 unless its limits exclude 0: then at the nearest limit, with a
// warning (the initial-state dictionary can choose another position). A joint that mimics
// another starts where its leader puts it; a leader's limits include those of its followers.
void Loader::setDefaultInitialPositions(Scene* scene) {
  for (std::size_t k = 0; k < scene->joints.size(); ++k) {
    JointModel& j = scene->joints[k];
    if (j.mimic) continue;
    const auto [lower, upper] = mimicRange(scene->joints, static_cast<int>(k));
    if (lower <= 0.0 && 0.0 <= upper) continue;
    const bool own = j.limits.has_position && (j.limits.lower > 0.0 || j.limits.upper < 0.0);
    j.initial_position = 0.0 < lower ? lower : upper;
    const char* unit = j.type == JointType::kPrismatic ? " m" : " rad";
    warnings_.push_back(
        source_ + ":" + std::to_string(xml_.joints.at(j.name).line) + ": joint " +
        inQuotes(j.name) + ": the default initial position 0" + unit + " is outside its limits [" +
        formatNumber(lower, kDigits) + ", " + formatNumber(upper, kDigits) + "]" + unit +
        (own ? "" : " (those of the joints that mimic it, mapped to it)") + ": clamped to the " +
        (0.0 < lower ? "lower" : "upper") + " limit " + formatNumber(j.initial_position, kDigits) +
        unit + " (~initial_state." + j.name + ".position chooses another)");
  }
}

Result<Scene> Loader::load(const std::string& xml) {
  if (auto err = checkOptions()) return *err;
  if (xml.size() > kMaxUrdfBytes) return fail(0, textTooLarge(xml.size()));
  auto checked = detail::readUrdfXml(xml, source_, options_.world_frame);
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
  scene.warnings = std::move(xml_.warnings);
  scene.warnings.insert(scene.warnings.end(), warnings_.begin(), warnings_.end());

  auto applied = applyInitialState(scene, options_.initial_state);
  if (!applied) return Error{applied.error()};
  return scene;
}

}  // namespace

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
  return Loader(path, base_dir, options).load(text.str());
}

Result<Scene> loadUrdfString(const std::string& xml, const std::string& source,
                             const SceneOptions& options) {
  const std::string base_dir;  // meshes: relative to the current directory
  return Loader(source, base_dir, options).load(xml);
}

}  // namespace scene
}  // namespace cga_rigid_sim
