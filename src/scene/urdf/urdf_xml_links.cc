// The URDF reader's links (urdf_reader.h): each <link>, its <inertial> as urdfdom will read
// it, its <visual> and <collision> geometry, and the extension <cga_rigid_sim:mass_from_geometry>
// (doc/urdf.md).
#include <cstring>

#include "cga_rigid_sim/format.h"
#include "scene/urdf/urdf_reader.h"

namespace cga_rigid_sim {
namespace scene {
namespace detail {

using tinyxml2::XMLAttribute;
using tinyxml2::XMLElement;

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

}  // namespace detail
}  // namespace scene
}  // namespace cga_rigid_sim
