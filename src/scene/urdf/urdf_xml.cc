#include "scene/urdf/urdf_xml.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>
#include <optional>
#include <sstream>

#include "cga_rigid_sim/format.h"
#include "cga_rigid_sim/scene/urdf/urdf_loader.h"
#include "scene/urdf/urdf_reader.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

using tinyxml2::XMLAttribute;
using tinyxml2::XMLElement;

std::optional<Error> Reader::readNumberAttr(const XMLElement* e, const char* attr,
                                            const std::string& owner, bool required,
                                            double* out) const {
  const char* text = e->Attribute(attr);
  if (!text) {
    if (!required) return std::nullopt;
    return fail(e->GetLineNum(), owner + ": <" + e->Name() + "> has no " + attr + " attribute");
  }
  if (!parseUrdfNumber(text, out))
    return fail(e->GetLineNum(), owner + ": <" + e->Name() + " " + attr +
                                     "> must be a finite number (got " + inQuotes(text) + ")");
  return std::nullopt;
}

std::optional<Error> Reader::readOrigin(const XMLElement* parent, const std::string& owner,
                                        Eigen::Isometry3d* X) const {
  X->setIdentity();
  const XMLElement* o = parent->FirstChildElement("origin");
  if (!o) return std::nullopt;
  Eigen::Vector3d xyz = Eigen::Vector3d::Zero(), rpy = Eigen::Vector3d::Zero();
  for (const char* attr : {"xyz", "rpy"}) {
    const char* text = o->Attribute(attr);
    if (!text) continue;
    if (!parseTriple(text, attr[0] == 'x' ? &xyz : &rpy))
      return fail(o->GetLineNum(), owner + ": <" + parent->Name() + "><origin " + attr +
                                       "> must be three finite numbers (got " + inQuotes(text) +
                                       ")");
  }
  X->linear() = rotationFromRpy(rpy);
  X->translation() = xyz;
  return std::nullopt;
}

// The <geometry> of a <visual> or <collision>: its shape element and numbers, in urdfdom's
// syntax. `strict` (a collision): sizes > 0 and a mesh scale without zeros, as a collision shape
// (and a mass from geometry) needs; a <visual> is only read as urdfdom reads it.
std::optional<Error> Reader::readMassFromGeometry(const std::string& owner, const XMLElement* ext,
                                                  LinkXml* out) const {
  MassFromGeometry& m = out->mass_from_geometry;
  m.line = ext->GetLineNum();
  const std::string where = owner + ": <" + kMassFromGeometryElement + ">";
  bool has_density = false, has_mass = false;
  for (const XMLAttribute* a = ext->FirstAttribute(); a; a = a->Next()) {
    const std::string name = a->Name();
    if (name == "density") {
      has_density = true;
      if (auto err = readNumberAttr(ext, "density", owner, true, &m.density)) return err;
    } else if (name == "mass") {
      has_mass = true;
      if (auto err = readNumberAttr(ext, "mass", owner, true, &m.mass)) return err;
    } else if (name.compare(0, 6, "xmlns:") != 0) {
      return fail(m.line, where + ": unknown attribute " + inQuotes(name) +
                              " (allowed: density in kg/m^3, or mass in kg)");
    }
  }
  if (has_density == has_mass)
    return fail(m.line, where + " needs exactly one of density (kg/m^3) or mass (kg)");
  m.by_mass = has_mass;
  const double value = has_mass ? m.mass : m.density;
  if (!(value > 0)) {
    return fail(m.line, where + " " + (has_mass ? "mass" : "density") + " must be > 0 (got " +
                            formatNumber(value, 6) + ")");
  }
  if (out->collisions.empty())
    return fail(m.line, where +
                            " needs at least one <collision> with a <geometry> to compute "
                            "the mass from");
  return std::nullopt;
}

