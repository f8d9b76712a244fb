// The URDF reader's document (urdf_reader.h): the <robot> and its top-level elements in
// document order, the bounds on their number, the extension's placement, and the number and
// origin syntax every part reads with (urdfdom's). doc/urdf.md.
#include "scene/urdf/urdf_xml.h"

#include <tinyxml2.h>

#include <cctype>
#include <charconv>
#include <cmath>
#include <cstring>
#include <optional>

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
  std::vector<const XMLElement*> gazebo;  // read once every link and joint is known
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
      gazebo.push_back(e);
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
  for (const XMLElement* e : gazebo)
    if (auto err = readGazeboSensors(e)) return *err;
  return std::move(out_);
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
                            const std::string& world_frame, const std::string& plugin_namespace) {
  return Reader(source, world_frame, plugin_namespace).read(xml);
}

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
