// The URDF reader's joints (urdf_reader.h): each <joint>, its type, <mimic>, and for a
// revolute, continuous or prismatic joint its <axis>, <limit> and <dynamics>; then the mimic
// chains checked (doc/urdf.md).
#include <algorithm>
#include <cmath>
#include <limits>

#include "cga_rigid_sim/format.h"
#include "scene/urdf/urdf_reader.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

using tinyxml2::XMLElement;

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

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