std::optional<Error> Reader::readLink(const XMLElement* e, int order) {
  const char* name_attr = e->Attribute("name");
  if (!name_attr || !*name_attr) return fail(e->GetLineNum(), "<link> has no name attribute");
  const std::string name = name_attr;
  const std::string owner = "link " + inQuotes(name);
  LinkXml link;
  link.order = order;
  link.line = e->GetLineNum();
  const auto found = out_.links.find(name);
  if (found != out_.links.end())
    return fail(link.line, "duplicate link name " + inQuotes(name) + " (first defined at line " +
                               std::to_string(found->second.line) + "); link names must be unique");

  const XMLElement* inertial = e->FirstChildElement("inertial");
  if (inertial) {
    if (inertial->NextSiblingElement("inertial"))
      return fail(inertial->NextSiblingElement("inertial")->GetLineNum(),
                  owner + " has more than one <inertial>");
    link.has_inertial = true;
    Eigen::Isometry3d X;
    if (auto err = readOrigin(inertial, owner, &X)) return err;
    const XMLElement* mass = inertial->FirstChildElement("mass");
    if (!mass) return fail(inertial->GetLineNum(), owner + ": <inertial> has no <mass value=...>");
    if (auto err = readNumberAttr(mass, "value", owner, true, &link.mass)) return err;
    const XMLElement* inertia = inertial->FirstChildElement("inertia");
    if (!inertia)
      return fail(inertial->GetLineNum(),
                  owner +
                      ": <inertial> has no <inertia ixx ixy ixz iyy iyz izz> (urdfdom would "
                      "read the link with zero inertia)");
    for (const char* attr : {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"}) {
      double v = 0;
      if (auto err = readNumberAttr(inertia, attr, owner, true, &v)) return err;
    }
  }
  for (const XMLElement* c = e->FirstChildElement("visual"); c;
       c = c->NextSiblingElement("visual")) {
    CollisionGeometry g;
    if (auto err = readGeometry(c, owner, false, &g)) return err;
  }
  int k = 0;
  for (const XMLElement* c = e->FirstChildElement("collision"); c;
       c = c->NextSiblingElement("collision")) {
    CollisionGeometry g;
    if (auto err = readCollision(c, name, k++, &g)) return err;
    link.collisions.push_back(std::move(g));
  }
  for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
    if (std::strcmp(c->Name(), kMassFromGeometryElement) != 0) continue;
    if (link.has_mass_from_geometry)
      return fail(c->GetLineNum(),
                  owner + " has more than one <" + std::string(kMassFromGeometryElement) + ">");
    link.has_mass_from_geometry = true;
    if (auto err = readMassFromGeometry(owner, c, &link)) return err;
  }
  if (link.has_inertial && link.has_mass_from_geometry)
    return fail(link.mass_from_geometry.line,
                owner + " has both <inertial> and <" + kMassFromGeometryElement +
                    ">: give one (the extension computes the inertial from the collision "
                    "geometry)");
  out_.links.emplace(name, std::move(link));
  link_names_.push_back(name);
  return std::nullopt;
}

// A revolute, continuous or prismatic joint's motion, as URDF defines it: <axis xyz> (default
// (1, 0, 0), normalised here), <limit lower upper effort velocity> (required for revolute and
// prismatic; effort and velocity required in every <limit>, as urdfdom requires them; lower and
// upper default to 0; a continuous joint has no position limits and ignores lower and upper),
// <dynamics damping friction> (at least one of them, as urdfdom requires; each defaults to 0).
std::optional<Error> Reader::readJointMotion(const XMLElement* e, const std::string& owner,
                                             JointXml* joint) {
  const JointType type = *joint->type;
  const std::string type_name = toString(type);
  if (const XMLElement* axis = e->FirstChildElement("axis")) {
    const char* text = axis->Attribute("xyz");
    if (!text)
      return fail(axis->GetLineNum(), owner +
                                          ": <axis> has no xyz attribute (urdfdom would read "
                                          "a zero axis); give the joint's direction, e.g. "
                                          "<axis xyz=\"0 0 1\"/>");
    Eigen::Vector3d xyz;
    if (!parseTriple(text, &xyz))
      return fail(axis->GetLineNum(),
                  owner + ": <axis xyz> must be three finite numbers (got " + inQuotes(text) + ")");
    // stableNorm: neither a tiny nor a huge axis under- or overflows on the way to unit length.
    const double norm = xyz.stableNorm();
    if (!(norm > 0) || !std::isfinite(norm))
      return fail(axis->GetLineNum(),
                  owner + ": <axis xyz> must not be zero (got " + inQuotes(text) +
                      "): it is the direction the " + type_name + " joint " +
                      (type == JointType::kPrismatic ? "slides along" : "turns about"));
    joint->axis = xyz / norm;
  }

  const XMLElement* limit = e->FirstChildElement("limit");
  JointLimits& limits = joint->limits;
  if (!limit && type != JointType::kContinuous)
    return fail(joint->line, owner + " is " + type_name +
                                 " but has no <limit>: URDF requires <limit lower=... upper=... "
                                 "effort=... velocity=.../> for revolute and prismatic joints "
                                 "(use 'continuous' for a revolute joint without position "
                                 "limits)");
  if (limit) {
    const int line = limit->GetLineNum();
    for (const char* attr : {"effort", "velocity"})
      if (!limit->Attribute(attr))
        return fail(line, owner + ": <limit> has no " + attr +
                              " attribute (URDF requires effort and velocity in every <limit>)");
    double lower = 0.0, upper = 0.0;  // URDF's defaults
    if (auto err = readNumberAttr(limit, "lower", owner, false, &lower)) return err;
    if (auto err = readNumberAttr(limit, "upper", owner, false, &upper)) return err;
    if (auto err = readNumberAttr(limit, "effort", owner, true, &limits.effort)) return err;
    if (auto err = readNumberAttr(limit, "velocity", owner, true, &limits.velocity)) return err;
    const char* unit = type == JointType::kPrismatic ? " N" : " N m";
    if (limits.effort < 0)
      return fail(line, owner + ": <limit> effort must be >= 0 (got " +
                            formatNumber(limits.effort, 10) + unit +
                            "): it bounds the magnitude of the joint's effort");
    unit = type == JointType::kPrismatic ? " m/s" : " rad/s";
    if (limits.velocity < 0)
      return fail(line, owner + ": <limit> velocity must be >= 0 (got " +
                            formatNumber(limits.velocity, 10) + unit +
                            "): it bounds the magnitude of the joint's velocity");
    // CAD exporters (the SolidWorks URDF exporter among them) write effort="0" velocity="0" as
    // placeholders; taken literally, an effort limit of 0 holds every command at 0.
    for (double* value : {&limits.effort, &limits.velocity}) {
      if (*value != 0.0) continue;
      *value = std::numeric_limits<double>::infinity();
      const bool effort = value == &limits.effort;
      out_.warnings.push_back(source_ + ":" + std::to_string(line) + ": " + owner + ": <limit " +
                              (effort ? "effort" : "velocity") +
                              "=\"0\"> read as no limit given (a placeholder CAD exporters "
                              "write; " +
                              (effort ? "a limit of 0 would hold every effort command at 0"
                                      : "a velocity limit is not enforced anyway") +
                              "): give the real limit to bound it");
    }
    if (type != JointType::kContinuous) {
      unit = type == JointType::kPrismatic ? " m" : " rad";
      if (lower > upper)
        return fail(line, owner + ": <limit> lower " + formatNumber(lower, 10) + unit +
                              " > upper " + formatNumber(upper, 10) + unit +
                              ": the range of positions is empty (lower must be <= upper)");
      for (const char* attr : {"lower", "upper"})
        if (!limit->Attribute(attr))
          out_.warnings.push_back(source_ + ":" + std::to_string(line) + ": " + owner +
                                  ": <limit> has no " + attr + "; URDF's default " + attr +
                                  " = 0 is used");
      limits.has_position = true;
      limits.lower = lower;
      limits.upper = upper;
    }
  }

  if (const XMLElement* dynamics = e->FirstChildElement("dynamics")) {
    const int line = dynamics->GetLineNum();
    if (!dynamics->Attribute("damping") && !dynamics->Attribute("friction"))
      return fail(line, owner +
                            ": <dynamics> has neither damping nor friction (urdfdom refuses "
                            "an empty <dynamics>; remove it for a joint without either)");
    if (auto err = readNumberAttr(dynamics, "damping", owner, false, &joint->damping)) return err;
    if (auto err = readNumberAttr(dynamics, "friction", owner, false, &joint->friction)) return err;
    if (joint->damping < 0)
      return fail(line, owner + ": <dynamics> damping must be >= 0 (got " +
                            formatNumber(joint->damping, 10) +
                            "): a negative viscous damping would feed energy into the joint");
    if (joint->friction < 0)
      return fail(line, owner + ": <dynamics> friction must be >= 0 (got " +
                            formatNumber(joint->friction, 10) +
                            "): it is the magnitude of the joint's Coulomb friction");
  }
  return std::nullopt;
}

std::optional<Error> Reader::readJoint(const XMLElement* e, int order) {
  const char* name_attr = e->Attribute("name");
  if (!name_attr || !*name_attr) return fail(e->GetLineNum(), "<joint> has no name attribute");
  const std::string name = name_attr;
  const std::string owner = "joint " + inQuotes(name);
  JointXml joint;
  joint.order = order;
  joint.line = e->GetLineNum();
  const auto found = out_.joints.find(name);
  if (found != out_.joints.end())
    return fail(joint.line, "duplicate joint name " + inQuotes(name) + " (first defined at line " +
                                std::to_string(found->second.line) +
                                "); joint names must be unique");
  const char* type = e->Attribute("type");
  if (!type) return fail(joint.line, owner + " has no type attribute");
  const std::string t = type;
  if (t == "planar")
    return fail(joint.line, owner +
                                " is of type 'planar', which is not supported: a planar "
                                "joint has three degrees of freedom in one plane; use "
                                "'floating' to make the child a free body, or a chain of "
                                "prismatic and revolute joints (each link between them "
                                "needs mass)");
  if (t == "revolute") joint.type = JointType::kRevolute;
  if (t == "continuous") joint.type = JointType::kContinuous;
  if (t == "prismatic") joint.type = JointType::kPrismatic;
  if (!joint.type && t != "fixed" && t != "floating")
    return fail(joint.line, owner + ": unknown joint type " + inQuotes(t) +
                                " (URDF joint types: fixed, floating, revolute, continuous, "
                                "prismatic, planar; supported: fixed, floating, revolute, "
                                "continuous, prismatic)");
  if (const XMLElement* mimic = e->FirstChildElement("mimic")) {
    MimicXml m;
    m.line = mimic->GetLineNum();
    const char* leader = mimic->Attribute("joint");
    if (!leader || !*leader)
      return fail(m.line, owner +
                              ": <mimic> has no joint attribute (it names the joint this "
                              "one follows)");
    m.joint = leader;
    if (auto err = readNumberAttr(mimic, "multiplier", owner, false, &m.multiplier)) return err;
    if (auto err = readNumberAttr(mimic, "offset", owner, false, &m.offset)) return err;
    if (!joint.type)
      return fail(m.line, owner + " is " + t +
                              " but has a <mimic>: only a revolute, continuous "
                              "or prismatic joint has a position that can follow another "
                              "joint's (remove the <mimic>)");
    joint.mimic = m;
  }
  Eigen::Isometry3d X;
  if (auto err = readOrigin(e, owner, &X)) return err;
  if (joint.type)
    if (auto err = readJointMotion(e, owner, &joint)) return err;
  JointEdge edge;
  edge.name = name;
  edge.line = joint.line;
  for (const char* role : {"parent", "child"}) {
    const XMLElement* r = e->FirstChildElement(role);
    const char* link = r ? r->Attribute("link") : nullptr;
    if (!link || !*link) return fail(joint.line, owner + " has no <" + role + " link=\"...\"/>");
    (role[0] == 'p' ? edge.parent : edge.child) = link;
  }
  out_.joints.emplace(name, joint);
  edges_.push_back(edge);
  return std::nullopt;
}

std::optional<Error> Reader::checkExtensionPlacement(const XMLElement* robot) const {
  // Every element of the extension must be known and in its place: a misspelt element would
  // otherwise be ignored silently, like urdfdom ignores it.
  std::vector<const XMLElement*> stack{robot};
  const std::size_t prefix = std::strlen(kExtensionPrefix);
  while (!stack.empty()) {
    const XMLElement* e = stack.back();
    stack.pop_back();
    for (const XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      if (std::strncmp(c->Name(), kExtensionPrefix, prefix) == 0) {
        const bool in_link = std::strcmp(e->Name(), "link") == 0 && e->Parent() == robot;
        const bool in_collision = std::strcmp(e->Name(), "collision") == 0 && e->Parent() &&
                                  e->Parent()->ToElement() &&
                                  std::strcmp(e->Parent()->ToElement()->Name(), "link") == 0 &&
                                  e->Parent()->Parent() == robot;
        const bool placed = std::strcmp(c->Name(), kMassFromGeometryElement) == 0 ? in_link
                            : std::strcmp(c->Name(), kContactElement) == 0        ? in_collision
                                                                                  : false;
        if (!placed)
          return fail(c->GetLineNum(), "unknown or misplaced element <" + std::string(c->Name()) +
                                           "> (the cga_rigid_sim extension has <" +
                                           kMassFromGeometryElement +
                                           ">, directly inside a <link>, and <" + kContactElement +
                                           ">, directly inside a link's <collision>)");
      }
      stack.push_back(c);
    }
  }
  return std::nullopt;
}

std::optional<Error> Reader::checkTree() const {
  std::unordered_map<std::string, const JointEdge*> parent_joint;
  std::unordered_map<std::string, std::vector<std::string>> children;
  for (const JointEdge& j : edges_) {
    const std::string owner = "joint " + inQuotes(j.name);
    for (const std::string* l : {&j.parent, &j.child})
      if (!out_.links.count(*l))
        return fail(j.line, owner + ": " + (l == &j.parent ? "parent" : "child") + " link " +
                                inQuotes(*l) + " is not defined (no <link name=\"" + *l + "\">)");
    if (j.parent == j.child)
      return fail(j.line, owner + " joins link " + inQuotes(j.child) + " to itself");
    const auto [it, added] = parent_joint.emplace(j.child, &j);
    if (!added)
      return fail(j.line, "link " + inQuotes(j.child) + " is the child of two joints, " +
                              inQuotes(it->second->name) + " (line " +
                              std::to_string(it->second->line) + ") and " + inQuotes(j.name) +
                              "; a URDF must be a tree (each link has at most one parent joint)");
    children[j.parent].push_back(j.child);
  }
  if (link_names_.empty()) return fail(1, "the <robot> has no <link>");
  std::vector<std::string> roots;
  for (const std::string& l : link_names_)
    if (!parent_joint.count(l)) roots.push_back(l);
  if (roots.size() > 1)
    return fail(out_.links.at(roots[1]).line,
                "more than one root link: " + inQuotes(roots[0]) + " and " + inQuotes(roots[1]) +
                    " both have no parent joint; a URDF is one tree (to simulate several bodies, "
                    "give each a floating joint from a common '" +
                    world_frame_ + "' link)");
  // Links not reachable from the root hang in a cycle of joints. The depth of each link (joints
  // from the root) is bounded: urdfdom builds the tree recursively.
  std::unordered_map<std::string, bool> reached;
  if (!roots.empty()) {
    std::vector<std::pair<std::string, int>> stack{{roots[0], 0}};
    reached[roots[0]] = true;
    while (!stack.empty()) {
      const auto [l, depth] = stack.back();
      stack.pop_back();
      const auto c = children.find(l);
      if (c == children.end()) continue;
      for (const std::string& child : c->second) {
        if (reached[child]) continue;
        reached[child] = true;
        if (depth + 1 > kMaxUrdfDepth)
          return fail(parent_joint.at(child)->line,
                      "link " + inQuotes(child) + " is more than " + std::to_string(kMaxUrdfDepth) +
                          " joints below the root link " + inQuotes(roots[0]) +
                          "; the loader takes chains of at most " + std::to_string(kMaxUrdfDepth) +
                          " joints (kMaxUrdfDepth: urdfdom builds the tree recursively, and a "
                          "tree integrator factors a mass matrix as large every step; "
                          "doc/urdf.md#bounds)");
        stack.emplace_back(child, depth + 1);
      }
    }
  }
  for (const std::string& l : link_names_) {
    if (reached.count(l)) continue;
    // Walk up the parents until a link repeats: that loop is the cycle.
    std::unordered_map<std::string, int> seen;
    std::vector<const JointEdge*> path;
    std::string at = l;
    while (!seen.count(at)) {
      seen[at] = static_cast<int>(path.size());
      path.push_back(parent_joint.at(at));
      at = path.back()->parent;
    }
    std::string joints;
    for (std::size_t k = seen[at]; k < path.size(); ++k)
      joints += (joints.empty() ? "" : ", ") + inQuotes(path[k]->name);
    return fail(
        path[seen[at]]->line,
        "the joints " + joints + " form a cycle (link " + inQuotes(l) + " is not connected to " +
            (roots.empty() ? std::string("any root link") : "the root link " + inQuotes(roots[0])) +
            "); a URDF must be a tree");
  }
  const auto world = parent_joint.find(world_frame_);
  if (world != parent_joint.end())
    return fail(world->second->line, "link " + inQuotes(world_frame_) +
                                         " is the world frame and must be the root of the tree, "
                                         "but joint " +
                                         inQuotes(world->second->name) + " makes it a child of " +
                                         inQuotes(world->second->parent));
  return std::nullopt;
}

std::optional<Error> Reader::checkMimics() const {
  for (const JointEdge& edge : edges_) {
    const JointXml& j = out_.joints.at(edge.name);
    if (!j.mimic) continue;
    const std::string owner = "joint " + inQuotes(edge.name);
    const MimicXml& m = *j.mimic;
    const auto leader = out_.joints.find(m.joint);
    if (leader == out_.joints.end())
      return fail(m.line, owner + ": <mimic joint=" + inQuotes(m.joint) + ">: no joint named " +
                              inQuotes(m.joint) +
                              " (a mimic joint follows another joint of "
                              "the robot)");
    if (m.joint == edge.name)
      return fail(m.line, owner +
                              ": <mimic> names the joint itself: a joint cannot follow "
                              "its own position");
    if (!leader->second.type)
      return fail(m.line, owner + ": <mimic joint=" + inQuotes(m.joint) +
                              ">: " + inQuotes(m.joint) +
                              " is a fixed or floating joint, which has no "
                              "position to follow (the leader must be revolute, continuous or "
                              "prismatic)");
    // Follow the chain of leaders: it must end at a joint without <mimic>.
    std::vector<std::string> chain{edge.name};
    for (std::string at = m.joint;;) {
      if (std::find(chain.begin(), chain.end(), at) != chain.end()) {
        std::string names;
        for (const std::string& c : chain) names += (names.empty() ? "" : " -> ") + inQuotes(c);
        return fail(m.line, "the mimic joints " + names + " -> " + inQuotes(at) +
                                " form a cycle: no joint among them moves on its own (one of "
                                "them must have no <mimic>)");
      }
      chain.push_back(at);
      const JointXml& next = out_.joints.at(at);
      if (!next.mimic) break;
      at = next.mimic->joint;
      if (!out_.joints.count(at)) break;  // reported for that joint
    }
  }
  return std::nullopt;
}

Result<UrdfXml> Reader::read(const std::string& xml) {
  tinyxml2::XMLDocument doc;
  doc.Parse(xml.data(), xml.size());
  if (doc.ErrorID() == tinyxml2::XML_ERROR_EMPTY_DOCUMENT)
    return fail(0, "the robot description is empty (no XML at all)");
  if (doc.Error()) {
    const char* detail = doc.ErrorStr();
    return fail(doc.ErrorLineNum(), std::string("malformed XML: ") + (detail ? detail : "") +
                                        " (the file is not well-formed XML; urdfdom refuses it "
                                        "too)");
  }
  const XMLElement* robot = doc.FirstChildElement("robot");
  if (!robot) {
    const XMLElement* first = doc.FirstChildElement();
    return fail(first ? first->GetLineNum() : 1,
                "no <robot> element at the top level (is this a URDF file?)");
  }
  const char* robot_name = robot->Attribute("name");
  if (!robot_name) return fail(robot->GetLineNum(), "the <robot> element has no name attribute");
  out_.robot_name = robot_name;
  int order = 0;
  for (const XMLElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement(), ++order) {
    const bool is_link = std::strcmp(e->Name(), "link") == 0;
    const bool is_joint = std::strcmp(e->Name(), "joint") == 0;
    const std::size_t count = is_link ? out_.links.size() : out_.joints.size();
    if ((is_link || is_joint) && count >= static_cast<std::size_t>(kMaxUrdfLinks))
      return fail(e->GetLineNum(), "the robot has more than " + std::to_string(kMaxUrdfLinks) +
                                       (is_link ? " links" : " joints") +
                                       "; the loader reads at most " +
                                       std::to_string(kMaxUrdfLinks) +
                                       " (kMaxUrdfLinks: a scene that size takes about 1.4 GB "
                                       "to load; doc/urdf.md#bounds)");
    if (is_link) {
      if (auto err = readLink(e, order)) return *err;
    } else if (is_joint) {
      if (auto err = readJoint(e, order)) return *err;
    } else if (std::strcmp(e->Name(), "gazebo") == 0) {
      readGazebo(e);
      if (auto err = readSelfCollide(e)) return *err;
    }
  }
  if (xml.find(kExtensionPrefix) != std::string::npos)
    if (auto err = checkExtensionPlacement(robot)) return *err;
  if (auto err = checkTree()) return *err;
  if (auto err = checkMimics()) return *err;
  if (auto err = applyGazeboFriction()) return *err;
  for (const auto& [link, line] : self_collide_lines_)
    if (!out_.links.count(link))
      return fail(line, "<gazebo reference=" + inQuotes(link) + "> gives <self_collide>, but " +
                            inQuotes(link) + " is not a link of this URDF");
  return std::move(out_);
}

// Gazebo's <self_collide> (true/false, 1/0), of the model (<gazebo> without reference) or of one
// link; the last one written wins, as in Gazebo. Links are checked once all are known.
std::optional<Error> Reader::readSelfCollide(const XMLElement* e) {
  const XMLElement* c = e->FirstChildElement("self_collide");
  if (!c) return std::nullopt;
  const char* raw = c->GetText();
  std::string text = raw ? raw : "";
  text.erase(0, text.find_first_not_of(" \t\n\r"));
  text.erase(text.find_last_not_of(" \t\n\r") + 1);
  bool value = false;
  if (text == "true" || text == "1")
    value = true;
  else if (text != "false" && text != "0")
    return fail(c->GetLineNum(),
                "<self_collide> must be true or false (got " + inQuotes(text) + ")");
  const char* reference = e->Attribute("reference");
  if (!reference) {
    out_.self_collide_model = value;
  } else {
    out_.self_collide_links[reference] = value;
    self_collide_lines_.emplace_back(reference, c->GetLineNum());
  }
  return std::nullopt;
}

bool parseUrdfNumber(const char* text, double* out) {
  const char* first = text;
  while (*first && std::isspace(static_cast<unsigned char>(*first))) ++first;
  const char* last = first + std::strlen(first);
  if (first != last && *first == '+' && first + 1 != last && first[1] != '-' && first[1] != '+')
    ++first;
  const auto r = std::from_chars(first, last, *out);
  return r.ec == std::errc() && r.ptr == last && first != last && std::isfinite(*out);
}

Result<UrdfXml> readUrdfXml(const std::string& xml, const std::string& source,
                            const std::string& world_frame) {
  return Reader(source, world_frame).read(xml);
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
